// A measured FRF as CSV (stability::parse_frf_csv). An FRF it accepts must
// write back (frf_csv) and read again to the same numbers, and give lobes
// without any error but deflex's own.
#include <cstdlib>

#include "deflex/stability/frf.hpp"
#include "deflex/stability/lobes.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  return fuzz::guarded([&] {
    const stability::Frf frf = stability::parse_frf_csv(text, "fuzz.csv");
    const stability::Frf again = stability::parse_frf_csv(stability::frf_csv(frf), "again.csv");
    if (again.frequency_Hz != frf.frequency_Hz || again.h_mm_per_N != frf.h_mm_per_N) std::abort();
    // Half-immersion down-milling, 4 teeth, an aluminium's coefficients.
    if (frf.frequency_Hz.size() <= 2000)
      stability::zero_order_lobes(frf, {4, 800, 0.3, 1.5707963267948966, 3.141592653589793}, 1000, 20000, 8);
  });
}
