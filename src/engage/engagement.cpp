#include "deflex/engage/engagement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "band.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "probe.hpp"

namespace deflex::engage {

namespace {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2 * pi;

using detail::CulledProbe;
using detail::LocalStock;
using detail::NearSweep;
using detail::PlainProbe;

}  // namespace

stock::ToolProfile tool_profile(const force::Cutter& c) {
  return {c.type, c.diameter_mm / 2, force::corner_radius_of(c)};
}

Engager::Engager(const force::CutterSlices& cs, const Options& o) : cs_(cs), o_(o), tool_(tool_profile(cs.cutter)) {
  if (o.angle_samples < 8 || o.angle_samples > 100000)
    throw Error(ErrorKind::config, "engagement: angle_samples must be between 8 and 100000");
  if (o.refine_steps < 0 || o.refine_steps > 40) throw Error(ErrorKind::config, "engagement: refine_steps must be in [0, 40]");
  if (o.bottom_rings < 1) throw Error(ErrorKind::config, "engagement: bottom_rings must be >= 1");
  const int N = o.angle_samples;
  sin_.resize(N);
  cos_.resize(N);
  for (int j = 0; j < N; ++j) {
    const double phi = (j + 0.5) * two_pi / N;
    sin_[j] = std::sin(phi);
    cos_[j] = std::cos(phi);
  }
  // The bisection of a transition between samples k - 1 and k (unwrapped, k in
  // [1, 2N)) only ever tests the midpoints of the tree of halvings of [angle(k - 1),
  // angle(k)]: their sines and cosines, tabulated as evaluate_with computes the
  // midpoints (node 1 the root, 2n and 2n + 1 the lower and upper halves of n).
  const int S = o.refine_steps;
  if (S > 0 && S <= 8 && 2 * N <= 4096) {
    refine_nodes_ = 1 << S;
    refine_sc_.resize(static_cast<std::size_t>(2 * N) * refine_nodes_);
    const double dphi = two_pi / N;
    auto angle = [&](int j) { return (j + 0.5) * dphi; };
    for (int k = 1; k < 2 * N; ++k) {
      std::array<double, 2>* t = &refine_sc_[static_cast<std::size_t>(k) * refine_nodes_];
      std::vector<std::array<double, 2>> range(refine_nodes_);  // [lo, hi] of each node
      range[1] = {angle(k - 1), angle(k)};
      for (int n = 1; n < refine_nodes_; ++n) {
        const double mid = 0.5 * (range[n][0] + range[n][1]);
        t[n] = {std::sin(mid), std::cos(mid)};
        if (2 * n < refine_nodes_) {
          range[2 * n] = {range[n][0], mid};
          range[2 * n + 1] = {mid, range[n][1]};
        }
      }
    }
  }
  // The integral of r dz over each slice's band (the top one varies with a_p).
  const double dz = cs_.dz_mm;
  band_rdz_.resize(cs_.slices.size());
  for (std::size_t i = 0; i < cs_.slices.size(); ++i) {
    const double z0 = static_cast<double>(i) * dz, z1 = z0 + dz;
    band_rdz_[i] = radius_integral(tool_, z1) - radius_integral(tool_, z0);
  }
}

Metrics Engager::evaluate(const StockView& stock, const CLPoint& p, const Process& proc,
                          force::Engagement& out) const {
  return evaluate_with<CulledProbe>(stock, p, proc, out);
}

Metrics Engager::evaluate_reference(const StockView& stock, const CLPoint& p, const Process& proc,
                                    force::Engagement& out) const {
  return evaluate_with<PlainProbe>(stock, p, proc, out);
}

// A flank passing along a wall the tool cut itself (the levels above in an
// offset pocket or a waterline, a corner of the tool's own radius) touches it
// over an arc at every height of the wall, up to a quadrant in such a corner,
// while nothing comes off: the envelope's top then counts a wall that is not
// cut. A height cuts when the stock before this move has material depth_mm
// inside the envelope along one of its engaged directions, i.e. the radial
// depth of cut there exceeds depth_mm. One Z-map cell: the Z-map holds a wall
// to within a cell (cell-centre heights interpolated across the cell,
// ZMap::height_smooth), so a thinner band cannot be told from the tool meeting
// its own wall, and a real cut that thin is below what the Z-map resolves.
// Where no height cuts that deep, the envelope's top stands.
template <class Probe>
double Engager::cut_top(const Probe& probe, const CLPoint& p, const stock::LineSweep* current,
                        const force::Engagement& out, std::size_t top_slice, double envelope_top_mm,
                        double depth_mm) const {
  const double tx = p.tip_mm[0], ty = p.tip_mm[1], tz = p.tip_mm[2], fx = p.feed_x, fy = p.feed_y;
  auto cuts = [&](double z, double phi) {
    const double r = std::max(0.0, stock::profile_radius(tool_, z) - depth_mm), sp = std::sin(phi), cp = std::cos(phi);
    return probe.in_region_before(tx + r * (sp * fx - cp * fy), ty + r * (sp * fy + cp * fx), tz + z, current);
  };
  const double dphi = two_pi / o_.angle_samples;
  for (std::size_t i = top_slice + 1; i-- > 0;) {
    const double z = cs_.slices[i].z_mm;
    for (const force::AngleInterval& iv : out.slices[i]) {
      // The middle of the interval first (it decides a real cut at once), then
      // its samples one angle step apart.
      double phi = 0.5 * (iv.start + iv.end);
      bool hit = cuts(z, phi);
      for (double a = iv.start + 0.5 * dphi; !hit && a < iv.end; a += dphi) hit = cuts(z, phi = a);
      if (!hit) continue;
      if (i == top_slice) return envelope_top_mm;
      // Between this slice and the graze above, along the direction that cuts.
      double lo = z, hi = cs_.slices[i + 1].z_mm;
      for (int k = 0; k < o_.refine_steps + 6; ++k) {
        const double zm = 0.5 * (lo + hi);
        (cuts(zm, phi) ? lo : hi) = zm;
      }
      return 0.5 * (lo + hi);
    }
  }
  return envelope_top_mm;
}

namespace {

// What the steps of one evaluate_with call share: the tool tip (tx, ty, tz), the
// feed direction (fx, fy) and the N sample directions (ux, uy) of the feed frame
// in the world frame, dphi apart.
struct Frame {
  double tx, ty, tz, fx, fy;
  int N;
  double dphi;
  const double *ux, *uy;
};

// The bisection's sines and cosines of Engager (its constructor): none when sc
// is null.
struct RefineTables {
  const std::array<double, 2>* sc;
  int nodes, steps;
};

// The sweeps whose footprint reaches the tool's of radius R at (tx, ty): the
// current move's and the pending ones, nearest first (the current move, at the
// axis, decides for the whole wake at once, and the culling of CulledProbe stops
// at the first one out of reach).
void gather_near(const StockView& stock, double tx, double ty, double R, std::vector<NearSweep>& near) {
  near.clear();
  auto overlaps = [&](const stock::LineSweep& l) {
    return l.x_min() <= tx + R && l.x_max() >= tx - R && l.y_min() <= ty + R && l.y_max() >= ty - R;
  };
  if (stock.current && overlaps(*stock.current)) near.push_back(detail::near_sweep(*stock.current, tx, ty));
  for (auto it = stock.pending.rbegin(); it != stock.pending.rend(); ++it)
    if (overlaps(*it)) near.push_back(detail::near_sweep(*it, tx, ty));
  std::sort(near.begin(), near.end(), [](const NearSweep& u, const NearSweep& v) {
    return u.axis_mm - u.radius_mm < v.axis_mm - v.radius_mm;
  });
}

// The angle intervals in material of the slice circle of radius r the probe
// scanned last (in[0, N): its samples, some in and some out), each boundary
// bisected between its two samples, added to slice i of out in angle order.
template <class Probe>
void slice_intervals(Probe& probe, const Frame& f, double r, const RefineTables& rt, std::vector<char>& in,
                     std::size_t i, force::Engagement& out) {
  thread_local std::vector<force::AngleInterval> ivs;
  const int N = f.N;
  auto test = [&](double sp, double cp) {
    return probe.on_slice(f.tx + r * (sp * f.fx - cp * f.fy), f.ty + r * (sp * f.fy + cp * f.fx));
  };
  // Boundary between sample angles phi_out and phi_in (unwrapped, adjacent).
  auto angle = [&](int j) { return (j + 0.5) * f.dphi; };  // j may be outside [0, N)
  // b = k: the boundary lies in [angle(k - 1), angle(k)]; in_low: the in side is k - 1.
  auto refine = [&](int b, bool in_low) {
    double phi_out = angle(in_low ? b : b - 1), phi_in = angle(in_low ? b - 1 : b);
    const std::array<double, 2>* sc = Probe::tables && rt.sc ? rt.sc + static_cast<std::size_t>(b) * rt.nodes : nullptr;
    int node = 1;
    for (int k = 0; k < rt.steps; ++k) {
      const double mid = 0.5 * (phi_out + phi_in);
      const bool inside = sc ? test(sc[node][0], sc[node][1]) : test(std::sin(mid), std::cos(mid));
      (inside ? phi_in : phi_out) = mid;
      node = 2 * node + (inside == in_low);  // the upper half when the low end moved
    }
    return 0.5 * (phi_out + phi_in);
  };
  ivs.clear();
  // Scan one turn starting just after an out sample, so no run is split.
  // in[] twice over, so unwrapped indices (< 2N here) need no modulo.
  std::copy(in.begin(), in.begin() + N, in.begin() + N);
  int j0 = 0;
  while (in[j0]) ++j0;
  for (int k = 1; k <= N; ++k) {
    const int j = j0 + k;
    if (!in[j] || in[j - 1]) continue;
    int e = j;
    while (in[e + 1]) ++e;
    const double a = refine(j, false);
    const double b = refine(e + 1, true);
    const double shift = two_pi * std::floor(a / two_pi);  // start into [0, 2 pi)
    ivs.push_back({a - shift, b - shift});
    k += e - j;
  }
  std::sort(ivs.begin(), ivs.end(), [](const auto& u, const auto& v) { return u.start < v.start; });
  for (const force::AngleInterval& iv : ivs) out.add(i, iv.start, iv.end);
}

constexpr std::size_t npos = static_cast<std::size_t>(-1);

// The flank's engagement, slice by slice from the tip up to the stock's highest
// point zmax (above the stock's base), into out; returns the highest engaged
// slice (npos: none).
template <class Probe>
std::size_t engaged_slices(Probe& probe, const Frame& f, const std::vector<force::Slice>& slices, double zmax,
                           double base, const RefineTables& rt, force::Engagement& out) {
  thread_local std::vector<char> in;
  thread_local std::vector<double> px, py;
  const int N = f.N;
  in.resize(static_cast<std::size_t>(2 * N));
  for (auto* v : {&px, &py}) v->resize(static_cast<std::size_t>(N));
  std::size_t top_slice = npos;
  for (std::size_t i = 0; i < slices.size(); ++i) {
    const double zq = f.tz + slices[i].z_mm;
    if (zq >= zmax) break;  // slices rise with i
    if (zq < base) continue;
    // Tested a hair inside the envelope: a flank sliding along its own earlier
    // positions (the side of a plunging end mill) rubs and must not count as
    // cutting; 1e-8 mm is far above rounding and far below any tolerance.
    const double r = slices[i].r_mm - 1e-8;
    if (probe.slice_empty(zq, r)) continue;
    for (int j = 0; j < N; ++j) {
      px[j] = f.tx + r * f.ux[j];
      py[j] = f.ty + r * f.uy[j];
    }
    const int count = probe.scan_slice(zq, r, N, px.data(), py.data(), in.data());
    if (count == 0) continue;
    top_slice = i;
    if (count == N)
      out.add(i, 0, two_pi);
    else
      slice_intervals(probe, f, r, rt, in, i, out);
  }
  return top_slice;
}

// a_p: from slice s, the highest engaged one (its intervals ivs), bisect upward
// to z_hi (the next slice or the stock's highest point) at the middle of each
// interval, for the height where the flank leaves the material.
template <class Probe>
double axial_depth(Probe& probe, const Frame& f, const stock::ToolProfile& tool, const force::Slice& s, double z_hi,
                   const std::vector<force::AngleInterval>& ivs, int steps) {
  double ap = 0;
  probe.begin_region(f.tz + z_hi, stock::profile_radius(tool, z_hi));
  for (const force::AngleInterval& iv : ivs) {
    const double mid = 0.5 * (iv.start + iv.end), sp = std::sin(mid), cp = std::cos(mid);
    double lo = s.z_mm, hi = z_hi;
    for (int k = 0; k < steps; ++k) {
      const double zm = 0.5 * (lo + hi);
      const double r = stock::profile_radius(tool, zm) - 1e-8;
      (probe.in_region(f.tx + r * (sp * f.fx - cp * f.fy), f.ty + r * (sp * f.fy + cp * f.fx), f.tz + zm) ? lo : hi) =
          zm;
    }
    ap = std::max(ap, 0.5 * (lo + hi));
  }
  return ap;
}

// The area of the flat bottom (radius rf about the axis) in material, by K rings
// of the sample directions: it cuts only when descending (its normal is -Z).
template <class Probe>
double bottom_area_mm2(Probe& probe, const Frame& f, double rf, int K) {
  double area = 0;
  const double dr = rf / K;
  probe.begin_region(f.tz, rf);
  for (int k = 0; k < K; ++k) {
    const double rho = (k + 0.5) * dr;
    for (int j = 0; j < f.N; ++j) {
      const double x = f.tx + rho * f.ux[j], y = f.ty + rho * f.uy[j];
      if (!probe.in_region(x, y, f.tz)) continue;
      area += rho * dr * f.dphi;  // midpoint rule, exact for the disc
    }
  }
  return area;
}

// The removal sums of the engaged slices. Slice i stands for the band [i dz, (i+1)
// dz] (band_rdz: the integral of r dz over it); the highest engaged one for [i dz,
// a_p], so the removal rate does not depend on where a_p falls in a slice.
Accum band_sums(const force::CutterSlices& cs, const stock::ToolProfile& tool, const std::vector<double>& band_rdz,
                const force::Engagement& out, std::size_t top_slice, double envelope_top_mm) {
  Accum acc;
  const double dz = cs.dz_mm;
  for (std::size_t i = 0; i < cs.slices.size() && i <= top_slice; ++i) {
    if (out.slices[i].empty()) continue;
    const double z0 = static_cast<double>(i) * dz, z1 = i == top_slice ? std::max(envelope_top_mm, z0) : z0 + dz;
    const double rdz = i == top_slice ? radius_integral(tool, z1) - radius_integral(tool, z0) : band_rdz[i];
    for (const force::AngleInterval& iv : out.slices[i])
      accumulate(cs.slices[i], iv.start, iv.end, z1 - z0, rdz, dz, acc);
  }
  return acc;
}

}  // namespace

template <class Probe>
Metrics Engager::evaluate_with(const StockView& stock, const CLPoint& p, const Process& proc,
                               force::Engagement& out) const {
  out.clear(cs_.slices.size());
  Metrics m;
  const double horiz = std::hypot(p.dir[0], p.dir[1]);
  m.plunge = horiz < 1e-6;
  m.ramp_angle = std::atan2(p.dir[2], horiz);
  const double cos_a = horiz, sin_a = p.dir[2];
  const double R = tool_.radius_mm, tx = p.tip_mm[0], ty = p.tip_mm[1], tz = p.tip_mm[2];
  // Bilinear lookups reach one cell beyond the footprint.
  const double Rc = R + stock.zmap->grid().cell_mm;
  const double zmax = stock.zmap->max_height_in(tx - Rc, ty - Rc, tx + Rc, ty + Rc);
  const double base = stock.zmap->base_z_mm();
  const int N = o_.angle_samples;
  thread_local std::vector<NearSweep> near;
  gather_near(stock, tx, ty, R, near);
  const LocalStock local{stock.zmap, base, tx, ty, p.feed_x, p.feed_y, &near};
  Probe probe(local);

  thread_local std::vector<double> ux, uy;
  for (auto* v : {&ux, &uy}) v->resize(static_cast<std::size_t>(N));
  for (int j = 0; j < N; ++j) {  // the sample directions in the world frame
    ux[j] = sin_[j] * p.feed_x - cos_[j] * p.feed_y;
    uy[j] = sin_[j] * p.feed_y + cos_[j] * p.feed_x;
  }
  probe.begin_circles(N, ux.data(), uy.data());
  const Frame f{tx, ty, tz, p.feed_x, p.feed_y, N, two_pi / N, ux.data(), uy.data()};
  const RefineTables rt{refine_nodes_ ? refine_sc_.data() : nullptr, refine_nodes_, o_.refine_steps};

  const std::size_t top_slice = engaged_slices(probe, f, cs_.slices, zmax, base, rt, out);

  double ap = 0, envelope_top = 0;
  Accum acc;
  if (top_slice != npos) {
    const force::Slice& s = cs_.slices[top_slice];
    const double z_hi = std::min(s.z_mm + cs_.dz_mm, zmax - tz);
    envelope_top = axial_depth(probe, f, tool_, s, z_hi, out.slices[top_slice], o_.refine_steps + 6);
    ap = cut_top(probe, p, stock.current, out, top_slice, envelope_top, stock.zmap->grid().cell_mm);
    acc = band_sums(cs_, tool_, band_rdz_, out, top_slice, envelope_top);
  }

  const double rf = R - stock::corner_of(tool_);
  if (rf > 0 && sin_a < -1e-9 && tz < zmax && tz >= base)
    m.bottom_area_mm2 = bottom_area_mm2(probe, f, rf, o_.bottom_rings);

  m.air_cut = out.empty() && m.bottom_area_mm2 == 0;
  if (m.air_cut) return m;
  const double vf_mm_per_s = proc.fz_mm * cs_.cutter.flutes * proc.spindle_rpm / 60;
  m.ap_mm = ap;
  m.d_eff_mm = 2 * stock::profile_radius(tool_, m.ap_mm);  // Bagci Eq. 2 for a ball
  m.cwe_area_mm2 = acc.cwe + m.bottom_area_mm2;
  m.section_mm2 = cos_a * acc.mrr_h + sin_a * acc.mrr_v - sin_a * m.bottom_area_mm2;
  m.mrr_mm3_per_s = vf_mm_per_s * m.section_mm2;
  if (acc.y_hi >= acc.y_lo) m.ae_mm = acc.y_hi - acc.y_lo;
  if (acc.up + acc.down > 0) m.up_share = acc.up / (acc.up + acc.down);
  return m;
}

}  // namespace deflex::engage
