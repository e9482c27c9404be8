// A CMM's CSV export of surface points (measure::read_points_csv).
#include "deflex/measure/samples.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  return fuzz::guarded([&] { measure::read_points_csv(text, "fuzz.csv"); });
}
