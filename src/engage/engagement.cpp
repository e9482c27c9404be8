#include "deflex/engage/engagement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::engage {

namespace {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2 * pi;

// The Z-map and the pending sweeps whose footprint reaches the tool's, newest first.
struct LocalStock {
  const stock::ZMap* zmap;
  double base;
  std::vector<const stock::LineSweep*>* near;
};

// The point (x, y, z) is in material: inside the Z-map column and outside every
// pending swept volume.
inline bool in_material(const LocalStock& s, double x, double y, double z) {
  if (!(z < s.zmap->height_smooth(x, y)) || z < s.base) return false;
  for (const stock::LineSweep* p : *s.near)
    if (p->lower_height(x, y) <= z) return false;
  return true;
}

// What the engaged intervals contribute to the per-point quantities.
struct Accum {
  double cwe = 0, mrr_h = 0, mrr_v = 0, up = 0, down = 0;
  double y_hi = -std::numeric_limits<double>::infinity();
  double y_lo = std::numeric_limits<double>::infinity();
};

// Integral of the profile radius from the tip to height z, mm^2 (exact: the
// corner arc integrates to circular-segment areas).
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

// Interval [a, b] of slice s, whose band of height h carries int r dz = rdz.
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

}  // namespace

stock::ToolProfile tool_profile(const force::Cutter& c) {
  stock::ToolProfile t;
  t.radius_mm = c.diameter_mm / 2;
  switch (c.type) {
    case force::CutterType::flat: t.kind = stock::ToolKind::flat; break;
    case force::CutterType::ball:
      t.kind = stock::ToolKind::ball;
      t.corner_radius_mm = t.radius_mm;
      break;
    case force::CutterType::bull:
      t.kind = stock::ToolKind::bull;
      t.corner_radius_mm = c.corner_radius_mm;
      break;
  }
  return t;
}

Engager::Engager(const force::CutterSlices& cs, const Options& o) : cs_(cs), o_(o), tool_(tool_profile(cs.cutter)) {
  if (o.angle_samples < 8 || o.angle_samples > 100000)
    throw Error(Exit::config, "engagement: angle_samples must be between 8 and 100000");
  if (o.refine_steps < 0 || o.refine_steps > 40) throw Error(Exit::config, "engagement: refine_steps must be in [0, 40]");
  if (o.bottom_rings < 1) throw Error(Exit::config, "engagement: bottom_rings must be >= 1");
  const int N = o.angle_samples;
  sin_.resize(N);
  cos_.resize(N);
  for (int j = 0; j < N; ++j) {
    const double phi = (j + 0.5) * two_pi / N;
    sin_[j] = std::sin(phi);
    cos_[j] = std::cos(phi);
  }
}

Metrics Engager::evaluate(const StockView& stock, const CLPoint& p, const Process& proc,
                          force::Engagement& out) const {
  const std::size_t n_slices = cs_.slices.size();
  out.clear(n_slices);
  Metrics m;
  const double horiz = std::hypot(p.dir[0], p.dir[1]);
  m.plunge = horiz < 1e-6;
  m.ramp_angle = std::atan2(p.dir[2], horiz);
  const double cos_a = horiz, sin_a = p.dir[2];
  const double fx = p.feed_x, fy = p.feed_y;
  const double R = tool_.radius_mm;
  const double tx = p.tip_mm[0], ty = p.tip_mm[1], tz = p.tip_mm[2];
  // Bilinear lookups reach one cell beyond the footprint.
  const double Rc = R + stock.zmap->grid().cell_mm;
  const double zmax = stock.zmap->max_height_in(tx - Rc, ty - Rc, tx + Rc, ty + Rc);
  const double base = stock.zmap->base_z_mm();
  const int N = o_.angle_samples;
  const double dphi = two_pi / N;
  thread_local std::vector<const stock::LineSweep*> near;
  near.clear();
  auto overlaps = [&](const stock::LineSweep& l) {
    return l.x_min() <= tx + R && l.x_max() >= tx - R && l.y_min() <= ty + R && l.y_max() >= ty - R;
  };
  if (stock.current && overlaps(*stock.current)) near.push_back(stock.current);
  for (auto it = stock.pending.rbegin(); it != stock.pending.rend(); ++it)
    if (overlaps(*it)) near.push_back(&*it);
  const LocalStock local{stock.zmap, base, &near};

  constexpr std::size_t npos = static_cast<std::size_t>(-1);
  std::size_t top_slice = npos;
  Accum acc;
  thread_local std::vector<char> in;
  thread_local std::vector<force::AngleInterval> ivs;
  in.resize(static_cast<std::size_t>(N));

  for (std::size_t i = 0; i < n_slices; ++i) {
    const force::Slice& s = cs_.slices[i];
    const double zq = tz + s.z_mm;
    if (zq >= zmax) break;  // slices rise with i
    if (zq < base) continue;
    // Tested a hair inside the envelope: a flank sliding along its own earlier
    // positions (the side of a plunging end mill) rubs and must not count as
    // cutting; 1e-8 mm is far above rounding and far below any tolerance.
    const double r = s.r_mm - 1e-8;
    auto test = [&](double sp, double cp) {
      return in_material(local, tx + r * (sp * fx - cp * fy), ty + r * (sp * fy + cp * fx), zq);
    };
    int count = 0;
    for (int j = 0; j < N; ++j) count += (in[j] = test(sin_[j], cos_[j]));
    if (count == 0) continue;
    top_slice = i;
    if (count == N) {
      out.add(i, 0, two_pi);
      continue;
    }
    // Boundary between sample angles phi_out and phi_in (unwrapped, adjacent).
    auto refine = [&](double phi_out, double phi_in) {
      for (int k = 0; k < o_.refine_steps; ++k) {
        const double mid = 0.5 * (phi_out + phi_in);
        (test(std::sin(mid), std::cos(mid)) ? phi_in : phi_out) = mid;
      }
      return 0.5 * (phi_out + phi_in);
    };
    auto angle = [&](int j) { return (j + 0.5) * dphi; };  // j may be outside [0, N)
    ivs.clear();
    // Scan one turn starting just after an out sample, so no run is split.
    int j0 = 0;
    while (in[j0]) ++j0;
    for (int k = 1; k <= N; ++k) {
      const int j = j0 + k;
      if (!in[j % N] || in[(j - 1) % N]) continue;
      int e = j;
      while (in[(e + 1) % N]) ++e;
      const double a = refine(angle(j - 1), angle(j));
      const double b = refine(angle(e + 1), angle(e));
      const double shift = two_pi * std::floor(a / two_pi);  // start into [0, 2 pi)
      ivs.push_back({a - shift, b - shift});
      k += e - j;
    }
    std::sort(ivs.begin(), ivs.end(), [](const auto& u, const auto& v) { return u.start < v.start; });
    for (const force::AngleInterval& iv : ivs) out.add(i, iv.start, iv.end);
  }

  // a_p: from the highest engaged slice, bisect upward (to the next slice or the
  // stock's highest point) at the middle of each of its intervals, for the
  // height where the flank leaves the material.
  double ap = 0;
  if (top_slice != npos) {
    const force::Slice& s = cs_.slices[top_slice];
    const double z_hi = std::min(s.z_mm + cs_.dz_mm, zmax - tz);
    for (const force::AngleInterval& iv : out.slices[top_slice]) {
      const double mid = 0.5 * (iv.start + iv.end), sp = std::sin(mid), cp = std::cos(mid);
      double lo = s.z_mm, hi = z_hi;
      for (int k = 0; k < o_.refine_steps + 6; ++k) {
        const double zm = 0.5 * (lo + hi);
        const double r = stock::profile_radius(tool_, zm) - 1e-8;
        (in_material(local, tx + r * (sp * fx - cp * fy), ty + r * (sp * fy + cp * fx), tz + zm) ? lo : hi) = zm;
      }
      ap = std::max(ap, 0.5 * (lo + hi));
    }
  }

  // Slice i stands for the band [i dz, (i+1) dz]; the highest engaged one for
  // [i dz, a_p], so the removal rate does not depend on where a_p falls in a slice.
  const double dz = cs_.dz_mm;
  for (std::size_t i = 0; i < n_slices && top_slice != npos && i <= top_slice; ++i) {
    if (out.slices[i].empty()) continue;
    const double z0 = static_cast<double>(i) * dz, z1 = i == top_slice ? std::max(ap, z0) : z0 + dz;
    const double rdz = radius_integral(tool_, z1) - radius_integral(tool_, z0);
    for (const force::AngleInterval& iv : out.slices[i]) accumulate(cs_.slices[i], iv.start, iv.end, z1 - z0, rdz, dz, acc);
  }

  // Flat bottom: cuts only when descending (its normal is -Z).
  const double rf = R - stock::corner_of(tool_);
  if (rf > 0 && sin_a < -1e-9 && tz < zmax && tz >= base) {
    const int K = o_.bottom_rings;
    const double dr = rf / K;
    for (int k = 0; k < K; ++k) {
      const double rho = (k + 0.5) * dr;
      for (int j = 0; j < N; ++j) {
        const double x = tx + rho * (sin_[j] * fx - cos_[j] * fy), y = ty + rho * (sin_[j] * fy + cos_[j] * fx);
        if (!in_material(local, x, y, tz)) continue;
        m.bottom_area_mm2 += rho * dr * dphi;  // midpoint rule, exact for the disc
      }
    }
  }

  m.air_cut = out.empty() && m.bottom_area_mm2 == 0;
  if (m.air_cut) return m;
  const double vf_mm_per_s = proc.fz_mm * cs_.cutter.flutes * proc.spindle_rpm / 60;
  m.ap_mm = ap;
  m.d_eff_mm = 2 * stock::profile_radius(tool_, m.ap_mm);  // Bagci Eq. 2 for a ball
  m.cwe_area_mm2 = acc.cwe + m.bottom_area_mm2;
  m.mrr_mm3_per_s = vf_mm_per_s * (cos_a * acc.mrr_h + sin_a * acc.mrr_v - sin_a * m.bottom_area_mm2);
  if (acc.y_hi >= acc.y_lo) m.ae_mm = acc.y_hi - acc.y_lo;
  if (acc.up + acc.down > 0) m.up_share = acc.up / (acc.up + acc.down);
  return m;
}

}  // namespace deflex::engage
