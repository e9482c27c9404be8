// The tool tip's FRF from modes, and its interpolation (frf.hpp).
#include "deflex/stability/frf.hpp"

#include <algorithm>
#include <cmath>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::stability {

Frf2 Frf::at(double f_Hz) const {
  if (frequency_Hz.empty()) throw Error(ErrorKind::internal, "an FRF without samples");
  if (f_Hz <= frequency_Hz.front()) return h_mm_per_N.front();
  if (f_Hz >= frequency_Hz.back()) return h_mm_per_N.back();
  const auto hi = static_cast<std::size_t>(std::upper_bound(frequency_Hz.begin(), frequency_Hz.end(), f_Hz) -
                                           frequency_Hz.begin());
  const double t = (f_Hz - frequency_Hz[hi - 1]) / (frequency_Hz[hi] - frequency_Hz[hi - 1]);
  return (1 - t) * h_mm_per_N[hi - 1] + t * h_mm_per_N[hi];
}

std::complex<double> modal_receptance(const std::vector<stiffness::Mode>& modes, double f_Hz) {
  std::complex<double> h = 0;
  for (const stiffness::Mode& m : modes) {
    const double r = f_Hz / m.frequency_Hz;
    h += 1.0 / (m.stiffness_N_per_mm * std::complex<double>(1 - r * r, 2 * m.damping_ratio * r));
  }
  return h;
}

namespace {

// The sampling step at f (frf.hpp): a tenth of the distance to the nearest
// peak, never below a tenth of that peak's zeta f_r, never above f_max / 400.
double step_Hz(const std::vector<stiffness::Mode>& x, const std::vector<stiffness::Mode>& y, double f,
               double f_max) {
  double s = f_max / 400;
  for (const auto* modes : {&x, &y})
    for (const stiffness::Mode& m : *modes)
      s = std::min(s, 0.1 * std::max(m.damping_ratio * m.frequency_Hz, std::abs(f - m.frequency_Hz)));
  return s;
}

}  // namespace

Frf frf_from_modes(const std::vector<stiffness::Mode>& x, const std::vector<stiffness::Mode>& y, double f_max_Hz) {
  if (!(f_max_Hz > 0) || !std::isfinite(f_max_Hz))
    throw Error(ErrorKind::settings, "the FRF's highest frequency must be > 0 Hz");
  for (const auto* modes : {&x, &y})
    for (const stiffness::Mode& m : *modes)
      if (!(m.frequency_Hz > 0 && m.stiffness_N_per_mm > 0 && m.damping_ratio > 0 && m.damping_ratio < 1))
        throw Error(ErrorKind::settings, "a mode needs frequency > 0, stiffness > 0 and 0 < damping ratio < 1");
  Frf frf;
  frf.source = "modal model";
  for (double f = f_max_Hz / 1000; f < f_max_Hz; f += step_Hz(x, y, f, f_max_Hz)) frf.frequency_Hz.push_back(f);
  frf.frequency_Hz.push_back(f_max_Hz);
  for (double f : frf.frequency_Hz) {
    Frf2 h = Frf2::Zero();
    h(0, 0) = modal_receptance(x, f);
    h(1, 1) = modal_receptance(y, f);
    frf.h_mm_per_N.push_back(h);
  }
  return frf;
}

}  // namespace deflex::stability
