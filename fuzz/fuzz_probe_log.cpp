// LinuxCNC's probe log, and its join with a probe program of three points
// (the count check, the error limit and its likely-cause arithmetic).
#include "fuzz_support.hpp"
#include "probe_targets.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  return fuzz::guarded([&] {
    const auto samples = measure::read_linuxcnc_probe_log(text, "fuzz.txt");
    measure::join_probe_log(fuzz::probe_targets(), samples, false, "fuzz.txt", text);
  });
}
