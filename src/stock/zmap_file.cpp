// The .zmap file (include/deflex/stock/zmap_file.hpp; the format in docs/zmap.md).
//
// Heights are kept bit for bit. What makes them small is the shape of a
// machined surface: neighbouring cells differ little, so the difference of
// their IEEE-754 bit patterns (taken as integers, modulo 2^32) has zero high
// bytes; grouping the bytes of a tile by significance ("byte shuffle", as the
// HDF5 shuffle filter and Blosc do) turns those into long runs that deflate
// (RFC 1951, in zlib's RFC 1950 wrapper) stores in a few bits. Untouched tiles
// are one height, as the Z-map itself holds them.
#include "deflex/stock/zmap_file.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <vector>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::stock {
namespace {

constexpr int T = ZMap::tile_cells;
constexpr std::size_t tile_cells_count = static_cast<std::size_t>(T) * T;
constexpr char magic[8] = {'D', 'E', 'F', 'L', 'E', 'X', 'Z', 'M'};
constexpr std::uint32_t version = 1;
constexpr std::size_t header_bytes = 56;
enum Kind : std::uint8_t { uniform_tile = 0, cells_tile = 1 };

std::uint32_t bits_of(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
float float_of(std::uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

// The cell a cell is predicted from: its left neighbour, the first of a row
// the first of the row below; the first cell of the tile from nothing (0).
std::size_t predictor(std::size_t k) { return k % T ? k - 1 : k - T; }

// Deflate into a stream, in chunks.
class Deflater {
 public:
  explicit Deflater(std::ostream& out) : out_(out) {
    if (deflateInit(&z_, Z_DEFAULT_COMPRESSION) != Z_OK) throw Error(ErrorKind::io, "zlib: deflateInit failed");
  }
  ~Deflater() { deflateEnd(&z_); }
  void put(const void* data, std::size_t n) { run(data, n, Z_NO_FLUSH); }
  void finish() { run(nullptr, 0, Z_FINISH); }

 private:
  void run(const void* data, std::size_t n, int flush) {
    z_.next_in = static_cast<Bytef*>(const_cast<void*>(data));
    z_.avail_in = static_cast<uInt>(n);
    int rc = Z_OK;
    do {
      z_.next_out = buf_.data();
      z_.avail_out = static_cast<uInt>(buf_.size());
      rc = deflate(&z_, flush);
      if (rc == Z_STREAM_ERROR) throw Error(ErrorKind::io, "zlib: deflate failed");
      out_.write(reinterpret_cast<const char*>(buf_.data()), static_cast<std::streamsize>(buf_.size() - z_.avail_out));
    } while (z_.avail_out == 0 || (flush == Z_FINISH && rc != Z_STREAM_END));
  }
  std::ostream& out_;
  z_stream z_{};
  std::array<Bytef, 1 << 16> buf_{};
};

[[noreturn]] void bad(const std::string& path, const std::string& why) {
  throw Error(ErrorKind::io, path + ": cannot read as a Z-map (.zmap): " + why);
}

// Inflate from the bytes after the header, exactly as many as asked for.
class Inflater {
 public:
  Inflater(const std::string& path, const std::string& bytes, std::size_t from) : path_(path) {
    if (bytes.size() - from > UINT32_MAX) bad(path, "more than 4 GiB of tile data");
    if (inflateInit(&z_) != Z_OK) throw Error(ErrorKind::io, "zlib: inflateInit failed");
    z_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data() + from));
    z_.avail_in = static_cast<uInt>(bytes.size() - from);
  }
  ~Inflater() { inflateEnd(&z_); }
  void get(void* dst, std::size_t n) {
    z_.next_out = static_cast<Bytef*>(dst);
    z_.avail_out = static_cast<uInt>(n);
    while (z_.avail_out > 0) {
      const int rc = inflate(&z_, Z_NO_FLUSH);
      if (rc == Z_STREAM_END && z_.avail_out > 0) bad(path_, "the tiles end early");
      if (rc != Z_OK && rc != Z_STREAM_END) bad(path_, std::string("corrupt tile data (zlib: ") + (z_.msg ? z_.msg : "error") + ")");
    }
  }
  // After the last tile: the stream ends there, and so does the file.
  void expect_end() {
    Bytef extra;
    z_.next_out = &extra;
    z_.avail_out = 1;
    const int rc = inflate(&z_, Z_FINISH);
    if (rc != Z_STREAM_END || z_.avail_out == 0) bad(path_, "more tile data than the grid holds");
    if (z_.avail_in != 0) bad(path_, "bytes after the tile data");
  }

 private:
  std::string path_;
  z_stream z_{};
};

template <class V>
void put_le(std::string& h, V v) {
  char b[sizeof v];
  std::memcpy(b, &v, sizeof v);  // little-endian, as every x86-64 and arm64 host deflex runs on
  h.append(b, sizeof v);
}
template <class V>
V get_le(const std::string& bytes, std::size_t at) {
  V v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  return v;
}

// A tile's cells (outside the grid: their predictor's value, so they cost nothing).
void gather(const ZMap& z, std::size_t tx, std::size_t ty, std::vector<std::uint32_t>& c) {
  const GridSpec& g = z.grid();
  for (std::size_t k = 0; k < tile_cells_count; ++k) {
    const int i = static_cast<int>(tx) * T + static_cast<int>(k % T), j = static_cast<int>(ty) * T + static_cast<int>(k / T);
    c[k] = i < g.nx && j < g.ny ? bits_of(z.at(i, j)) : k ? c[predictor(k)] : 0;
  }
}

void write_tile(Deflater& d, const std::vector<std::uint32_t>& c, std::vector<std::uint8_t>& planes) {
  for (std::size_t k = tile_cells_count; k-- > 1;) {
    const std::uint32_t delta = c[k] - c[predictor(k)];
    for (int b = 0; b < 4; ++b) planes[b * tile_cells_count + k] = static_cast<std::uint8_t>(delta >> (8 * b));
  }
  for (int b = 0; b < 4; ++b) planes[b * tile_cells_count] = static_cast<std::uint8_t>(c[0] >> (8 * b));
  d.put(planes.data(), planes.size());
}

bool height_ok(float h) { return std::isfinite(h) || h == no_material; }

// Undoes write_tile into `out`.
void read_tile(Inflater& in, const std::string& path, std::vector<std::uint8_t>& planes, std::vector<float>& out) {
  in.get(planes.data(), planes.size());
  for (std::size_t k = 0; k < tile_cells_count; ++k) {
    std::uint32_t delta = 0;
    for (int b = 0; b < 4; ++b) delta |= static_cast<std::uint32_t>(planes[b * tile_cells_count + k]) << (8 * b);
    out[k] = float_of(k ? bits_of(out[predictor(k)]) + delta : delta);
    if (!height_ok(out[k])) bad(path, "a height that is neither a number nor 'no material'");
  }
}

GridSpec read_header(const std::string& path, const std::string& bytes, double& base_z_mm) {
  if (bytes.size() < header_bytes || std::memcmp(bytes.data(), magic, 8) != 0) bad(path, "no DEFLEXZM header");
  if (get_le<std::uint32_t>(bytes, 8) != version)
    bad(path, "format version " + std::to_string(get_le<std::uint32_t>(bytes, 8)) + ", this deflex reads 1");
  if (get_le<std::uint32_t>(bytes, 12) != T) bad(path, "tiles of other than 64 x 64 cells");
  GridSpec g;
  g.nx = get_le<std::int32_t>(bytes, 16);
  g.ny = get_le<std::int32_t>(bytes, 20);
  g.x0_mm = get_le<double>(bytes, 24);
  g.y0_mm = get_le<double>(bytes, 32);
  g.cell_mm = get_le<double>(bytes, 40);
  base_z_mm = get_le<double>(bytes, 48);
  if (g.nx < 1 || g.ny < 1 || !(static_cast<double>(g.nx) * g.ny <= max_cells)) bad(path, "a grid of no or too many cells");
  if (!(g.cell_mm > 0) || !std::isfinite(g.cell_mm) || !std::isfinite(g.x0_mm) || !std::isfinite(g.y0_mm) ||
      !std::isfinite(base_z_mm))
    bad(path, "a non-finite origin, base or cell size");
  return g;
}

}  // namespace

void write_zmap(std::ostream& out, const ZMap& z) {
  const GridSpec& g = z.grid();
  std::string h(magic, 8);
  put_le(h, version);
  put_le(h, static_cast<std::uint32_t>(T));
  put_le(h, static_cast<std::int32_t>(g.nx));
  put_le(h, static_cast<std::int32_t>(g.ny));
  put_le(h, g.x0_mm);
  put_le(h, g.y0_mm);
  put_le(h, g.cell_mm);
  put_le(h, z.base_z_mm());
  out.write(h.data(), static_cast<std::streamsize>(h.size()));
  Deflater d(out);
  std::vector<std::uint32_t> c(tile_cells_count);
  std::vector<std::uint8_t> planes(4 * tile_cells_count);
  for (std::size_t ty = 0; ty < z.tiles_y(); ++ty)
    for (std::size_t tx = 0; tx < z.tiles_x(); ++tx) {
      gather(z, tx, ty, c);
      const bool uniform = std::all_of(c.begin(), c.end(), [&](std::uint32_t v) { return v == c[0]; });
      const std::uint8_t kind = uniform ? uniform_tile : cells_tile;
      d.put(&kind, 1);
      if (uniform) d.put(&c[0], 4);
      else write_tile(d, c, planes);
    }
  d.finish();
  if (!out) throw Error(ErrorKind::io, "writing the Z-map failed");
}

ZMap read_zmap(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error(ErrorKind::io, path + ": cannot open");
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  double base_z_mm = 0;
  const GridSpec g = read_header(path, bytes, base_z_mm);
  ZMap z(g, no_material, base_z_mm);
  Inflater in(path, bytes, header_bytes);
  std::vector<std::uint8_t> planes(4 * tile_cells_count);
  std::vector<float> cells(tile_cells_count);
  for (std::size_t ty = 0; ty < z.tiles_y(); ++ty)
    for (std::size_t tx = 0; tx < z.tiles_x(); ++tx) {
      std::uint8_t kind = 0;
      in.get(&kind, 1);
      if (kind == uniform_tile) {
        std::uint32_t u = 0;
        in.get(&u, 4);
        if (!height_ok(float_of(u))) bad(path, "a height that is neither a number nor 'no material'");
        std::fill(cells.begin(), cells.end(), float_of(u));
      } else if (kind == cells_tile) {
        read_tile(in, path, planes, cells);
      } else {
        bad(path, "tile kind " + std::to_string(kind) + " (0 or 1 expected)");
      }
      z.assign_tile(tx, ty, cells.data());
    }
  in.expect_end();
  return z;
}

bool is_zmap_path(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return e == ".zmap";
}

ZMap zmap_from_file(const std::string& path, double cell_mm) {
  ZMap src = read_zmap(path);
  const GridSpec& s = src.grid();
  if (std::fabs(s.cell_mm - cell_mm) <= 1e-9 * cell_mm) return src;
  ZMap z(grid_covering(s.x0_mm, s.y0_mm, s.x0_mm + s.nx * s.cell_mm, s.y0_mm + s.ny * s.cell_mm, cell_mm), no_material,
         src.base_z_mm());
  std::vector<float> cells(tile_cells_count);
  for (std::size_t ty = 0; ty < z.tiles_y(); ++ty)
    for (std::size_t tx = 0; tx < z.tiles_x(); ++tx) {
      // Between the file's cell centres (as an STL through them would give):
      // the cell under a new centre would shift the stock by half a file cell
      // where a coarser cell's centre falls on a boundary of the file's cells.
      for (std::size_t k = 0; k < tile_cells_count; ++k)
        cells[k] = static_cast<float>(src.height_smooth(z.cx(static_cast<int>(tx) * T + static_cast<int>(k % T)),
                                                        z.cy(static_cast<int>(ty) * T + static_cast<int>(k / T))));
      z.assign_tile(tx, ty, cells.data());
    }
  return z;
}

}  // namespace deflex::stock
