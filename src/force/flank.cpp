// The flank surface error profile (Morelli 2021 §2.3-2.4), see flank.hpp.
#include "deflex/force/flank.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::force {

SliceCompliance slice_compliance(const CutterSlices& cs,
                                 const std::function<Mat3(double z_mm, double zp_mm)>& c) {
  SliceCompliance out;
  out.n = cs.slices.size();
  out.c_mm_per_N.resize(out.n * out.n);
  for (std::size_t i = 0; i < out.n; ++i)
    for (std::size_t m = 0; m < out.n; ++m)
      out.c_mm_per_N[i * out.n + m] = c(cs.slices[i].z_mm, cs.slices[m].z_mm);
  return out;
}

double generating_phi(MillingMode mode) { return mode == MillingMode::down ? std::numbers::pi : 0.0; }

Vec3 wall_normal(double phi_n) { return Vec3(-std::sin(phi_n), -std::cos(phi_n), 0.0); }

void summarize_profile(const Vec3& normal, FlankProfile& out) {
  out.min_mm = out.max_mm = out.z_of_min_mm = out.z_of_max_mm = 0;
  if (!out.points.empty()) {
    const auto [lo, hi] = std::minmax_element(
        out.points.begin(), out.points.end(),
        [](const FlankPoint& a, const FlankPoint& b) { return a.error_mm < b.error_mm; });
    out.min_mm = lo->error_mm;
    out.z_of_min_mm = lo->z_mm;
    out.max_mm = hi->error_mm;
    out.z_of_max_mm = hi->z_mm;
  }
  // Chebyshev centre of [min, max]: max |e - s| = (max - min) / 2 at s = mid-range.
  out.mid_offset_mm = 0.5 * (out.max_mm + out.min_mm);
  out.mid_offset_vec_mm = out.mid_offset_mm * normal;
}

void flank_error_profile(const FlankInput& in, const SliceCompliance& c, GeneratingLoads& loads,
                         FlankProfile& out) {
  if (c.n != in.cs.slices.size())
    throw Error(ErrorKind::internal, "flank_error_profile: compliance built for another slicing");
  surface_generating_loads(in.cs, in.k, in.fz_mm, in.eng, in.phi_n, loads);
  const std::size_t n = loads.size();
  out.points.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    // Only n . delta is wanted: n^T C(z_i, z_m) F_m summed over the slices m.
    Vec3 delta = Vec3::Zero();
    for (std::size_t m = 0; m < n; ++m) delta += c.at(loads.slice[i], loads.slice[m]) * loads.at(i, m);
    out.points[i] = {loads.z_mm[i], in.normal.dot(delta)};
  }
  summarize_profile(in.normal, out);
}

FlankProfile flank_error_profile(const FlankInput& in, const SliceCompliance& c) {
  GeneratingLoads loads;
  FlankProfile out;
  flank_error_profile(in, c, loads, out);
  return out;
}

const char* to_string(FeatureKind k) {
  switch (k) {
    case FeatureKind::slope_break: return "slope break";
    case FeatureKind::curvature_break: return "curvature break";
    case FeatureKind::minimum: return "minimum";
    case FeatureKind::maximum: return "maximum";
  }
  return "?";
}

namespace {

// Least-squares quadratic through samples e[j], e[j + d], ..., e[j + w d] (d = +-1)
// evaluated at z_j: slope and second derivative per sample step, from the
// normal equations of the offsets t = 0, d, ..., w d.
struct Side {
  double slope = 0, curv = 0;
};
Side side_fit(std::span<const FlankPoint> p, std::size_t j, int dir, int w) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (int k = 0; k <= w; ++k) {
    const double t = dir * k;
    const Eigen::Vector3d row(1, t, t * t);
    A += row * row.transpose();
    b += row * p[static_cast<std::size_t>(static_cast<long>(j) + dir * k)].error_mm;
  }
  const Eigen::Vector3d c = A.ldlt().solve(b);
  return {c(1), 2 * c(2)};
}

double median_abs(std::vector<double> v) {
  if (v.empty()) return 0;
  for (double& x : v) x = std::abs(x);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Indices whose |value| exceeds `threshold` and every other within +-radius
// (the first of equals).
std::vector<std::size_t> peaks(const std::vector<double>& value, double threshold, std::size_t radius) {
  std::vector<std::size_t> out;
  for (std::size_t g = 0; g < value.size(); ++g) {
    if (!(std::abs(value[g]) > threshold)) continue;
    bool best = true;
    for (std::size_t h = g > radius ? g - radius : 0; h <= std::min(value.size() - 1, g + radius); ++h)
      if (std::abs(value[h]) > std::abs(value[g]) || (std::abs(value[h]) == std::abs(value[g]) && h < g))
        best = false;
    if (best) out.push_back(g);
  }
  return out;
}

}  // namespace

std::vector<ProfileFeature> profile_features(std::span<const FlankPoint> p, double min_strength) {
  // Each sample j is tested as a break: one quadratic fitted on each side (w + 1
  // samples ending at j). Their slope and curvature differences vanish on smooth
  // stretches (to O(dz^3)); a kink shows as a slope jump, an edge crossing at
  // zero load density as a curvature jump. The slicing quantises breaks to the
  // samples, so the sample is the estimate (to half a slice).
  constexpr int w = 5;
  std::vector<ProfileFeature> out;
  const std::size_t n = p.size();
  if (n < 2 * w + 3) return out;
  std::vector<double> dslope(n, 0.0), dcurv(n, 0.0);
  for (std::size_t j = w; j + w < n; ++j) {
    const Side l = side_fit(p, j, -1, w), r = side_fit(p, j, +1, w);
    dslope[j] = r.slope - l.slope;
    dcurv[j] = r.curv - l.curv;
  }
  // Excess over the smooth background of each measure (O(dz^3) times the third
  // derivative there, varying slowly): the mean of the values just outside the
  // +-w samples a break disturbs, so a weak break on a curved profile stands out.
  constexpr std::size_t L = w + 1;
  if (n < 2 * (w + L) + 1) return out;
  std::vector<double> xslope(n, 0.0), xcurv(n, 0.0);
  for (std::size_t j = w + L; j + w + L < n; ++j) {
    xslope[j] = dslope[j] - 0.5 * (dslope[j - L] + dslope[j + L]);
    xcurv[j] = dcurv[j] - 0.5 * (dcurv[j - L] + dcurv[j + L]);
  }
  double emax = 0;
  for (const FlankPoint& q : p) emax = std::max(emax, std::abs(q.error_mm));
  // Robust background (most samples are smooth); the floor keeps the rounding
  // noise of a constant profile out.
  const std::vector<double> sv(xslope.begin() + w + L, xslope.end() - w - L);
  const std::vector<double> cv(xcurv.begin() + w + L, xcurv.end() - w - L);
  const double s_scale = std::max(median_abs(sv), 1e-12 * emax);
  const double c_scale = std::max(median_abs(cv), 1e-12 * emax);
  // Kind by the larger response in sample units: a kink gives |dslope| = jump and
  // |dcurv| <= 0.46 of it nearby, a curvature jump |dcurv| = jump and |dslope|
  // <= 0.85 of it (least-squares fits of w = 5 to (t)+ and (t)+^2 / 2).
  auto local_max = [&](const std::vector<double>& v, std::size_t j) {
    double m = 0;
    for (std::size_t h = j - w; h <= j + w; ++h) m = std::max(m, std::abs(v[h]));
    return m;
  };
  constexpr double ratio = 0.75;
  for (std::size_t j : peaks(xslope, min_strength * s_scale, w))
    if (local_max(dcurv, j) < ratio * std::abs(dslope[j]))
      out.push_back({FeatureKind::slope_break, p[j].z_mm, std::abs(xslope[j]) / s_scale});
  for (std::size_t j : peaks(xcurv, min_strength * c_scale, w))
    if (std::abs(dcurv[j]) >= ratio * local_max(dslope, j))
      out.push_back({FeatureKind::curvature_break, p[j].z_mm, std::abs(xcurv[j]) / c_scale});
  // Extrema: strict over +-w samples, so quantisation ripples on a flat stretch do
  // not count.
  for (std::size_t j = w; j + w < n; ++j) {
    bool is_min = true, is_max = true;
    for (std::size_t h = j - w; h <= j + w; ++h) {
      if (h == j) continue;
      if (p[h].error_mm <= p[j].error_mm) is_min = false;
      if (p[h].error_mm >= p[j].error_mm) is_max = false;
    }
    if (is_min) out.push_back({FeatureKind::minimum, p[j].z_mm, 0});
    if (is_max) out.push_back({FeatureKind::maximum, p[j].z_mm, 0});
  }
  std::sort(out.begin(), out.end(),
            [](const ProfileFeature& a, const ProfileFeature& b) { return a.z_mm < b.z_mm; });
  return out;
}

}  // namespace deflex::force
