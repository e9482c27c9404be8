#include "deflex/force/engagement.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace deflex::force {

namespace {
constexpr double two_pi = 2 * std::numbers::pi;
}

void Engagement::clear(std::size_t slice_count) {
  if (slices.size() != slice_count) slices.resize(slice_count);
  for (auto& s : slices) s.clear();
}

void Engagement::add(std::size_t slice, double start, double end) {
  if (slice >= slices.size()) slices.resize(slice + 1);
  if (!(end > start)) return;
  double w = std::min(end - start, two_pi);
  double s = std::fmod(start, two_pi);
  if (s < 0) s += two_pi;
  slices[slice].push_back({s, s + w});
}

bool Engagement::empty() const {
  return std::all_of(slices.begin(), slices.end(), [](const auto& v) { return v.empty(); });
}

AngleInterval immersion_interval(double r_mm, double R0_mm, double ae_mm, MillingMode mode) {
  // The stock wall is at distance R0 - a_e from the axis on the cutting side; an
  // edge point of radius r is in the stock where r cos(phi) >= R0 - a_e (up) or
  // r cos(phi) <= -(R0 - a_e) (down), on the front half phi in [0, pi].
  const double c = (R0_mm - ae_mm) / r_mm;
  if (c >= 1) return {0, 0};
  const double a = c <= -1 ? std::numbers::pi : std::acos(c);
  if (mode == MillingMode::up) return {0, a};
  return {std::numbers::pi - a, std::numbers::pi};
}

void simple_engagement(const CutterSlices& cs, double ae_mm, double ap_mm, MillingMode mode,
                       Engagement& out) {
  out.clear(cs.slices.size());
  const double R0 = cs.cutter.diameter_mm / 2;
  for (std::size_t i = 0; i < cs.slices.size(); ++i) {
    const Slice& s = cs.slices[i];
    if (s.z_mm >= ap_mm) break;
    const AngleInterval iv = immersion_interval(s.r_mm, R0, ae_mm, mode);
    if (iv.end > iv.start) out.add(i, iv.start, iv.end);
  }
}

AngleInterval cutting_side(const AngleInterval& iv) {
  const double pi = std::numbers::pi, two_pi = 2 * pi;
  double s = iv.start, t = iv.end;
  if (t > two_pi) s = 0;  // it wraps: [0, t - 2 pi] is engaged too
  if (iv.start > pi) {
    if (t <= two_pi) return {0, 0};
    t -= two_pi;
  }
  t = std::min(t, pi);
  return t > s ? AngleInterval{s, t} : AngleInterval{0, 0};
}

}  // namespace deflex::force
