// The Z-map as a file of its own (.zmap, docs/zmap.md): every cell's height
// exactly as the stock holds it, a few MB where the STL of the same stock is
// hundreds, read back in a fraction of a second. The stock between operations
// (`deflex stock -o rest.zmap`, then `--stock rest.zmap`); the STL stays for
// viewers and CAM systems.
#pragma once
#include <iosfwd>
#include <string>

#include "deflex/stock/zmap.hpp"

namespace deflex::stock {

// Writes `z` (header, then its tiles through deflate); throws Error(ErrorKind::io)
// when the stream or zlib fails.
void write_zmap(std::ostream& out, const ZMap& z);

// Reads a .zmap file: the Z-map it was written from, bit for bit. Throws
// Error(ErrorKind::io) naming `path` on anything malformed (magic, version, grid,
// a non-finite height other than "no material", a short or long payload).
ZMap read_zmap(const std::string& path);

// Whether a stock spec names a .zmap file (by its extension, any case).
bool is_zmap_path(const std::string& path);

// The Z-map of `path` on a grid of `cell_mm` cells: as read where the file has
// that cell size, else each new cell takes the height of the file's cell under
// its centre (as an STL read back is sampled at the cell centres).
ZMap zmap_from_file(const std::string& path, double cell_mm);

}  // namespace deflex::stock
