// The .zmap stock file (stock::read_zmap), and a file it accepts written back
// the same byte for byte. Grids over 10^6 cells are skipped: legal ones cost
// memory and time, not a bug (the cell limit itself is tested in tests/stock).
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "deflex/stock/zmap_file.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size >= 24) {
    std::int32_t nx = 0, ny = 0;
    std::memcpy(&nx, data + 16, 4);
    std::memcpy(&ny, data + 20, 4);
    if (static_cast<double>(nx) * ny > 1e6) return 0;
  }
  const std::string path = fuzz::temp_file(".zmap", data, size);
  return fuzz::guarded([&] {
    const stock::ZMap z = stock::read_zmap(path);
    std::ostringstream once, twice;
    stock::write_zmap(once, z);
    const std::string again = fuzz::temp_file(".zmap", reinterpret_cast<const std::uint8_t*>(once.str().data()),
                                              once.str().size());
    stock::write_zmap(twice, stock::read_zmap(again));
    if (once.str() != twice.str()) std::abort();
  });
}
