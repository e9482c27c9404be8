#include "band.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace deflex::engage {

namespace {
constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2 * pi;
}  // namespace

double radius_integral(const stock::ToolProfile& t, double z) {
  if (z <= 0) return 0;
  const double R = t.radius_mm, rc = stock::corner_of(t);
  auto G = [rc](double u) { return 0.5 * (u * std::sqrt(std::max(0.0, rc * rc - u * u)) + rc * rc * std::asin(std::clamp(u / rc, -1.0, 1.0))); };
  if (rc <= 0) return R * z;
  const double zc = std::min(z, rc);
  double f = (R - rc) * zc + G(zc - rc) - G(-rc);
  if (z > rc) f += R * (z - rc);
  return f;
}

void accumulate(const force::Slice& s, double a, double b, double h, double rdz, double dz, Accum& acc) {
  const double r = s.r_mm, w = s.width_mm * h / dz;
  acc.cwe += r * (b - a) * w;
  // Bagci Eq. 1: removal rate = integral over the engaged envelope of v . N_s,
  // with the outward normal N_s = (sin k sin phi, sin k cos phi, -cos k) in the
  // feed frame and dA = r dphi db (db sin k = dz); horizontal and vertical parts
  // of v apart. The horizontal part uses the exact int r dz of the band.
  acc.mrr_v += -s.cos_kappa * (b - a) * r * w;
  // Horizontal part split at multiples of pi/2: up-milling where cos(phi) > 0.
  const double lo = std::floor(a / (pi / 2)) * (pi / 2);
  for (double p = lo; p < b; p += pi / 2) {
    const double u = std::max(p, a), v = std::min(p + pi / 2, b);
    if (v <= u) continue;
    const double part = (std::cos(u) - std::cos(v)) * rdz;
    acc.mrr_h += part;
    if (part <= 0) continue;
    (std::cos(0.5 * (u + v)) > 0 ? acc.up : acc.down) += part;
  }
  // Extent along Y' of r cos(phi) over [a, b].
  auto contains = [&](double phi0) {  // some phi0 + 2 pi k in [a, b]
    const double k = std::ceil((a - phi0) / two_pi);
    return phi0 + k * two_pi <= b;
  };
  const double ca = std::cos(a), cb = std::cos(b);
  acc.y_hi = std::max(acc.y_hi, contains(0) ? r : r * std::max(ca, cb));
  acc.y_lo = std::min(acc.y_lo, contains(pi) ? -r : r * std::min(ca, cb));
}

}  // namespace deflex::engage
