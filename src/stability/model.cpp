// The tool tip's FRF from the beam model, and the limit along a program
// (model.hpp).
#include "deflex/stability/model.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <mutex>
#include <numbers>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stiffness/modes.hpp"

namespace deflex::stability {

TipModel tip_model_of(std::vector<stiffness::Mode> modes) {
  TipModel r;
  r.modes = std::move(modes);
  r.frf = frf_from_modes(r.modes, r.modes, 1.5 * r.modes.back().frequency_Hz);
  return r;
}

TipModel tip_model(const stiffness::Tool& t, const stiffness::MachineStiffness& m, bool tool_only, int modes) {
  std::vector<stiffness::Mode> found = stiffness::tip_modes(t, m, tool_only, modes);
  if (found.empty()) throw Error(ErrorKind::config, "tool " + t.id + ": the beam model has no mode that moves the tip");
  TipModel r = tip_model_of(std::move(found));
  r.frf.source = "the beam model of " + t.id + (tool_only ? " clamped at the holder face" : " on the machine");
  return r;
}

std::pair<double, double> rpm_range(double max_rpm) { return {max_rpm / 50, max_rpm}; }

Eigen::Matrix2d directional_matrix_mm(const force::CutterSlices& cs, const force::Engagement& e,
                                      const force::Coefficients& k) {
  Eigen::Matrix2d B = Eigen::Matrix2d::Zero();
  if (!(k.Ktc_N_per_mm2 > 0)) return B;
  for (std::size_t i = 0; i < e.slices.size() && i < cs.slices.size(); ++i) {
    const force::Slice& sl = cs.slices[i];
    const double Kr = (k.Krc_N_per_mm2 * sl.sin_kappa + k.Kac_N_per_mm2 * sl.cos_kappa) / k.Ktc_N_per_mm2;
    for (const force::AngleInterval& iv : e.slices[i]) {
      const force::AngleInterval c = force::cutting_side(iv);
      if (c.end > c.start)
        B += cs.dz_mm * directional_coefficients({cs.cutter.flutes, k.Ktc_N_per_mm2, Kr, c.start, c.end});
    }
  }
  return B;
}

LimitCache::LimitCache(const TipModel& tip, const force::Coefficients& k, int flutes, double max_rpm)
    : frf_(tip.frf), Kt_N_per_mm2_(k.Ktc_N_per_mm2), flutes_(flutes) {
  std::tie(rpm_min_, rpm_max_) = rpm_range(max_rpm);
}

LimitCache::LimitCache(Frf measured, const force::Coefficients& k, int flutes, double max_rpm)
    : frf_(std::move(measured)), Kt_N_per_mm2_(k.Ktc_N_per_mm2), flutes_(flutes), symmetric_(false) {
  std::tie(rpm_min_, rpm_max_) = rpm_range(max_rpm);
}

template <class Key, class Alpha>
double LimitCache::cached_limit(std::map<Key, std::unique_ptr<ChatterSweep>>& sweeps,
                                std::map<std::pair<Key, double>, double>& limits, const Key& key, double rpm,
                                const Alpha& alpha) const {
  // Below the range every lobe crowds in: the absolute minimum, on the safe side.
  const bool inside = rpm >= rpm_min_ && rpm <= rpm_max_;
  const std::pair<Key, double> at{key, inside ? rpm : -1.0};
  const ChatterSweep* sweep = nullptr;
  {
    std::shared_lock lock(mutex_);
    if (auto it = limits.find(at); it != limits.end()) return it->second;
    if (auto it = sweeps.find(key); it != sweeps.end()) sweep = it->second.get();
  }
  // Made outside the lock: two threads may make the same one, the first kept.
  if (!sweep) {
    auto made = std::make_unique<ChatterSweep>(chatter_sweep(frf_, alpha(), flutes_, Kt_N_per_mm2_));
    std::unique_lock lock(mutex_);
    sweep = sweeps.try_emplace(key, std::move(made)).first->second.get();
  }
  const double a = inside ? ap_limit_at(*sweep, rpm) : sweep->ap_min_mm;
  std::unique_lock lock(mutex_);
  return limits.try_emplace(at, a).first->second;
}

double LimitCache::ap_limit_mm(const Eigen::Matrix2d& B_mm, double ap_mm, double rpm) const {
  if (!symmetric_) {
    const double s = B_mm.norm();
    if (!(s > 1e-12)) return std::numeric_limits<double>::infinity();
    std::array<int, 4> key;
    for (int i = 0; i < 4; ++i) key[i] = static_cast<int>(std::lround(64 * B_mm(i / 2, i % 2) / s));
    const auto alpha = [&key] {
      Eigen::Matrix2cd a;
      for (int i = 0; i < 4; ++i) a(i / 2, i % 2) = key[i] / 64.0;
      return a;
    };
    // The key's matrix is B / s to within its rounding: its limit over s is B's.
    return ap_mm * cached_limit(matrix_sweeps_, matrix_limits_, key, rpm, alpha) / s;
  }
  // The eigenvalues of the 2 x 2 in closed form (this runs at every point).
  const double tr = B_mm.trace(), det = B_mm.determinant();
  const std::complex<double> disc = std::sqrt(std::complex<double>(tr * tr - 4 * det));
  const std::complex<double> mu[2] = {0.5 * (tr + disc), 0.5 * (tr - disc)};
  double scale = std::numeric_limits<double>::infinity();
  for (int b = 0; b < 2; ++b) {
    const double r = std::abs(mu[b]);
    if (!(r > 1e-12)) continue;
    int degree = static_cast<int>(std::lround(std::arg(mu[b]) * 180 / std::numbers::pi));
    if (degree == -180) degree = 180;
    const auto alpha = [degree] {
      return Eigen::Matrix2cd(std::polar(1.0, degree * std::numbers::pi / 180) * Eigen::Matrix2cd::Identity());
    };
    scale = std::min(scale, cached_limit(sweeps_, limits_, degree, rpm, alpha) / r);
  }
  return ap_mm * scale;
}

}  // namespace deflex::stability
