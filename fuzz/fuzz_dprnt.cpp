// Fanuc DPRNT output of the probe program, and its join by id with a probe
// program of three points; the same input also read as a probe program.
#include "fuzz_support.hpp"
#include "probe_targets.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  fuzz::guarded([&] {
    const auto samples = measure::read_dprnt(text, "fuzz.txt");
    measure::join_probe_log(fuzz::probe_targets(), samples, true, "fuzz.txt", text);
  });
  return fuzz::guarded([&] { measure::read_probe_targets(text, "fuzz.nc"); });
}
