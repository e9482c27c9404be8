// LineSweep: the envelope of the tool moving on one straight line, cell by cell
// (lower_height) and row by row (row_range); the fast row kernels are in
// row_kernels.cpp, the hand-off to the next move in handoff.cpp.
#include "deflex/stock/sweep.hpp"

#include <algorithm>
#include <cmath>

#include "kernels.hpp"

namespace deflex::stock {

using detail::inf;

LineSweep::LineSweep(const ToolProfile& tool, const Point3& a_mm, const Point3& b_mm)
    : tool_(tool), a_(a_mm), b_(b_mm) {
  const double dx = b_[0] - a_[0], dy = b_[1] - a_[1];
  len_ = std::hypot(dx, dy);
  // Below 1 nm of XY travel the move is a plunge (vertical).
  if (len_ > 1e-6) {
    ex_ = dx / len_;
    ey_ = dy / len_;
    slope_ = (b_[2] - a_[2]) / len_;
    ball_k_ = slope_ / std::sqrt(1 + slope_ * slope_);
  } else {
    len_ = 0;
  }
  const double R = tool_.radius_mm;
  xmin_ = std::min(a_[0], b_[0]) - R;
  xmax_ = std::max(a_[0], b_[0]) + R;
  ymin_ = std::min(a_[1], b_[1]) - R;
  ymax_ = std::max(a_[1], b_[1]) + R;
}

namespace {

// A bull nose's lower surface over a cell, f(s) = a_z + m s + g(d(s)) with d =
// hypot(s - par, perp) and g the corner height, is convex in s: its derivative
// f'(s) = m + g'(d) (s - par) / d and, for Newton's method, f''(s) = g''(d) (q /
// d)^2 + g'(d) perp^2 / d^3.
struct BullSlope {
  double m, par, perp, rc, rf;  // rf = R - r_c
  double operator()(double s, double* d2f) const {
    const double q = s - par, d = std::sqrt(q * q + perp * perp), e = d - rf;
    if (e <= 0 || d == 0) {
      if (d2f) *d2f = 0;
      return m;
    }
    const double w = rc * rc - e * e;
    if (!(w > 0)) {
      if (d2f) *d2f = 0;
      return q > 0 ? inf : q < 0 ? -inf : m;
    }
    const double sw = std::sqrt(w), g1 = e / sw;
    if (d2f) *d2f = rc * rc / (w * sw) * (q / d) * (q / d) + g1 * perp * perp / (d * d * d);
    return m + g1 * q / d;
  }
};

// The travel s in [lo, hi] where f is least: the root of f' by Newton's method
// kept inside a bisection bracket (to 1e-12 of the segment, as plain bisection).
double bull_contact(const BullSlope& deriv, double lo, double hi, double len) {
  const double tol = 1e-12 * (1 + len);
  double l = lo, h = hi;
  if (deriv(l, nullptr) >= 0) return l;
  if (deriv(h, nullptr) <= 0) return h;
  double s = 0.5 * (l + h);
  for (int it = 0; it < 200 && h - l > tol; ++it) {
    double d2f;
    const double f1 = deriv(s, &d2f);
    if (f1 == 0) break;
    (f1 > 0 ? h : l) = s;
    const double step = d2f > 0 ? f1 / d2f : inf;
    const double nt = s - step;
    if (nt > l && nt < h && std::fabs(step) < 0.5 * (h - l)) {
      s = nt;
      if (std::fabs(step) <= tol) break;
    } else {
      s = 0.5 * (l + h);
    }
  }
  return s;
}

}  // namespace

double LineSweep::lower_height(double x, double y) const {
  if (x < xmin_ || x > xmax_ || y < ymin_ || y > ymax_) return inf;
  const double R = tool_.radius_mm;
  const double wx = x - a_[0], wy = y - a_[1];
  if (len_ == 0) {  // plunge: the lowest of the two tool positions
    const double d = std::sqrt(wx * wx + wy * wy);  // mm: no overflow, cheaper than hypot
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
    const double q = par - s;
    return tip_z(0) + profile_height(tool_, std::sqrt(q * q + perp * perp));
  }
  switch (tool_.kind) {
    case EndShape::flat:
      // Height a_z + m sigma on the interval where the disc covers (x, y).
      return tip_z(m > 0 ? lo : hi);
    case EndShape::ball: {
      // Ball centre c(s) = tip + R; the surface below (x, y) is at
      // c_z(s) - sqrt(rho^2 - (s - par)^2). Setting the derivative to zero:
      // (s - par) / sqrt(rho^2 - (s - par)^2) = -m  =>  s - par = -m rho / sqrt(1 + m^2).
      const double s = std::clamp(par - ball_k_ * rho, lo, hi);
      const double q = s - par;
      return tip_z(s) + R - std::sqrt(std::max(0.0, rho * rho - q * q));
    }
    case EndShape::bull: {
      const double rc = tool_.corner_radius_mm;
      const double s = bull_contact(BullSlope{m, par, perp, rc, R - rc}, lo, hi, len_);
      const double q = s - par;
      return tip_z(s) + profile_height(tool_, std::min(R, std::sqrt(q * q + perp * perp)));
    }
  }
  return inf;
}

namespace detail {

StartCut start_cut_of(const LineSweep& s, bool start_cut) {
  StartCut c;
  const double slope = s.slope(), R = s.tool().radius_mm;
  c.cut = start_cut && s.xy_length() > 0 && (slope >= 0 || s.tool().kind != EndShape::flat);
  if (!c.cut || !(slope < 0)) return c;
  // g'(d) / d >= 1 / R for a ball; a bull nose's g'(r1) = 1 / sqrt(3).
  if (s.tool().kind == EndShape::ball) {
    c.back = -slope * R;
  } else {
    c.r1 = R - 0.5 * corner_of(s.tool());
    c.back = -slope * c.r1 * std::sqrt(3.0);
  }
  c.back *= 1 + 1e-9;  // rounding: never drop a cell on the boundary
  return c;
}

}  // namespace detail

namespace {

// The footprint of s on the line y: the discs about a and b and, for a line, the
// band 0 <= par <= len, |perp| <= R between them, linear in x on the row.
void footprint_row(const LineSweep& s, double y, double& lo, double& hi) {
  const double R = s.tool().radius_mm, len = s.xy_length(), ex = s.dir_x(), ey = s.dir_y();
  const Point3 &a = s.a(), &b = s.b();
  lo = inf;
  hi = -inf;
  auto disc = [&](const Point3& c) {
    const double dy = y - c[1];
    if (std::fabs(dy) > R) return;
    const double w = std::sqrt(R * R - dy * dy);
    lo = std::min(lo, c[0] - w);
    hi = std::max(hi, c[0] + w);
  };
  disc(a);
  disc(b);
  if (len > 0) {
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
    const double wy = y - a[1];
    clip(ex, -a[0] * ex + wy * ey, 0, len);
    clip(ey, -a[0] * ey - wy * ex, -R, R);
    if (bl <= bh) {
      lo = std::min(lo, bl);
      hi = std::max(hi, bh);
    }
  }
}

// Narrows [lo, hi] on the line y to start_cut's window c: par(x) = ex x + c0 >=
// -back, plus for a descending bull nose the chord of the disc of radius r1 about a.
void start_cut_row(const LineSweep& s, const detail::StartCut& c, double y, double& lo, double& hi) {
  const double ex = s.dir_x(), ey = s.dir_y();
  const Point3& a = s.a();
  double clo = lo, chi = hi;
  const double c0 = -a[0] * ex + (y - a[1]) * ey;
  if (std::fabs(ex) < 1e-15) {
    if (c0 < -c.back) chi = -inf;
  } else if (ex > 0) {
    clo = std::max(clo, (-c.back - c0) / ex);
  } else {
    chi = std::min(chi, (-c.back - c0) / ex);
  }
  const double dy = y - a[1];
  if (c.r1 > 0 && std::fabs(dy) <= c.r1) {
    const double w = std::sqrt(c.r1 * c.r1 - dy * dy);
    clo = std::min(clo, a[0] - w);
    chi = std::max(chi, a[0] + w);
  }
  lo = std::max(lo, clo);
  hi = std::min(hi, chi);
}

}  // namespace

bool LineSweep::row_range(double y, double& x0, double& x1, bool start_cut) const {
  if (start_cut && len_ == 0 && b_[2] >= a_[2]) return false;  // a retract removes nothing new
  double lo, hi;
  footprint_row(*this, y, lo, hi);
  const detail::StartCut c = detail::start_cut_of(*this, start_cut);
  if (c.cut) start_cut_row(*this, c, y, lo, hi);
  if (lo > hi) return false;
  x0 = lo;
  x1 = hi;
  return true;
}

}  // namespace deflex::stock
