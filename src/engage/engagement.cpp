#include "deflex/engage/engagement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "deflex/diag/diagnostics.hpp"
#include "band.hpp"

namespace deflex::engage {

namespace {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2 * pi;

// A pending sweep whose footprint reaches the tool's, with what the distance
// pre-test of CulledProbe needs.
struct NearSweep {
  const stock::LineSweep* s;
  double ax, ay, ex, ey, len;  // XY segment: from (ax, ay) along the unit (ex, ey), len mm (0: plunge)
  double z_low;                // lowest tip height on the segment
  double axis_mm;              // XY distance from the tool axis to the segment
  double radius_mm;            // of its tool
};

// XY distance from (x, y) to the segment, squared.
inline double segment_distance2(double ax, double ay, double ex, double ey, double len, double x, double y) {
  const double wx = x - ax, wy = y - ay;
  const double par = wx * ex + wy * ey, perp = wx * ey - wy * ex;
  const double q = par - std::clamp(par, 0.0, len);
  return q * q + perp * perp;
}

NearSweep near_sweep(const stock::LineSweep& l, double tx, double ty) {
  NearSweep n{&l, l.a()[0], l.a()[1], l.dir_x(), l.dir_y(), l.xy_length(), std::min(l.a()[2], l.b()[2]), 0,
              l.tool().radius_mm};
  n.axis_mm = std::sqrt(segment_distance2(n.ax, n.ay, n.ex, n.ey, n.len, tx, ty));
  return n;
}

// The Z-map and the pending sweeps whose footprint reaches the tool's.
struct LocalStock {
  const stock::ZMap* zmap;
  double base;
  double tx, ty;  // tool axis
  double fx, fy;  // feed direction
  const std::vector<NearSweep>* near;
};

// The definition: the point (x, y, z) is in material when it is inside the
// Z-map column and outside every pending swept volume (but `skip`).
inline bool in_material(const LocalStock& s, double x, double y, double z, const stock::LineSweep* skip = nullptr) {
  if (!(z < s.zmap->height_smooth(x, y)) || z < s.base) return false;
  for (const NearSweep& n : *s.near)
    if (n.s != skip && n.s->lower_height(x, y) <= z) return false;
  return true;
}

// The probes answer "in material?" for the points evaluate_with asks about, in
// three contexts: the samples of one slice circle (scan_slice, then on_slice for
// the refinement of its transitions, at the same height and radius), and points
// of a region (begin_region, then in_region) within `reach` of the axis at
// heights up to z_top (the a_p bisection, the flat bottom); in_region_before
// answers for the stock before the current move (the depth of the cut).

// The definition, point by point (evaluate_reference).
class PlainProbe {
 public:
  static constexpr bool tables = false;  // sin and cos of the refinement computed as they come
  explicit PlainProbe(const LocalStock& s) : s_(s) {}
  void begin_circles(int, const double*, const double*) {}
  bool slice_empty(double, double) const { return false; }
  int scan_slice(double z, double, int n, const double* px, const double* py, char* in) {
    z_ = z;
    int count = 0;
    for (int j = 0; j < n; ++j) count += (in[j] = in_material(s_, px[j], py[j], z));
    return count;
  }
  bool on_slice(double x, double y) const { return in_material(s_, x, y, z_); }
  void begin_region(double, double) {}
  bool in_region(double x, double y, double z) const { return in_material(s_, x, y, z); }
  bool in_region_before(double x, double y, double z, const stock::LineSweep* current) const {
    return in_material(s_, x, y, z, current);
  }

 private:
  const LocalStock& s_;
  double z_ = 0;
};

// The largest float h such that a bilinear blend of heights <= h (rounding
// included, a few 1e-16 relative) stays below z: when no cell near a point is
// above h, the point is not below the Z-map surface at height z.
float float_below(double z) {
  const double lim = z - 1e-9 * (1 + std::fabs(z));
  float h = static_cast<float>(lim);
  if (static_cast<double>(h) > lim) h = std::nextafter(h, -std::numeric_limits<float>::infinity());
  return h;
}

// The same answers with less work: each shortcut skips only tests whose
// outcome it has proved, so the answers are the definition's, bit for bit.
//
// Z-map: most samples of the upper slices lie above the stock (the slices go up
// to the highest point of the whole footprint). A slice circle, then each of its
// 8 arcs, is out at once when no cell its bilinear lookups can read (its
// bounding box plus 1.5 cells) is above float_below(z): ZMap::none_above, from
// the tile row maxima, stopping at the first tile above. The remaining lookups
// are prefetched together.
//
// Sweeps: a point in material paid for a lower_height call per near sweep (30-60
// on a finishing path). The tool's lower surface rises with the XY distance d
// from the segment, from the segment's lowest tip z_low: lower_height >= z_low +
// profile_height(d) (lower_height evaluates the tool at some position of the
// segment, exact to a few 1e-16 relative, 1e-7 mm where the square root of a
// profile near its equator cancels). So a sweep cannot reach a point at height
// <= z beyond rho = profile_radius(z - z_low + 1e-6) + 1e-5 mm: it is dropped for
// the whole slice (region) when even the circle's nearest point is farther, and
// a point farther than rho from the segment (by a distance pre-test, or because
// it lies ahead of the segment's front along the feed) skips the call. The
// margins are far above the rounding and far below anything that matters to the
// culling.
class CulledProbe {
 public:
  static constexpr int arcs = 8;  // per slice circle, tested against the Z-map first
  static constexpr bool tables = true;
  explicit CulledProbe(const LocalStock& s) : s_(s), margin_(1.5 * s.zmap->grid().cell_mm) {}

  // The sample directions (unit offsets from the axis, world frame) of this
  // evaluation: the arcs' bounding boxes on the unit circle. A sample of a
  // slice of radius r is at t + r u, rounded as a monotone function of u, so the
  // box of an arc is t + r times its unit box, exactly.
  void begin_circles(int n, const double* ux, const double* uy) {
    const int g = (n + arcs - 1) / arcs;
    for (int a = 0; a * g < n; ++a) {
      const int j0 = a * g, j1 = std::min(n, j0 + g);
      Box& b = arc_[a];
      b = {ux[j0], ux[j0], uy[j0], uy[j0]};
      for (int j = j0 + 1; j < j1; ++j) {
        b.x0 = std::min(b.x0, ux[j]);
        b.x1 = std::max(b.x1, ux[j]);
        b.y0 = std::min(b.y0, uy[j]);
        b.y1 = std::max(b.y1, uy[j]);
      }
    }
  }

  bool slice_empty(double z, double r) const {
    const double m = r + margin_;
    return s_.zmap->none_above(s_.tx - m, s_.ty - m, s_.tx + m, s_.ty + m, float_below(z));
  }

  int scan_slice(double z, double r, int n, const double* px, const double* py, char* in) {
    z_ = z;
    reach_ = r;
    built_ = false;
    std::vector<double>& hs = heights();
    hs.resize(static_cast<std::size_t>(n));
    const float h = float_below(z);
    const int g = (n + arcs - 1) / arcs;
    auto end = [&](int a) { return std::min(n, a * g + g); };
    bool skip[arcs] = {};
    for (int a = 0; a * g < n; ++a) {
      const Box& b = arc_[a];
      const double xa = s_.tx + r * b.x0, xb = s_.tx + r * b.x1, ya = s_.ty + r * b.y0, yb = s_.ty + r * b.y1;
      skip[a] = s_.zmap->none_above(std::min(xa, xb) - margin_, std::min(ya, yb) - margin_, std::max(xa, xb) + margin_,
                                    std::max(ya, yb) + margin_, h);
      if (!skip[a])
        for (int j = a * g; j < end(a); ++j) s_.zmap->prefetch_smooth(px[j], py[j]);
    }
    // The lookups after all the prefetches: they often miss the cache and do not
    // depend on one another.
    for (int a = 0; a * g < n; ++a)
      if (!skip[a])
        for (int j = a * g; j < end(a); ++j) hs[j] = s_.zmap->height_smooth(px[j], py[j]);
    int count = 0;
    for (int a = 0; a * g < n; ++a)
      for (int j = a * g; j < end(a); ++j) count += (in[j] = !skip[a] && below(hs[j], z) && slice_clear(px[j], py[j]));
    return count;
  }

  bool on_slice(double x, double y) { return below(s_.zmap->height_smooth(x, y), z_) && slice_clear(x, y); }

  void begin_region(double z_top, double reach) { keep(z_top, reach); }

  bool in_region(double x, double y, double z) const {
    return below(s_.zmap->height_smooth(x, y), z) && outside_sweeps(x, y, z);
  }
  bool in_region_before(double x, double y, double z, const stock::LineSweep* current) const {
    return below(s_.zmap->height_smooth(x, y), z) && outside_sweeps(x, y, z, current);
  }

 private:
  // The kept sweeps as arrays for the two-at-a-time pre-test: the nearest
  // first, then by decreasing front (the largest coordinate along the feed
  // direction, from the axis, of a point within their reach); padded with an
  // entry that never passes.
  struct Kept {
    std::vector<const stock::LineSweep*> s;
    std::vector<double> ax, ay, ex, ey, len, reach2, front;
    std::vector<char> pass;
    std::size_t n = 0;
    void reserve(std::size_t m) {  // grows only, so that a warm thread does not allocate
      if (s.size() >= m) return;
      for (auto* v : {&ax, &ay, &ex, &ey, &len, &reach2, &front}) v->resize(m);
      s.resize(m);
      pass.resize(m);
    }
    void move(std::size_t from, std::size_t to) {
      s[to] = s[from];
      ax[to] = ax[from];
      ay[to] = ay[from];
      ex[to] = ex[from];
      ey[to] = ey[from];
      len[to] = len[from];
      reach2[to] = reach2[from];
      front[to] = front[from];
    }
  };

  // z is below the Z-map surface at height `surface` and above the base.
  bool below(double surface, double z) const { return z < surface && !(z < s_.base); }

  bool slice_clear(double x, double y) {
    if (!built_) {  // at the first sample below the surface
      keep(z_, reach_);
      built_ = true;
    }
    return outside_sweeps(x, y, z_);
  }

  // The near sweeps that may reach a point within `reach` of the axis at a
  // height <= z.
  void keep(double z, double reach) {
    Kept& k = kept();
    const std::vector<NearSweep>& near = *s_.near;
    k.reserve(near.size() + 1);
    std::size_t n = 0;
    for (const NearSweep& w : near) {
      if (w.axis_mm - w.radius_mm > reach + 1e-5) break;  // out of reach, and so are the rest
      const double h = z - w.z_low + 1e-6;
      if (h < 0) continue;
      const double rho = stock::profile_radius(w.s->tool(), h) + 1e-5;
      if (w.axis_mm > reach + rho) continue;
      // Front along the feed: the segment's farther end plus the reach; a
      // point ahead of it is farther than the reach from the whole segment.
      // Insertion by decreasing front after the nearest (mostly an append: the
      // nearer sweeps reach farther ahead).
      const double a = (w.ax - s_.tx) * s_.fx + (w.ay - s_.ty) * s_.fy;
      const double front = std::max(a, a + w.len * (w.ex * s_.fx + w.ey * s_.fy)) + rho;
      std::size_t q = n;
      for (; q > 1 && k.front[q - 1] < front; --q) k.move(q - 1, q);
      k.s[q] = w.s;
      k.ax[q] = w.ax;
      k.ay[q] = w.ay;
      k.ex[q] = w.ex;
      k.ey[q] = w.ey;
      k.len[q] = w.len;
      k.reach2[q] = rho * rho;
      k.front[q] = front;
      ++n;
    }
    k.n = n;
    k.ax[n] = k.ay[n] = k.ex[n] = k.ey[n] = k.len[n] = 0;  // the pad, never passes
    k.reach2[n] = -1;
  }

  bool outside_sweeps(double x, double y, double z, const stock::LineSweep* skip = nullptr) const {
    Kept& k = kept();
    const std::size_t n = k.n;
    if (n == 0) return true;
    // The nearest alone first: in the wake of the current move it decides at once.
    if (segment_distance2(k.ax[0], k.ay[0], k.ex[0], k.ey[0], k.len[0], x, y) <= k.reach2[0] && k.s[0] != skip &&
        k.s[0]->lower_height(x, y) <= z)
      return false;
    // The others whose front is not behind the point.
    const double along = (x - s_.tx) * s_.fx + (y - s_.ty) * s_.fy;
    std::size_t c = 1;
    while (c < n && !(k.front[c] < along)) ++c;
#ifdef __SSE2__
    // The pre-test two at a time (the arithmetic of segment_distance2; a
    // pre-test needs only to be conservative, and the margins of keep() are far
    // above any difference in rounding).
    const __m128d px = _mm_set1_pd(x), py = _mm_set1_pd(y), zero = _mm_setzero_pd();
    for (std::size_t i = 1; i < c; i += 2) {
      const __m128d wx = _mm_sub_pd(px, _mm_loadu_pd(&k.ax[i])), wy = _mm_sub_pd(py, _mm_loadu_pd(&k.ay[i]));
      const __m128d ex = _mm_loadu_pd(&k.ex[i]), ey = _mm_loadu_pd(&k.ey[i]);
      const __m128d par = _mm_add_pd(_mm_mul_pd(wx, ex), _mm_mul_pd(wy, ey));
      const __m128d perp = _mm_sub_pd(_mm_mul_pd(wx, ey), _mm_mul_pd(wy, ex));
      const __m128d q = _mm_sub_pd(par, _mm_min_pd(_mm_max_pd(par, zero), _mm_loadu_pd(&k.len[i])));
      const __m128d d2 = _mm_add_pd(_mm_mul_pd(q, q), _mm_mul_pd(perp, perp));
      const int m = _mm_movemask_pd(_mm_cmple_pd(d2, _mm_loadu_pd(&k.reach2[i])));
      k.pass[i] = m & 1;
      k.pass[i + 1] = m >> 1;
    }
    for (std::size_t i = 1; i < c; ++i)
      if (k.pass[i] && k.s[i] != skip && k.s[i]->lower_height(x, y) <= z) return false;
#else
    for (std::size_t i = 1; i < c; ++i)
      if (segment_distance2(k.ax[i], k.ay[i], k.ex[i], k.ey[i], k.len[i], x, y) <= k.reach2[i] && k.s[i] != skip &&
          k.s[i]->lower_height(x, y) <= z)
        return false;
#endif
    return true;
  }

  static Kept& kept() {
    thread_local Kept v;
    return v;
  }
  static std::vector<double>& heights() {
    thread_local std::vector<double> v;
    return v;
  }

  struct Box {
    double x0, x1, y0, y1;
  };

  const LocalStock& s_;
  double margin_;
  Box arc_[arcs];
  double z_ = 0, reach_ = 0;
  bool built_ = false;
};

}  // namespace

stock::ToolProfile tool_profile(const force::Cutter& c) {
  return {c.type, c.diameter_mm / 2, force::corner_radius_of(c)};
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

template <class Probe>
Metrics Engager::evaluate_with(const StockView& stock, const CLPoint& p, const Process& proc,
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
  thread_local std::vector<NearSweep> near;
  near.clear();
  auto overlaps = [&](const stock::LineSweep& l) {
    return l.x_min() <= tx + R && l.x_max() >= tx - R && l.y_min() <= ty + R && l.y_max() >= ty - R;
  };
  if (stock.current && overlaps(*stock.current)) near.push_back(near_sweep(*stock.current, tx, ty));
  for (auto it = stock.pending.rbegin(); it != stock.pending.rend(); ++it)
    if (overlaps(*it)) near.push_back(near_sweep(*it, tx, ty));
  // Nearest first: the current move (at the axis) decides for the whole wake at
  // once, and the culling of CulledProbe stops at the first one out of reach.
  std::sort(near.begin(), near.end(), [](const NearSweep& u, const NearSweep& v) {
    return u.axis_mm - u.radius_mm < v.axis_mm - v.radius_mm;
  });
  const LocalStock local{stock.zmap, base, tx, ty, fx, fy, &near};
  Probe probe(local);

  constexpr std::size_t npos = static_cast<std::size_t>(-1);
  std::size_t top_slice = npos;
  Accum acc;
  thread_local std::vector<char> in;
  thread_local std::vector<force::AngleInterval> ivs;
  thread_local std::vector<double> ux, uy, px, py;
  in.resize(static_cast<std::size_t>(2 * N));
  for (auto* v : {&ux, &uy, &px, &py}) v->resize(static_cast<std::size_t>(N));
  for (int j = 0; j < N; ++j) {  // the sample directions in the world frame
    ux[j] = sin_[j] * fx - cos_[j] * fy;
    uy[j] = sin_[j] * fy + cos_[j] * fx;
  }
  probe.begin_circles(N, ux.data(), uy.data());

  for (std::size_t i = 0; i < n_slices; ++i) {
    const force::Slice& s = cs_.slices[i];
    const double zq = tz + s.z_mm;
    if (zq >= zmax) break;  // slices rise with i
    if (zq < base) continue;
    // Tested a hair inside the envelope: a flank sliding along its own earlier
    // positions (the side of a plunging end mill) rubs and must not count as
    // cutting; 1e-8 mm is far above rounding and far below any tolerance.
    const double r = s.r_mm - 1e-8;
    if (probe.slice_empty(zq, r)) continue;
    auto test = [&](double sp, double cp) {
      return probe.on_slice(tx + r * (sp * fx - cp * fy), ty + r * (sp * fy + cp * fx));
    };
    for (int j = 0; j < N; ++j) {
      px[j] = tx + r * ux[j];
      py[j] = ty + r * uy[j];
    }
    const int count = probe.scan_slice(zq, r, N, px.data(), py.data(), in.data());
    if (count == 0) continue;
    top_slice = i;
    if (count == N) {
      out.add(i, 0, two_pi);
      continue;
    }
    // Boundary between sample angles phi_out and phi_in (unwrapped, adjacent).
    auto angle = [&](int j) { return (j + 0.5) * dphi; };  // j may be outside [0, N)
    // b = k: the boundary lies in [angle(k - 1), angle(k)]; in_low: the in side is k - 1.
    auto refine = [&](int b, bool in_low) {
      double phi_out = angle(in_low ? b : b - 1), phi_in = angle(in_low ? b - 1 : b);
      const std::array<double, 2>* sc =
          Probe::tables && refine_nodes_ ? &refine_sc_[static_cast<std::size_t>(b) * refine_nodes_] : nullptr;
      int node = 1;
      for (int k = 0; k < o_.refine_steps; ++k) {
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

  // a_p: from the highest engaged slice, bisect upward (to the next slice or the
  // stock's highest point) at the middle of each of its intervals, for the
  // height where the flank leaves the material.
  double ap = 0;
  if (top_slice != npos) {
    const force::Slice& s = cs_.slices[top_slice];
    const double z_hi = std::min(s.z_mm + cs_.dz_mm, zmax - tz);
    probe.begin_region(tz + z_hi, stock::profile_radius(tool_, z_hi));
    for (const force::AngleInterval& iv : out.slices[top_slice]) {
      const double mid = 0.5 * (iv.start + iv.end), sp = std::sin(mid), cp = std::cos(mid);
      double lo = s.z_mm, hi = z_hi;
      for (int k = 0; k < o_.refine_steps + 6; ++k) {
        const double zm = 0.5 * (lo + hi);
        const double r = stock::profile_radius(tool_, zm) - 1e-8;
        (probe.in_region(tx + r * (sp * fx - cp * fy), ty + r * (sp * fy + cp * fx), tz + zm) ? lo : hi) = zm;
      }
      ap = std::max(ap, 0.5 * (lo + hi));
    }
  }
  const double envelope_top = ap;
  if (top_slice != npos)
    ap = cut_top(probe, p, stock.current, out, top_slice, envelope_top, stock.zmap->grid().cell_mm);

  // Slice i stands for the band [i dz, (i+1) dz]; the highest engaged one for
  // [i dz, a_p], so the removal rate does not depend on where a_p falls in a slice.
  const double dz = cs_.dz_mm;
  for (std::size_t i = 0; i < n_slices && top_slice != npos && i <= top_slice; ++i) {
    if (out.slices[i].empty()) continue;
    const double z0 = static_cast<double>(i) * dz, z1 = i == top_slice ? std::max(envelope_top, z0) : z0 + dz;
    const double rdz = i == top_slice ? radius_integral(tool_, z1) - radius_integral(tool_, z0) : band_rdz_[i];
    for (const force::AngleInterval& iv : out.slices[i]) accumulate(cs_.slices[i], iv.start, iv.end, z1 - z0, rdz, dz, acc);
  }

  // Flat bottom: cuts only when descending (its normal is -Z).
  const double rf = R - stock::corner_of(tool_);
  if (rf > 0 && sin_a < -1e-9 && tz < zmax && tz >= base) {
    const int K = o_.bottom_rings;
    const double dr = rf / K;
    probe.begin_region(tz, rf);
    for (int k = 0; k < K; ++k) {
      const double rho = (k + 0.5) * dr;
      for (int j = 0; j < N; ++j) {
        const double x = tx + rho * ux[j], y = ty + rho * uy[j];
        if (!probe.in_region(x, y, tz)) continue;
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
  m.section_mm2 = cos_a * acc.mrr_h + sin_a * acc.mrr_v - sin_a * m.bottom_area_mm2;
  m.mrr_mm3_per_s = vf_mm_per_s * m.section_mm2;
  if (acc.y_hi >= acc.y_lo) m.ae_mm = acc.y_hi - acc.y_lo;
  if (acc.up + acc.down > 0) m.up_share = acc.up / (acc.up + acc.down);
  return m;
}

}  // namespace deflex::engage
