// PLY point clouds, ascii and binary (measure::parse_ply, the bytes read_point_cloud reads).
#include "deflex/measure/samples.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  return fuzz::guarded([&] { measure::parse_ply(bytes, "fuzz.ply"); });
}
