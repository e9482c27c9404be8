#include "deflex/stock/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::stock {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// Derivative of the corner-arc height g(d) (profile_height) for d in (R0 - rc, R0).
double profile_slope(double rc, double e) {
  const double q = rc * rc - e * e;
  return q > 0 ? e / std::sqrt(q) : inf;
}

}  // namespace

LineSweep::LineSweep(const ToolProfile& tool, const Point3& a_mm, const Point3& b_mm)
    : tool_(tool), a_(a_mm), b_(b_mm) {
  const double dx = b_[0] - a_[0], dy = b_[1] - a_[1];
  len_ = std::hypot(dx, dy);
  // Below 1 nm of XY travel the move is a plunge (vertical).
  if (len_ > 1e-6) {
    ex_ = dx / len_;
    ey_ = dy / len_;
    slope_ = (b_[2] - a_[2]) / len_;
  } else {
    len_ = 0;
  }
  const double R = tool_.radius_mm;
  xmin_ = std::min(a_[0], b_[0]) - R;
  xmax_ = std::max(a_[0], b_[0]) + R;
  ymin_ = std::min(a_[1], b_[1]) - R;
  ymax_ = std::max(a_[1], b_[1]) + R;
}

double LineSweep::lower_height(double x, double y) const {
  if (x < xmin_ || x > xmax_ || y < ymin_ || y > ymax_) return inf;
  const double R = tool_.radius_mm;
  const double wx = x - a_[0], wy = y - a_[1];
  if (len_ == 0) {  // plunge: the lowest of the two tool positions
    const double d = std::hypot(wx, wy);
    return d > R ? inf : std::min(a_[2], b_[2]) + profile_height(tool_, d);
  }
  // XY coordinates along (par) and across (perp) the segment; sigma in [0, len]
  // is the XY travel, the tip at sigma is at height a_z + slope sigma.
  const double par = wx * ex_ + wy * ey_;
  const double perp = std::fabs(wx * ey_ - wy * ex_);
  if (perp > R) return inf;
  const double rho = std::sqrt(R * R - perp * perp);  // half-chord of the footprint disc
  const double lo = std::max(0.0, par - rho), hi = std::min(len_, par + rho);
  if (lo > hi) return inf;
  const double m = slope_;
  auto tip_z = [&](double s) { return a_[2] + m * s; };
  if (m == 0) {  // horizontal: the nearest tool position is the lowest
    const double s = std::clamp(par, 0.0, len_);
    return tip_z(0) + profile_height(tool_, std::hypot(par - s, perp));
  }
  switch (tool_.kind) {
    case ToolKind::flat:
      // Height a_z + m sigma on the interval where the disc covers (x, y).
      return tip_z(m > 0 ? lo : hi);
    case ToolKind::ball: {
      // Ball centre c(s) = tip + R; the surface below (x, y) is at
      // c_z(s) - sqrt(rho^2 - (s - par)^2). Setting the derivative to zero:
      // (s - par) / sqrt(rho^2 - (s - par)^2) = -m  =>  s - par = -m rho / sqrt(1 + m^2).
      const double s = std::clamp(par - m * rho / std::sqrt(1 + m * m), lo, hi);
      const double q = s - par;
      return tip_z(s) + R - std::sqrt(std::max(0.0, rho * rho - q * q));
    }
    case ToolKind::bull: {
      // Convex in s: bisect on the sign of the derivative
      // m + g'(d) (s - par) / d, d = hypot(s - par, perp), g the corner height.
      const double rc = tool_.corner_radius_mm, rf = R - rc;
      auto deriv = [&](double s) {
        const double q = s - par, d = std::hypot(q, perp), e = d - rf;
        if (e <= 0 || d == 0) return m;
        return m + profile_slope(rc, e) * q / d;
      };
      double l = lo, h = hi;
      if (deriv(l) >= 0) {
        h = l;
      } else if (deriv(h) <= 0) {
        l = h;
      } else {
        for (int it = 0; it < 60 && h - l > 1e-12 * (1 + len_); ++it) {
          const double mid = 0.5 * (l + h);
          (deriv(mid) > 0 ? h : l) = mid;
        }
      }
      const double s = 0.5 * (l + h);
      return tip_z(s) + profile_height(tool_, std::min(R, std::hypot(s - par, perp)));
    }
  }
  return inf;
}

bool LineSweep::row_range(double y, double& x0, double& x1, bool start_cut) const {
  const double R = tool_.radius_mm;
  if (start_cut && len_ == 0 && b_[2] >= a_[2]) return false;  // a retract removes nothing new
  double lo = inf, hi = -inf;
  auto disc = [&](const Point3& c) {
    const double dy = y - c[1];
    if (std::fabs(dy) > R) return;
    const double w = std::sqrt(R * R - dy * dy);
    lo = std::min(lo, c[0] - w);
    hi = std::max(hi, c[0] + w);
  };
  disc(a_);
  disc(b_);
  if (len_ > 0) {
    // The band 0 <= par <= len, |perp| <= R is linear in x on this row.
    double bl = -inf, bh = inf;
    auto clip = [&](double coef, double c0, double vmin, double vmax) {
      // vmin <= coef x + c0 <= vmax
      if (std::fabs(coef) < 1e-15) {
        if (c0 < vmin || c0 > vmax) bl = inf;
        return;
      }
      double p = (vmin - c0) / coef, q = (vmax - c0) / coef;
      if (p > q) std::swap(p, q);
      bl = std::max(bl, p);
      bh = std::min(bh, q);
    };
    const double wy = y - a_[1];
    clip(ex_, -a_[0] * ex_ + wy * ey_, 0, len_);
    clip(ey_, -a_[0] * ey_ - wy * ex_, -R, R);
    if (bl <= bh) {
      lo = std::min(lo, bl);
      hi = std::max(hi, bh);
    }
  }
  if (start_cut && len_ > 0 && slope_ >= 0) {
    // Keep par(x) = ex x + c >= 0.
    const double c = -a_[0] * ex_ + (y - a_[1]) * ey_;
    if (std::fabs(ex_) < 1e-15) {
      if (c < 0) return false;
    } else if (ex_ > 0) {
      lo = std::max(lo, -c / ex_);
    } else {
      hi = std::min(hi, -c / ex_);
    }
  }
  if (lo > hi) return false;
  x0 = lo;
  x1 = hi;
  return true;
}

namespace {

// Rows [j0, j1] of one sweep.
double sweep_rows(ZMap& z, const LineSweep& s, int j0, int j1, bool start_cut) {
  const GridSpec& g = z.grid();
  j0 = std::max({j0, 0, z.iy(s.y_min())});
  j1 = std::min({j1, g.ny - 1, z.iy(s.y_max())});
  thread_local std::vector<float> buf;
  double removed = 0;
  for (int j = j0; j <= j1; ++j) {
    const double y = z.cy(j);
    double xa, xb;
    if (!s.row_range(y, xa, xb, start_cut)) continue;
    // Cells whose centre lies in [xa, xb].
    const int i0 = std::max(0, static_cast<int>(std::ceil((xa - g.x0_mm) / g.cell_mm - 0.5)));
    const int i1 = std::min(g.nx - 1, static_cast<int>(std::floor((xb - g.x0_mm) / g.cell_mm - 0.5)));
    if (i1 < i0) continue;
    buf.resize(static_cast<std::size_t>(i1 - i0 + 1));
    for (int i = i0; i <= i1; ++i) {
      const double h = s.lower_height(z.cx(i), y);
      buf[static_cast<std::size_t>(i - i0)] =
          h == inf ? std::numeric_limits<float>::infinity() : static_cast<float>(h);
    }
    removed += z.lower_row(j, i0, i1 - i0 + 1, buf.data());
  }
  return removed;
}

}  // namespace

double sweep_line(ZMap& z, const LineSweep& s, bool start_cut) {
  return sweep_rows(z, s, 0, z.grid().ny - 1, start_cut);
}

double sweep_lines(ZMap& z, std::span<const LineSweep> s, bool first_start_cut) {
  if (s.empty()) return 0;
  double y0 = s[0].y_min(), y1 = s[0].y_max();
  for (const LineSweep& l : s) {
    y0 = std::min(y0, l.y_min());
    y1 = std::max(y1, l.y_max());
  }
  const int T = ZMap::tile_cells;
  const int j0 = std::max(0, z.iy(y0)), j1 = std::min(z.grid().ny - 1, z.iy(y1));
  if (j1 < j0) return 0;
  auto chained = [&](std::size_t k) {
    if (k == 0) return first_start_cut;
    return s[k].a() == s[k - 1].b();
  };
  // One task per tile row: lower_row on different tile rows never shares a tile.
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(j0 / T, j1 / T + 1, 1), 0.0,
      [&](const tbb::blocked_range<int>& r, double acc) {
        for (int band = r.begin(); band != r.end(); ++band)
          for (std::size_t k = 0; k < s.size(); ++k)
            acc += sweep_rows(z, s[k], band * T, band * T + T - 1, chained(k));
        return acc;
      },
      [](double a, double b) { return a + b; });
}

double sweep_line(ZMap& z, const ToolProfile& tool, const Point3& a_mm, const Point3& b_mm) {
  return sweep_line(z, LineSweep(tool, a_mm, b_mm));
}

double sweep_polyline(ZMap& z, const ToolProfile& tool, std::span<const Point3> pts) {
  std::vector<LineSweep> segs;
  segs.reserve(pts.size());
  for (std::size_t k = 1; k < pts.size(); ++k) segs.emplace_back(tool, pts[k - 1], pts[k]);
  return sweep_lines(z, segs, false);
}

// ---- arcs ---------------------------------------------------------------------

namespace {

struct PlaneIdx {
  int a, b, n;  // in-plane axes (angle measured from a toward b) and normal
};
PlaneIdx plane_idx(int plane) {
  if (plane == 18) return {2, 0, 1};
  if (plane == 19) return {1, 2, 0};
  return {0, 1, 2};
}

}  // namespace

double arc_radius_mm(const Arc& a) {
  const PlaneIdx p = plane_idx(a.plane);
  return std::hypot(a.start_mm[p.a] - a.centre_mm[p.a], a.start_mm[p.b] - a.centre_mm[p.b]);
}

double arc_angle(const Arc& a) {
  const PlaneIdx p = plane_idx(a.plane);
  const double t0 = std::atan2(a.start_mm[p.b] - a.centre_mm[p.b], a.start_mm[p.a] - a.centre_mm[p.a]);
  const double t1 = std::atan2(a.end_mm[p.b] - a.centre_mm[p.b], a.end_mm[p.a] - a.centre_mm[p.a]);
  constexpr double two_pi = 2 * std::numbers::pi;
  double d = a.cw ? t0 - t1 : t1 - t0;
  d -= two_pi * std::floor(d / two_pi);
  // Same start and end angle: a full circle (the interpreter only emits those on purpose).
  if (d < 1e-9) d = two_pi;
  return d;
}

double arc_length_mm(const Arc& a) {
  const PlaneIdx p = plane_idx(a.plane);
  return std::hypot(arc_radius_mm(a) * arc_angle(a), a.end_mm[p.n] - a.start_mm[p.n]);
}

Point3 arc_point(const Arc& a, double u) {
  if (u <= 0) return a.start_mm;
  if (u >= 1) return a.end_mm;
  const PlaneIdx p = plane_idx(a.plane);
  const double t0 = std::atan2(a.start_mm[p.b] - a.centre_mm[p.b], a.start_mm[p.a] - a.centre_mm[p.a]);
  const double t = t0 + (a.cw ? -1 : 1) * arc_angle(a) * u;
  const double r = arc_radius_mm(a);
  Point3 q{};
  q[p.a] = a.centre_mm[p.a] + r * std::cos(t);
  q[p.b] = a.centre_mm[p.b] + r * std::sin(t);
  q[p.n] = a.start_mm[p.n] + (a.end_mm[p.n] - a.start_mm[p.n]) * u;
  return q;
}

Point3 arc_tangent(const Arc& a, double u) {
  const PlaneIdx p = plane_idx(a.plane);
  const double t0 = std::atan2(a.start_mm[p.b] - a.centre_mm[p.b], a.start_mm[p.a] - a.centre_mm[p.a]);
  const double ang = arc_angle(a);
  const double sgn = a.cw ? -1 : 1;
  const double t = t0 + sgn * ang * u;
  const double r = arc_radius_mm(a);
  Point3 v{};
  // d/du of the point: r * ang * sgn * (-sin t, cos t), rise along the normal.
  v[p.a] = -r * ang * sgn * std::sin(t);
  v[p.b] = r * ang * sgn * std::cos(t);
  v[p.n] = a.end_mm[p.n] - a.start_mm[p.n];
  const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (l > 0)
    for (double& c : v) c /= l;
  return v;
}

int arc_chord_count(const Arc& a, double chord_tol_mm) {
  if (!(chord_tol_mm > 0)) throw Error(Exit::internal, "arc_chord_count: tolerance must be > 0");
  const double r = arc_radius_mm(a);
  if (r <= chord_tol_mm) return std::max(1, static_cast<int>(std::ceil(arc_angle(a) / (std::numbers::pi / 2))));
  const double dmax = 2 * std::acos(1 - chord_tol_mm / r);
  return std::max(1, static_cast<int>(std::ceil(arc_angle(a) / dmax - 1e-9)));
}

std::vector<Point3> arc_polyline(const Arc& a, int chords) {
  chords = std::max(1, chords);
  std::vector<Point3> pts(static_cast<std::size_t>(chords) + 1);
  for (int k = 0; k <= chords; ++k) pts[static_cast<std::size_t>(k)] = arc_point(a, static_cast<double>(k) / chords);
  return pts;
}

double sweep_arc(ZMap& z, const ToolProfile& tool, const Arc& a, double chord_tol_mm) {
  const auto pts = arc_polyline(a, arc_chord_count(a, chord_tol_mm));
  return sweep_polyline(z, tool, pts);
}

}  // namespace deflex::stock
