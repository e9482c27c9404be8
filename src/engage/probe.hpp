// The probes of the engagement (engagement.cpp): whether a point is in material,
// the Z-map less the pending swept volumes, asked point by point (PlainProbe,
// the definition) or with every shortcut that provably keeps its answers
// (CulledProbe).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "deflex/stock/sweep.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::engage::detail {

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

inline NearSweep near_sweep(const stock::LineSweep& l, double tx, double ty) {
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
inline float float_below(double z) {
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

}  // namespace deflex::engage::detail
