#include "deflex/stock/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>


namespace deflex::stock {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
// sweep_rows leaves a row alone when its stock lies this far below the tool's
// lowest possible surface on it (float rounding at |z| = 1000 mm: 6e-5 mm).
constexpr double kRowSkipMargin_mm = 1e-3;

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
    case ToolKind::flat:
      // Height a_z + m sigma on the interval where the disc covers (x, y).
      return tip_z(m > 0 ? lo : hi);
    case ToolKind::ball: {
      // Ball centre c(s) = tip + R; the surface below (x, y) is at
      // c_z(s) - sqrt(rho^2 - (s - par)^2). Setting the derivative to zero:
      // (s - par) / sqrt(rho^2 - (s - par)^2) = -m  =>  s - par = -m rho / sqrt(1 + m^2).
      const double s = std::clamp(par - ball_k_ * rho, lo, hi);
      const double q = s - par;
      return tip_z(s) + R - std::sqrt(std::max(0.0, rho * rho - q * q));
    }
    case ToolKind::bull: {
      // Convex in s: the root of the derivative f'(s) = m + g'(d) (s - par) / d,
      // d = hypot(s - par, perp), g the corner height, by Newton's method kept
      // inside a bisection bracket (to 1e-12 of the segment, as plain bisection).
      const double rc = tool_.corner_radius_mm, rf = R - rc;
      const double tol = 1e-12 * (1 + len_);
      double l = lo, h = hi, s;
      // f'(s) and f''(s) = g''(d) (q / d)^2 + g'(d) perp^2 / d^3.
      auto deriv = [&](double s, double* d2f) {
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
      };
      if (deriv(l, nullptr) >= 0) {
        s = l;
      } else if (deriv(h, nullptr) <= 0) {
        s = h;
      } else {
        s = 0.5 * (l + h);
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
      }
      const double q = s - par;
      return tip_z(s) + profile_height(tool_, std::min(R, std::sqrt(q * q + perp * perp)));
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
  if (start_cut && len_ > 0 && (slope_ >= 0 || tool_.kind != ToolKind::flat)) {
    // Keep par(x) = ex x + c >= -back (see the header), plus for a descending
    // bull nose the chord of the disc of radius r1 about a.
    double back = 0, r1 = 0;
    if (slope_ < 0) {
      const double rc = corner_of(tool_);
      if (tool_.kind == ToolKind::ball) {
        back = -slope_ * R;
      } else {
        r1 = R - 0.5 * rc;
        back = -slope_ * r1 * std::sqrt(3.0);  // g'(r1) = 1 / sqrt(3)
      }
      back *= 1 + 1e-9;  // rounding: never drop a cell on the boundary
    }
    double clo = lo, chi = hi;
    const double c = -a_[0] * ex_ + (y - a_[1]) * ey_;
    if (std::fabs(ex_) < 1e-15) {
      if (c < -back) chi = -inf;
    } else if (ex_ > 0) {
      clo = std::max(clo, (-back - c) / ex_);
    } else {
      chi = std::min(chi, (-back - c) / ex_);
    }
    const double dy = y - a_[1];
    if (r1 > 0 && std::fabs(dy) <= r1) {
      const double w = std::sqrt(r1 * r1 - dy * dy);
      clo = std::min(clo, a_[0] - w);
      chi = std::max(chi, a_[0] + w);
    }
    lo = std::max(lo, clo);
    hi = std::min(hi, chi);
  }
  if (lo > hi) return false;
  x0 = lo;
  x1 = hi;
  return true;
}

// ---- hand-off between chained moves -------------------------------------------
//
// Move k (a -> b: direction e, slope m, XY length L) followed by move n (b -> b':
// e', m', L') swept with start_cut, both with the same tool. Over a cell p the tool's
// lower surface at travel s is a convex f(s) = z(s) + g(d(s)) (g the profile), the
// tool at b gives T_b(p) = f_k(L) = f_n(0), and a cell ends at the minimum of its
// height and of the row kernels' heights H of every move that evaluates it (the
// order does not matter). So k may leave p out when n evaluates p and H_n(p) <=
// H_k(p). That holds, with a margin, where (par = (p - b).e, par' = (p - b).e',
// perp across e, d = |p - b|, rho = sqrt(R^2 - perp^2), K = m / sqrt(1 + m^2),
// r1 = R - r_c / 2):
//  (i)  k cannot lower p below T_b, so min f_k = T_b (start_cut's rule with the
//       move reversed). Ball: the unclamped contact of row_heights, L + par - K rho,
//       is past the end: par >= K rho (exact; an ellipse about b cut from or added
//       to par >= 0). Bull (g'(d) / d >= 1/(sqrt 3 r1) at d >= r1): f_k'(L) = m -
//       g'(d) par / d <= 0 where par >= 0, rising also par >= sqrt(3) r1 m and d >=
//       r1. Flat: par >= 0, level or descending only.
//  (ii) n lowers p below T_b by at least G: convexity gives T_b - min f_n >=
//       f_n(0) - f_n(sg) >= integral of -f_n' over [0, sg], sg = mu / 2 <= L'.
//       Ball: f_n'' >= 1/R and f_n' = 0 at n's contact par' - K' rho', so where that
//       is >= mu, G >= 3 mu^2 / (8 R). Bull: with par' >= max(m', 0) sqrt(3) r1 + mu
//       outside the disc of radius r1 + mu about b, -f_n' >= mu / (2 sqrt(3) r1)
//       on [0, sg], G >= mu^2 / (4 sqrt(3) r1); a steep enough descent has -f_n' >=
//       |m'| >= that without the disc. Flat, descending at least mu / (2 R): G >=
//       |m'| mu / 2 where par' >= mu (a level or rising flat end does not lower its
//       footprint: nothing is left to it).
//  (iii) p is in n's row_range with start_cut (so n evaluates it).
// The row kernels are exact up to ~1e-13 mm, up to ~6e-8 R on the rim of a
// footprint (the square root of a rounded ~0); with mu = max(0.02, R / 200) mm,
// G >= 9e-6 R (ball), 3.6e-6 R (bull) is more than 50 times both errors, so H_n <=
// T_b - G + err <= H_k, and rounding to float keeps the order. The regions are
// made smaller than derived by 1e-6 mm (and 1e-9 relative), far more than the
// rounding of their bounds. Slopes above 1000 are left alone (the ball's contact is
// then at its equator, where the kernel's error grows); above 10, and below 1e-3,
// the ball's ellipses give way to half-planes inside the regions (K rho <= K R). A
// cell n leaves out in turn is left to n + 1, lower still; the last move of a
// sweep_lines call leaves out nothing.

namespace {

// (p - b).e - K sqrt(R^2 - perp^2) >= c on the cells of a row: a half-plane for K
// = 0, that minus an ellipse about par = c for K > 0, plus one for K < 0.
struct Cond {
  double ex = 1, ey = 0, c = 0, K = 0, R = 0;
  // Per-row constants (prepare()).
  double inv_ex = 0, K2 = 0, A = 0, inv_2a = 0;
  void prepare() {
    inv_ex = std::fabs(ex) < 1e-12 ? 0 : 1 / ex;
    K2 = K * K;
    A = ex * ex + K2 * ey * ey;
    inv_2a = K == 0 ? 0 : 0.5 / A;
  }
};

struct Handoff {
  double bx = 0, by = 0;  // b
  Cond own, next;         // (i), (ii)
  double r_out = 0;       // and |p - b| >= r_out (0: no disc)
};

constexpr double tiny_mm = 1e-6;

// The ball's condition "the contact of row_heights is at least c past b":
// (p - b).e - K rho >= c, shrunk by tiny_mm; a half-plane inside it when K is small
// (ill-conditioned ellipse) or the move steep.
Cond ball_cond(const LineSweep& l, double c, double R) {
  const double m = l.slope(), K = m / std::sqrt(1 + m * m);
  Cond q{l.dir_x(), l.dir_y(), c + tiny_mm, 0, 0};
  if (std::fabs(K) < 1e-3 || std::fabs(m) > 10) {
    if (K > 0) q.c += K * R;  // K rho <= K R
  } else {
    q.K = K;
    q.R = K > 0 ? R * (1 + 1e-9) + tiny_mm : R * (1 - 1e-9) - tiny_mm;
  }
  return q;
}

bool same_tool(const ToolProfile& t, const ToolProfile& u) {
  return t.kind == u.kind && t.radius_mm == u.radius_mm && t.corner_radius_mm == u.corner_radius_mm;
}

double margin_mm(const ToolProfile& t) { return std::max(0.02, t.radius_mm / 200); }

bool make_handoff(const LineSweep& k, const LineSweep& n, Handoff& h) {
  const ToolProfile& t = k.tool();
  if (!same_tool(t, n.tool()) || n.a() != k.b() || k.xy_length() == 0) return false;
  const double R = t.radius_mm, m = k.slope(), mn = n.slope(), mu = margin_mm(t);
  if (n.xy_length() < mu / 2 || std::fabs(m) > 1000 || std::fabs(mn) > 1000) return false;
  h.bx = k.b()[0];
  h.by = k.b()[1];
  h.own = {k.dir_x(), k.dir_y(), tiny_mm};
  h.next = {n.dir_x(), n.dir_y(), mu};
  h.r_out = 0;
  const double r1 = R - 0.5 * corner_of(t), s3 = std::sqrt(3.0);
  switch (t.kind) {
    case ToolKind::ball:
      h.own = ball_cond(k, 0, R);
      h.next = ball_cond(n, mu, R);
      break;
    case ToolKind::bull:
      if (m > 0) {
        h.own.c += s3 * r1 * m;
        h.r_out = r1 * (1 + 1e-9) + tiny_mm;
      }
      h.next.c += std::max(mn, 0.0) * s3 * r1;
      if (!(-mn >= mu / (2 * s3 * r1))) h.r_out = std::max(h.r_out, r1 + mu);
      break;
    case ToolKind::flat:
      if (m > 0 || !(-mn >= mu / (2 * R))) return false;
      break;
  }
  h.own.prepare();
  h.next.prepare();
  return true;
}

// The cells of row y (wy = y - b_y) meeting a condition: up to two intervals.
int cond_row(const Cond& q, double bx, double wy, double* l, double* r) {
  // par = (x - bx) ex + wy ey >= c: x >= h or x <= h.
  double hl = -inf, hr = inf;
  const double rest = q.c - wy * q.ey;
  if (q.inv_ex == 0) {
    if (rest > 0) hl = inf;
  } else if (q.ex > 0) {
    hl = bx + rest * q.inv_ex;
  } else {
    hr = bx + rest * q.inv_ex;
  }
  int cnt = 0;
  auto add = [&](double a, double b) {
    if (a <= b) {
      l[cnt] = a;
      r[cnt++] = b;
    }
  };
  if (q.K == 0) {
    add(hl, hr);
    return cnt;
  }
  // Ellipse (par - c)^2 + K^2 perp^2 <= K^2 R^2 with perp = (x - bx) ey - wy ex:
  // A u^2 + B u + C <= 0, u = x - bx.
  const double p0 = wy * q.ey - q.c, q0 = -wy * q.ex;
  const double B = 2 * (q.ex * p0 + q.K2 * q.ey * q0), C = p0 * p0 + q.K2 * (q0 * q0 - q.R * q.R);
  const double D = B * B - 4 * q.A * C;
  if (!(D > 0)) {
    add(hl, hr);
    return cnt;
  }
  const double sd = std::sqrt(D), e0 = bx + (-B - sd) * q.inv_2a, e1 = bx + (-B + sd) * q.inv_2a;
  if (q.K > 0) {  // half-line minus the open chord
    add(hl, std::min(hr, e0));
    add(std::max(hl, e1), hr);
  } else {  // half-line plus the chord
    if (e1 < hl || e0 > hr) {
      add(hl, hr);
      add(e0, e1);
    } else {
      add(std::min(hl, e0), std::max(hr, e1));
    }
  }
  return cnt;
}

// Narrows [x0, x1] (cells both moves evaluate on row y) to one interval of cells
// move k may leave out (the longest where the conditions split it), given the
// pieces of h.own (no of them) and of h.next (nn) on the row; a piece with l > r
// is none.
bool handoff_pieces(const Handoff& h, double wy, double& x0, double& x1, double min_len, int no, double* ol,
                    double* orr, int nn, const double* nl, const double* nr) {
  int kept = 0;
  for (int i = 0; i < no; ++i)  // the cheap test first: pieces of the window as long as asked
    if (std::min(x1, orr[i]) - std::max(x0, ol[i]) >= min_len) {
      ol[kept] = ol[i];
      orr[kept++] = orr[i];
    }
  if ((no = kept) == 0) return false;
  double dl = inf, dr = -inf;  // the disc's chord, left out
  if (h.r_out > 0 && std::fabs(wy) < h.r_out) {
    const double w = std::sqrt(h.r_out * h.r_out - wy * wy);
    dl = h.bx - w;
    dr = h.bx + w;
  }
  double bl = 0, br = -1;
  auto take = [&](double l, double r) {
    if (l <= r && (br < bl || r - l > br - bl)) {
      bl = l;
      br = r;
    }
  };
  for (int i = 0; i < no; ++i)
    for (int k = 0; k < nn; ++k) {
      const double l = std::max({x0, ol[i], nl[k]}), r = std::min({x1, orr[i], nr[k]});
      if (dl < dr) {
        take(l, std::min(r, dl));
        take(std::max(l, dr), r);
      } else {
        take(l, r);
      }
    }
  if (br < bl) return false;
  x0 = bl;
  x1 = br;
  return true;
}

bool handoff_row(const Handoff& h, double y, double& x0, double& x1, double min_len = 0) {
  const double wy = y - h.by;
  double ol[2], orr[2], nl[2], nr[2];
  const int no = cond_row(h.own, h.bx, wy, ol, orr);
  bool any = false;  // (as before: next's pieces only when some of own's is long enough)
  for (int i = 0; i < no; ++i) any |= std::min(x1, orr[i]) - std::max(x0, ol[i]) >= min_len;
  if (!any) return false;
  const int nn = cond_row(h.next, h.bx, wy, nl, nr);
  return handoff_pieces(h, wy, x0, x1, min_len, no, ol, orr, nn, nl, nr);
}

// cond_row on rows wy[0, n) into two fixed slots per row (l0, r0), (l1, r1), in
// cond_row's order, an absent piece as (inf, -inf); four rows at a time with AVX2,
// the same operations, so the same doubles.
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) int cond_rows_avx2(const Cond& q, double bx, const double* wys, int n, double* L0,
                                                   double* R0, double* L1, double* R1) {
  const __m256d vinf = _mm256_set1_pd(inf), vninf = _mm256_set1_pd(-inf), zero = _mm256_setzero_pd();
  const __m256d vbx = _mm256_set1_pd(bx), vc = _mm256_set1_pd(q.c), vey = _mm256_set1_pd(q.ey),
                vex = _mm256_set1_pd(q.ex), vinv = _mm256_set1_pd(q.inv_ex), sign = _mm256_set1_pd(-0.0);
  const __m256d two = _mm256_set1_pd(2.0), K2 = _mm256_set1_pd(q.K2), K2ey = _mm256_set1_pd(q.K2 * q.ey),
                RR = _mm256_set1_pd(q.R * q.R), A4 = _mm256_set1_pd(4 * q.A), inv2a = _mm256_set1_pd(q.inv_2a);
  int k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256d wy = _mm256_loadu_pd(wys + k);
    const __m256d rest = _mm256_sub_pd(vc, _mm256_mul_pd(wy, vey));
    __m256d hl = vninf, hr = vinf;
    if (q.inv_ex == 0) {
      hl = _mm256_blendv_pd(vninf, vinf, _mm256_cmp_pd(rest, zero, _CMP_GT_OQ));
    } else if (q.ex > 0) {
      hl = _mm256_add_pd(vbx, _mm256_mul_pd(rest, vinv));
    } else {
      hr = _mm256_add_pd(vbx, _mm256_mul_pd(rest, vinv));
    }
    __m256d l0 = hl, r0 = hr, l1 = vinf, r1 = vninf;
    if (q.K != 0) {
      const __m256d p0 = _mm256_sub_pd(_mm256_mul_pd(wy, vey), vc);
      const __m256d q0 = _mm256_mul_pd(_mm256_xor_pd(wy, sign), vex);
      const __m256d B = _mm256_mul_pd(two, _mm256_add_pd(_mm256_mul_pd(vex, p0), _mm256_mul_pd(K2ey, q0)));
      const __m256d C =
          _mm256_add_pd(_mm256_mul_pd(p0, p0), _mm256_mul_pd(K2, _mm256_sub_pd(_mm256_mul_pd(q0, q0), RR)));
      const __m256d D = _mm256_sub_pd(_mm256_mul_pd(B, B), _mm256_mul_pd(A4, C));
      const __m256d pos = _mm256_cmp_pd(D, zero, _CMP_GT_OQ);
      const __m256d sd = _mm256_sqrt_pd(D), nB = _mm256_xor_pd(B, sign);
      const __m256d e0 = _mm256_add_pd(vbx, _mm256_mul_pd(_mm256_sub_pd(nB, sd), inv2a));
      const __m256d e1 = _mm256_add_pd(vbx, _mm256_mul_pd(_mm256_add_pd(nB, sd), inv2a));
      __m256d nl0, nr0, nl1, nr1;
      if (q.K > 0) {
        nl0 = hl;
        nr0 = _mm256_min_pd(e0, hr);
        nl1 = _mm256_max_pd(e1, hl);
        nr1 = hr;
      } else {
        const __m256d sep = _mm256_or_pd(_mm256_cmp_pd(e1, hl, _CMP_LT_OQ), _mm256_cmp_pd(e0, hr, _CMP_GT_OQ));
        nl0 = _mm256_blendv_pd(_mm256_min_pd(e0, hl), hl, sep);
        nr0 = _mm256_blendv_pd(_mm256_max_pd(e1, hr), hr, sep);
        nl1 = _mm256_blendv_pd(vinf, e0, sep);
        nr1 = _mm256_blendv_pd(vninf, e1, sep);
      }
      l0 = _mm256_blendv_pd(l0, nl0, pos);
      r0 = _mm256_blendv_pd(r0, nr0, pos);
      l1 = _mm256_blendv_pd(l1, nl1, pos);
      r1 = _mm256_blendv_pd(r1, nr1, pos);
    }
    _mm256_storeu_pd(L0 + k, l0);
    _mm256_storeu_pd(R0 + k, r0);
    _mm256_storeu_pd(L1 + k, l1);
    _mm256_storeu_pd(R1 + k, r1);
  }
  return k;
}
#endif

bool cpu_avx2() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return has;
#else
  return false;
#endif
}

void cond_rows(const Cond& q, double bx, const double* wy, int n, double* L0, double* R0, double* L1, double* R1) {
  int k = 0;
#if defined(__x86_64__) && defined(__GNUC__)
  if (cpu_avx2()) k = cond_rows_avx2(q, bx, wy, n, L0, R0, L1, R1);
#endif
  for (; k < n; ++k) {
    double l[2], r[2];
    const int c = cond_row(q, bx, wy[k], l, r);
    L0[k] = c > 0 ? l[0] : inf;
    R0[k] = c > 0 ? r[0] : -inf;
    L1[k] = c > 1 ? l[1] : inf;
    R1[k] = c > 1 ? r[1] : -inf;
  }
}

}  // namespace

bool LineSweep::end_handoff(const LineSweep& next, double y, double& x0, double& x1) const {
  Handoff h;
  double na, nb;
  if (!make_handoff(*this, next, h) || !next.row_range(y, na, nb, true)) return false;
  x0 = std::max(x0, na);
  x1 = std::min(x1, nb);
  return handoff_row(h, y, x0, x1);
}

// ---- row kernels --------------------------------------------------------------
//
// Per cell centre x on a row y (wx = x - a_x, wy = y - a_y):
//   par = wx ex + wy ey, cr = wx ey - wy ex (signed perp), rho^2 = R^2 - cr^2.
// Ball: the contact is at s = clamp(par - k rho, 0, L), k = m / sqrt(1 + m^2)
// (the clamp to [par - rho, par + rho] of lower_height is implied by |k| < 1),
// height a_z + R + m s - sqrt(rho^2 - (s - par)^2).
// Flat: a_z + m s with s = max(0, par - rho) rising, min(L, par + rho) falling.
// +inf where the footprint misses (cr^2 > R^2 or |s - par| > rho).
// The AVX2 paths do the same operations in the same order (no FMA), so every
// lane equals the scalar result bit for bit.

namespace {

struct RowConsts {
  double gx0, cell, ax, ex, ey, wyey, wyex, R2, L, m, k, az, azR;
};

inline float ball_cell(const RowConsts& c, int i) {
  const double x = c.gx0 + (static_cast<double>(i) + 0.5) * c.cell;
  const double wx = x - c.ax;
  const double par = wx * c.ex + c.wyey;
  const double cr = wx * c.ey - c.wyex;
  const double cr2 = cr * cr;
  const double rho2 = c.R2 - cr2;
  const double rho = std::sqrt(std::max(rho2, 0.0));
  const double s = std::min(std::max(par - c.k * rho, 0.0), c.L);
  const double q = s - par;
  const double t = rho2 - q * q;
  const double h = c.azR + c.m * s - std::sqrt(std::max(t, 0.0));
  return (cr2 > c.R2 || t < 0) ? std::numeric_limits<float>::infinity() : static_cast<float>(h);
}

template <bool Rising>
inline float flat_cell(const RowConsts& c, int i) {
  const double x = c.gx0 + (static_cast<double>(i) + 0.5) * c.cell;
  const double wx = x - c.ax;
  const double par = wx * c.ex + c.wyey;
  const double cr = wx * c.ey - c.wyex;
  const double cr2 = cr * cr;
  const double rho = std::sqrt(std::max(c.R2 - cr2, 0.0));
  const double lo = par - rho, hi = par + rho;
  const double s = Rising ? std::max(lo, 0.0) : std::min(hi, c.L);
  const double h = c.az + c.m * s;
  return (cr2 > c.R2 || lo > c.L || hi < 0) ? std::numeric_limits<float>::infinity() : static_cast<float>(h);
}

#if defined(__x86_64__) && defined(__GNUC__)
#define DEFLEX_SWEEP_AVX2 1

// Four lanes to out[0, cnt), cnt <= 4.
__attribute__((target("avx2"), always_inline)) inline void store_lanes(float* out, __m128 v, int cnt) {
  if (cnt == 4) {
    _mm_storeu_ps(out, v);
    return;
  }
  // Masked: the floats past cnt are not touched (no copy through memory).
  const __m128i mask = _mm_cmpgt_epi32(_mm_set1_epi32(cnt), _mm_setr_epi32(0, 1, 2, 3));
  _mm_maskstore_ps(out, mask, v);
}

// Cells [i0, i0 + n) in blocks of 4, the last one partly (n >= 4; fewer are left
// to the scalar path); returns how many were done. Short pieces of rows (the
// hand-off splits them) would otherwise spend more on the scalar tail than here.
__attribute__((target("avx2"))) int ball_row_avx2(const RowConsts& c, int i0, int n, float* out) {
  const __m256d gx0 = _mm256_set1_pd(c.gx0), cell = _mm256_set1_pd(c.cell), half = _mm256_set1_pd(0.5);
  const __m256d ax = _mm256_set1_pd(c.ax), ex = _mm256_set1_pd(c.ex), ey = _mm256_set1_pd(c.ey);
  const __m256d wyey = _mm256_set1_pd(c.wyey), wyex = _mm256_set1_pd(c.wyex), R2 = _mm256_set1_pd(c.R2);
  const __m256d L = _mm256_set1_pd(c.L), m = _mm256_set1_pd(c.m), k = _mm256_set1_pd(c.k);
  const __m256d azR = _mm256_set1_pd(c.azR), zero = _mm256_setzero_pd();
  const __m256d dinf = _mm256_set1_pd(inf);
  __m256d idx = _mm256_setr_pd(i0, i0 + 1.0, i0 + 2.0, i0 + 3.0);
  const __m256d four = _mm256_set1_pd(4.0);
  int done = 0;
  for (const int stop = n >= 4 ? n : 0; done < stop; done += 4, idx = _mm256_add_pd(idx, four)) {
    const __m256d x = _mm256_add_pd(gx0, _mm256_mul_pd(_mm256_add_pd(idx, half), cell));
    const __m256d wx = _mm256_sub_pd(x, ax);
    const __m256d par = _mm256_add_pd(_mm256_mul_pd(wx, ex), wyey);
    const __m256d cr = _mm256_sub_pd(_mm256_mul_pd(wx, ey), wyex);
    const __m256d cr2 = _mm256_mul_pd(cr, cr);
    const __m256d rho2 = _mm256_sub_pd(R2, cr2);
    const __m256d rho = _mm256_sqrt_pd(_mm256_max_pd(rho2, zero));
    const __m256d s = _mm256_min_pd(_mm256_max_pd(_mm256_sub_pd(par, _mm256_mul_pd(k, rho)), zero), L);
    const __m256d q = _mm256_sub_pd(s, par);
    const __m256d t = _mm256_sub_pd(rho2, _mm256_mul_pd(q, q));
    const __m256d h = _mm256_sub_pd(_mm256_add_pd(azR, _mm256_mul_pd(m, s)), _mm256_sqrt_pd(_mm256_max_pd(t, zero)));
    const __m256d miss = _mm256_or_pd(_mm256_cmp_pd(cr2, R2, _CMP_GT_OQ), _mm256_cmp_pd(t, zero, _CMP_LT_OQ));
    store_lanes(out + done, _mm256_cvtpd_ps(_mm256_blendv_pd(h, dinf, miss)), std::min(4, n - done));
  }
  return std::min(done, n);
}

template <bool Rising>
__attribute__((target("avx2"))) int flat_row_avx2(const RowConsts& c, int i0, int n, float* out) {
  const __m256d gx0 = _mm256_set1_pd(c.gx0), cell = _mm256_set1_pd(c.cell), half = _mm256_set1_pd(0.5);
  const __m256d ax = _mm256_set1_pd(c.ax), ex = _mm256_set1_pd(c.ex), ey = _mm256_set1_pd(c.ey);
  const __m256d wyey = _mm256_set1_pd(c.wyey), wyex = _mm256_set1_pd(c.wyex), R2 = _mm256_set1_pd(c.R2);
  const __m256d L = _mm256_set1_pd(c.L), m = _mm256_set1_pd(c.m), az = _mm256_set1_pd(c.az);
  const __m256d zero = _mm256_setzero_pd();
  const __m256d dinf = _mm256_set1_pd(inf);
  __m256d idx = _mm256_setr_pd(i0, i0 + 1.0, i0 + 2.0, i0 + 3.0);
  const __m256d four = _mm256_set1_pd(4.0);
  int done = 0;
  for (const int stop = n >= 4 ? n : 0; done < stop; done += 4, idx = _mm256_add_pd(idx, four)) {
    const __m256d x = _mm256_add_pd(gx0, _mm256_mul_pd(_mm256_add_pd(idx, half), cell));
    const __m256d wx = _mm256_sub_pd(x, ax);
    const __m256d par = _mm256_add_pd(_mm256_mul_pd(wx, ex), wyey);
    const __m256d cr = _mm256_sub_pd(_mm256_mul_pd(wx, ey), wyex);
    const __m256d cr2 = _mm256_mul_pd(cr, cr);
    const __m256d rho = _mm256_sqrt_pd(_mm256_max_pd(_mm256_sub_pd(R2, cr2), zero));
    const __m256d lo = _mm256_sub_pd(par, rho), hi = _mm256_add_pd(par, rho);
    const __m256d s = Rising ? _mm256_max_pd(lo, zero) : _mm256_min_pd(hi, L);
    const __m256d h = _mm256_add_pd(az, _mm256_mul_pd(m, s));
    const __m256d miss = _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(cr2, R2, _CMP_GT_OQ), _mm256_cmp_pd(lo, L, _CMP_GT_OQ)),
                                      _mm256_cmp_pd(hi, zero, _CMP_LT_OQ));
    store_lanes(out + done, _mm256_cvtpd_ps(_mm256_blendv_pd(h, dinf, miss)), std::min(4, n - done));
  }
  return std::min(done, n);
}

// Bull nose, 4 cells at a time: the cells whose minimum lies at an end of the
// feasible interval (f'(lo) >= 0 or f'(hi) <= 0: with short moves, nearly all of
// them) and every cell of a horizontal move are evaluated here with the
// operations of lower_height; the others are left to lower_height (Newton).
struct BullV {
  __m256d Rv, rf, rcv, rc2, m, az, zero, dinf, ninf;
  bool level;
};

// f'(s) of lower_height.
__attribute__((target("avx2"), always_inline)) inline __m256d bull_deriv(const BullV& c, __m256d s, __m256d par,
                                                                          __m256d pp) {
  const __m256d q = _mm256_sub_pd(s, par);
  const __m256d d = _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(q, q), pp));
  const __m256d e = _mm256_sub_pd(d, c.rf);
  const __m256d w = _mm256_sub_pd(c.rc2, _mm256_mul_pd(e, e));
  const __m256d g1 = _mm256_div_pd(e, _mm256_sqrt_pd(w));
  __m256d f = _mm256_add_pd(c.m, _mm256_div_pd(_mm256_mul_pd(g1, q), d));
  const __m256d bad = _mm256_cmp_pd(w, c.zero, _CMP_NGT_UQ);  // !(w > 0)
  const __m256d edge = _mm256_blendv_pd(_mm256_blendv_pd(c.m, c.ninf, _mm256_cmp_pd(q, c.zero, _CMP_LT_OQ)), c.dinf,
                                        _mm256_cmp_pd(q, c.zero, _CMP_GT_OQ));
  f = _mm256_blendv_pd(f, edge, bad);
  const __m256d flat = _mm256_or_pd(_mm256_cmp_pd(e, c.zero, _CMP_LE_OQ), _mm256_cmp_pd(d, c.zero, _CMP_EQ_OQ));
  return _mm256_blendv_pd(f, c.m, flat);
}

// a_z + m s + profile_height(min(R, d)) (level: no min, beyond R is +inf).
__attribute__((target("avx2"), always_inline)) inline __m256d bull_height(const BullV& c, __m256d s, __m256d par,
                                                                           __m256d pp) {
  const __m256d q = c.level ? _mm256_sub_pd(par, s) : _mm256_sub_pd(s, par);
  __m256d d = _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(q, q), pp));
  const __m256d beyond = _mm256_cmp_pd(d, c.Rv, _CMP_GT_OQ);
  if (!c.level) d = _mm256_min_pd(c.Rv, d);
  const __m256d e = _mm256_sub_pd(d, c.rf);
  const __m256d ph = _mm256_blendv_pd(
      _mm256_sub_pd(c.rcv, _mm256_sqrt_pd(_mm256_max_pd(_mm256_sub_pd(c.rc2, _mm256_mul_pd(e, e)), c.zero))), c.zero,
      _mm256_cmp_pd(e, c.zero, _CMP_LE_OQ));
  const __m256d h = _mm256_add_pd(_mm256_add_pd(c.az, _mm256_mul_pd(c.m, s)), ph);
  return c.level ? _mm256_blendv_pd(h, c.dinf, beyond) : h;
}

__attribute__((target("avx2"))) void bull_row_avx2(const LineSweep& sw, double y, double gx0, double cell, int i0, int n,
                                                   float* out) {
  const ToolProfile& t = sw.tool();
  const double R = t.radius_mm, rc = t.corner_radius_mm;
  const BullV c{_mm256_set1_pd(R),         _mm256_set1_pd(R - rc),      _mm256_set1_pd(rc),
                _mm256_set1_pd(rc * rc),   _mm256_set1_pd(sw.slope()),  _mm256_set1_pd(sw.a()[2]),
                _mm256_setzero_pd(),       _mm256_set1_pd(inf),         _mm256_set1_pd(-inf),
                sw.slope() == 0};
  const __m256d gx = _mm256_set1_pd(gx0), cl = _mm256_set1_pd(cell), half = _mm256_set1_pd(0.5);
  const __m256d ax = _mm256_set1_pd(sw.a()[0]), ex = _mm256_set1_pd(sw.dir_x()), ey = _mm256_set1_pd(sw.dir_y());
  const double wy = y - sw.a()[1];
  const __m256d wyey = _mm256_set1_pd(wy * sw.dir_y()), wyex = _mm256_set1_pd(wy * sw.dir_x());
  const __m256d R2 = _mm256_set1_pd(R * R), L = _mm256_set1_pd(sw.xy_length());
  const __m256d xmin = _mm256_set1_pd(sw.x_min()), xmax = _mm256_set1_pd(sw.x_max());
  const __m256d sign = _mm256_set1_pd(-0.0), ones = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  __m256d idx = _mm256_setr_pd(i0, i0 + 1.0, i0 + 2.0, i0 + 3.0);
  const __m256d four = _mm256_set1_pd(4.0);
  int k = 0;
  for (; k + 4 <= n; k += 4, idx = _mm256_add_pd(idx, four)) {
    const __m256d x = _mm256_add_pd(gx, _mm256_mul_pd(_mm256_add_pd(idx, half), cl));
    const __m256d wx = _mm256_sub_pd(x, ax);
    const __m256d par = _mm256_add_pd(_mm256_mul_pd(wx, ex), wyey);
    const __m256d perp = _mm256_andnot_pd(sign, _mm256_sub_pd(_mm256_mul_pd(wx, ey), wyex));
    const __m256d pp = _mm256_mul_pd(perp, perp);
    const __m256d rho = _mm256_sqrt_pd(_mm256_sub_pd(R2, pp));
    const __m256d lo = _mm256_max_pd(_mm256_sub_pd(par, rho), c.zero), hi = _mm256_min_pd(_mm256_add_pd(par, rho), L);
    __m256d miss = _mm256_or_pd(_mm256_cmp_pd(x, xmin, _CMP_LT_OQ), _mm256_cmp_pd(x, xmax, _CMP_GT_OQ));
    miss = _mm256_or_pd(miss, _mm256_cmp_pd(perp, c.Rv, _CMP_GT_OQ));
    miss = _mm256_or_pd(miss, _mm256_cmp_pd(lo, hi, _CMP_GT_OQ));
    __m256d h, todo = c.zero;
    if (c.level) {
      h = bull_height(c, _mm256_min_pd(_mm256_max_pd(par, c.zero), L), par, pp);
    } else {
      const __m256d at_lo = _mm256_cmp_pd(bull_deriv(c, lo, par, pp), c.zero, _CMP_GE_OQ);
      const __m256d at_hi = _mm256_cmp_pd(bull_deriv(c, hi, par, pp), c.zero, _CMP_LE_OQ);
      todo = _mm256_andnot_pd(_mm256_or_pd(at_lo, at_hi), ones);
      h = bull_height(c, _mm256_blendv_pd(hi, lo, at_lo), par, pp);
    }
    h = _mm256_blendv_pd(h, c.dinf, miss);
    _mm_storeu_ps(out + k, _mm256_cvtpd_ps(h));
    const int rest = _mm256_movemask_pd(_mm256_andnot_pd(miss, todo));
    for (int l = 0; l < 4; ++l)
      if (rest >> l & 1) {
        const double v = sw.lower_height(gx0 + (static_cast<double>(i0 + k + l) + 0.5) * cell, y);
        out[k + l] = v == inf ? std::numeric_limits<float>::infinity() : static_cast<float>(v);
      }
  }
  for (; k < n; ++k) {
    const double v = sw.lower_height(gx0 + (static_cast<double>(i0 + k) + 0.5) * cell, y);
    out[k] = v == inf ? std::numeric_limits<float>::infinity() : static_cast<float>(v);
  }
}

bool cpu_has_avx2() {
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return has;
}
#endif

}  // namespace

#ifdef DEFLEX_SWEEP_AVX2
namespace {

// row_range's disc and clip lambdas, four rows at a time.
__attribute__((target("avx2"), always_inline)) inline void rr_disc(__m256d y, __m256d c0, __m256d c1, __m256d Rv,
                                                                  __m256d R2, __m256d sign, __m256d& lo, __m256d& hi) {
  const __m256d dy = _mm256_sub_pd(y, c1);
  const __m256d in = _mm256_cmp_pd(_mm256_andnot_pd(sign, dy), Rv, _CMP_NGT_UQ);  // !(|dy| > R)
  const __m256d w = _mm256_sqrt_pd(_mm256_sub_pd(R2, _mm256_mul_pd(dy, dy)));
  lo = _mm256_blendv_pd(lo, _mm256_min_pd(_mm256_sub_pd(c0, w), lo), in);
  hi = _mm256_blendv_pd(hi, _mm256_max_pd(_mm256_add_pd(c0, w), hi), in);
}

__attribute__((target("avx2"), always_inline)) inline void rr_clip(double coef, __m256d c0, __m256d vmin, __m256d vmax,
                                                                  __m256d dinf, __m256d& bl, __m256d& bh) {
  if (std::fabs(coef) < 1e-15) {
    const __m256d out = _mm256_or_pd(_mm256_cmp_pd(c0, vmin, _CMP_LT_OQ), _mm256_cmp_pd(c0, vmax, _CMP_GT_OQ));
    bl = _mm256_blendv_pd(bl, dinf, out);
    return;
  }
  const __m256d cf = _mm256_set1_pd(coef);
  const __m256d p = _mm256_div_pd(_mm256_sub_pd(vmin, c0), cf), q = _mm256_div_pd(_mm256_sub_pd(vmax, c0), cf);
  const __m256d sw = _mm256_cmp_pd(p, q, _CMP_GT_OQ);
  bl = _mm256_max_pd(_mm256_blendv_pd(p, q, sw), bl);
  bh = _mm256_min_pd(_mm256_blendv_pd(q, p, sw), bh);
}

// LineSweep::row_range on rows y[0, n) four at a time, the same operations in the
// same order (IEEE division and square root, std::min / std::max as min_pd / max_pd
// with the same operand order, no FMA); returns how many rows were done.
__attribute__((target("avx2"))) int row_ranges_avx2(const LineSweep& s, const double* ys, int n, double* x0,
                                                    double* x1, unsigned char* ok, bool start_cut) {
  const double R = s.tool().radius_mm, len = s.xy_length(), ex = s.dir_x(), ey = s.dir_y(), slope = s.slope();
  const Point3 &a = s.a(), &b = s.b();
  const __m256d Rv = _mm256_set1_pd(R), R2 = _mm256_set1_pd(R * R), sign = _mm256_set1_pd(-0.0);
  const __m256d dinf = _mm256_set1_pd(inf), dninf = _mm256_set1_pd(-inf);
  const bool cut = start_cut && len > 0 && (slope >= 0 || s.tool().kind != ToolKind::flat);
  double back = 0, r1 = 0;
  if (cut && slope < 0) {
    const double rc = corner_of(s.tool());
    if (s.tool().kind == ToolKind::ball) {
      back = -slope * R;
    } else {
      r1 = R - 0.5 * rc;
      back = -slope * r1 * std::sqrt(3.0);
    }
    back *= 1 + 1e-9;
  }
  const __m256d ca0 = _mm256_set1_pd(a[0]), ca1 = _mm256_set1_pd(a[1]);
  const __m256d cb0 = _mm256_set1_pd(b[0]), cb1 = _mm256_set1_pd(b[1]);
  const __m256d vex = _mm256_set1_pd(ex), vey = _mm256_set1_pd(ey);
  const __m256d c1x = _mm256_set1_pd(-a[0] * ex), c2x = _mm256_set1_pd(-a[0] * ey);
  const __m256d vzero = _mm256_setzero_pd(), vlen = _mm256_set1_pd(len), vmR = _mm256_set1_pd(-R);
  const __m256d mback = _mm256_set1_pd(-back), vr1 = _mm256_set1_pd(r1), r1sq = _mm256_set1_pd(r1 * r1);
  int k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256d y = _mm256_loadu_pd(ys + k);
    __m256d lo = dinf, hi = dninf;
    rr_disc(y, ca0, ca1, Rv, R2, sign, lo, hi);
    rr_disc(y, cb0, cb1, Rv, R2, sign, lo, hi);
    const __m256d wy = _mm256_sub_pd(y, ca1);
    if (len > 0) {
      __m256d bl = dninf, bh = dinf;
      rr_clip(ex, _mm256_add_pd(c1x, _mm256_mul_pd(wy, vey)), vzero, vlen, dinf, bl, bh);
      rr_clip(ey, _mm256_sub_pd(c2x, _mm256_mul_pd(wy, vex)), vmR, Rv, dinf, bl, bh);
      const __m256d in = _mm256_cmp_pd(bl, bh, _CMP_LE_OQ);
      lo = _mm256_blendv_pd(lo, _mm256_min_pd(bl, lo), in);
      hi = _mm256_blendv_pd(hi, _mm256_max_pd(bh, hi), in);
    }
    if (cut) {
      __m256d clo = lo, chi = hi;
      const __m256d c = _mm256_add_pd(c1x, _mm256_mul_pd(wy, vey));
      if (std::fabs(ex) < 1e-15) {
        chi = _mm256_blendv_pd(chi, dninf, _mm256_cmp_pd(c, mback, _CMP_LT_OQ));
      } else if (ex > 0) {
        clo = _mm256_max_pd(_mm256_div_pd(_mm256_sub_pd(mback, c), vex), clo);
      } else {
        chi = _mm256_min_pd(_mm256_div_pd(_mm256_sub_pd(mback, c), vex), chi);
      }
      if (r1 > 0) {
        const __m256d in = _mm256_cmp_pd(_mm256_andnot_pd(sign, wy), vr1, _CMP_LE_OQ);
        const __m256d w = _mm256_sqrt_pd(_mm256_sub_pd(r1sq, _mm256_mul_pd(wy, wy)));
        clo = _mm256_blendv_pd(clo, _mm256_min_pd(_mm256_sub_pd(ca0, w), clo), in);
        chi = _mm256_blendv_pd(chi, _mm256_max_pd(_mm256_add_pd(ca0, w), chi), in);
      }
      lo = _mm256_max_pd(clo, lo);
      hi = _mm256_min_pd(chi, hi);
    }
    _mm256_storeu_pd(x0 + k, lo);
    _mm256_storeu_pd(x1 + k, hi);
    const int good = _mm256_movemask_pd(_mm256_cmp_pd(lo, hi, _CMP_NGT_UQ));  // !(lo > hi)
    for (int l = 0; l < 4; ++l) ok[k + l] = static_cast<unsigned char>(good >> l & 1);
  }
  return k;
}

}  // namespace
#endif

void LineSweep::row_ranges(const double* y, int n, double* x0, double* x1, unsigned char* ok, bool start_cut) const {
  if (start_cut && len_ == 0 && b_[2] >= a_[2]) {  // a retract removes nothing new
    std::fill(ok, ok + std::max(n, 0), 0);
    return;
  }
  int k = 0;
#ifdef DEFLEX_SWEEP_AVX2
  if (cpu_has_avx2()) k = row_ranges_avx2(*this, y, n, x0, x1, ok, start_cut);
#endif
  for (; k < n; ++k) ok[k] = row_range(y[k], x0[k], x1[k], start_cut);
}

void LineSweep::row_heights(double y, double gx0, double cell, int i0, int n, float* out) const {
  if (n <= 0) return;
#ifdef DEFLEX_SWEEP_AVX2
  if (len_ > 0 && tool_.kind == ToolKind::bull && cpu_has_avx2() && y >= ymin_ && y <= ymax_) {
    bull_row_avx2(*this, y, gx0, cell, i0, n, out);
    return;
  }
#endif
  const bool vec = len_ > 0 && (tool_.kind == ToolKind::ball || tool_.kind == ToolKind::flat);
  if (!vec) {  // plunges and bull noses: per cell
    for (int k = 0; k < n; ++k) {
      const double h = lower_height(gx0 + (static_cast<double>(i0 + k) + 0.5) * cell, y);
      out[k] = h == inf ? std::numeric_limits<float>::infinity() : static_cast<float>(h);
    }
    return;
  }
  const double wy = y - a_[1], R = tool_.radius_mm;
  const RowConsts c{gx0, cell, a_[0], ex_, ey_, wy * ey_, wy * ex_, R * R, len_, slope_, ball_k_, a_[2], a_[2] + R};
  int done = 0;
  if (tool_.kind == ToolKind::ball) {
#ifdef DEFLEX_SWEEP_AVX2
    if (cpu_has_avx2()) done = ball_row_avx2(c, i0, n, out);
#endif
    for (int k = done; k < n; ++k) out[k] = ball_cell(c, i0 + k);
  } else if (slope_ >= 0) {
#ifdef DEFLEX_SWEEP_AVX2
    if (cpu_has_avx2()) done = flat_row_avx2<true>(c, i0, n, out);
#endif
    for (int k = done; k < n; ++k) out[k] = flat_cell<true>(c, i0 + k);
  } else {
#ifdef DEFLEX_SWEEP_AVX2
    if (cpu_has_avx2()) done = flat_row_avx2<false>(c, i0, n, out);
#endif
    for (int k = done; k < n; ++k) out[k] = flat_cell<false>(c, i0 + k);
  }
}

namespace {

// A move's cells (row_range with start_cut) on the rows of one band, found while
// sweeping the move before it, which needs them for the hand-off.
struct RowCache {
  static constexpr int rows = ZMap::tile_cells;
  int j0 = 0;
  bool known[rows];
  int lo[rows], hi[rows];  // cells [lo, hi]; none if hi < lo
  void reset(int band_j0) {
    j0 = band_j0;
    std::fill(known, known + rows, false);
  }
};

// Rows [j0, j1] (within one band when a cache is given) of one sweep; with a
// hand-off, the cells `next` (swept right after it on the same rows) lowers further
// are left out. mine: this move's cells if known; theirs: next's, filled here.
double sweep_rows(ZMap& z, const LineSweep& s, int j0, int j1, bool start_cut, const LineSweep* next = nullptr,
                  const Handoff* h = nullptr, const RowCache* mine = nullptr, RowCache* theirs = nullptr) {
  const GridSpec& g = z.grid();
  // Cells whose centre lies in [xa, xb]: [first(xa), last(xb)].
  auto first = [&](double xa) { return std::max(0, static_cast<int>(std::ceil((xa - g.x0_mm) / g.cell_mm - 0.5))); };
  auto last = [&](double xb) {
    return std::min(g.nx - 1, static_cast<int>(std::floor((xb - g.x0_mm) / g.cell_mm - 0.5)));
  };
  // The same for the left-out cells, inside [lo, hi]: by a multiplication (the
  // regions have margins far above its rounding).
  const double inv_cell = 1 / g.cell_mm;
  auto inner = [&](double xa, double xb, int lo, int hi, int& c0, int& c1) {
    const double t0 = std::clamp((xa - g.x0_mm) * inv_cell - 0.5, lo - 1.0, hi + 1.0);
    const double t1 = std::clamp((xb - g.x0_mm) * inv_cell - 0.5, lo - 1.0, hi + 1.0);
    const int k0 = static_cast<int>(t0), k1 = static_cast<int>(t1);  // toward zero: ceil and floor below
    c0 = std::max(lo, k0 + (k0 < t0));
    c1 = std::min(hi, k1 - (k1 > t1));
  };
  // next's rows (sweep_rows of next clips to these).
  const int nj0 = next ? z.iy(next->y_min()) : 0, nj1 = next ? z.iy(next->y_max()) : -1;
  j0 = std::max({j0, 0, z.iy(s.y_min())});
  j1 = std::min({j1, g.ny - 1, z.iy(s.y_max())});
  // Row heights: on the stack for rows of up to 1024 cells (D 51 mm at 0.05 mm).
  constexpr int stack_cells = 1024;
  float stack_buf[stack_cells];
  thread_local std::vector<float> heap_buf;
  double removed = 0;
  // Rows in chunks: the row ranges of this move (unless known) and of next come
  // from row_ranges, several rows per step.
  constexpr int chunk = ZMap::tile_cells;
  double ys[chunk], sa[chunk], sb[chunk], ra[chunk], rb[chunk];
  unsigned char sok[chunk], rok[chunk];
  int nlo[chunk], nhi[chunk];
  // The hand-off conditions' pieces per row (cond_rows): own's, then next's.
  double wys[chunk], ol0[chunk], or0[chunk], ol1[chunk], or1[chunk], pl0[chunk], pr0[chunk], pl1[chunk], pr1[chunk];
  for (int jc = j0; jc <= j1; jc += chunk) {
   const int jn = std::min(j1 - jc + 1, chunk);
   for (int r = 0; r < jn; ++r) ys[r] = z.cy(jc + r);
   if (!mine) s.row_ranges(ys, jn, sa, sb, sok, start_cut);
   // next's rows in this chunk: [q0, q1)
   const int q0 = h ? std::clamp(nj0 - jc, 0, jn) : 0, q1 = h ? std::clamp(nj1 - jc + 1, 0, jn) : 0;
   if (q1 > q0) {
     next->row_ranges(ys + q0, q1 - q0, ra + q0, rb + q0, rok + q0, true);
     for (int r = q0; r < q1; ++r) wys[r] = ys[r] - h->by;
     cond_rows(h->own, h->bx, wys + q0, q1 - q0, ol0 + q0, or0 + q0, ol1 + q0, or1 + q0);
     cond_rows(h->next, h->bx, wys + q0, q1 - q0, pl0 + q0, pr0 + q0, pl1 + q0, pr1 + q0);
     for (int r = q0; r < q1; ++r) {
       nlo[r] = rok[r] ? first(ra[r]) : 0;
       nhi[r] = rok[r] ? last(rb[r]) : -1;
       if (theirs) {
         const int t = jc + r - theirs->j0;
         theirs->known[t] = true;
         theirs->lo[t] = nlo[r];
         theirs->hi[t] = nhi[r];
       }
     }
   }
   for (int r = 0; r < jn; ++r) {
    const int j = jc + r;
    const double y = ys[r];
    int i0, i1;
    if (mine && mine->known[j - mine->j0]) {
      i0 = mine->lo[j - mine->j0];
      i1 = mine->hi[j - mine->j0];
    } else {
      double xa, xb;
      if (mine) {
        if (!s.row_range(y, xa, xb, start_cut)) continue;
      } else {
        if (!sok[r]) continue;
        xa = sa[r];
        xb = sb[r];
      }
      i0 = first(xa);
      i1 = last(xb);
    }
    if (i1 < i0) continue;
    // Nothing on this row stands above the tool: in a finishing raster, the
    // rows on the side the pass before has cut (about half the footprint).
    // The margin is far above the rounding of the row kernels, so every height
    // they would compute stays above every cell and the row is left as it is.
    if (!z.row_above(j, i0, i1, static_cast<float>(s.row_floor(y) - kRowSkipMargin_mm))) continue;
    // Cells [e0, e1] are left to next (inside next's cells on this row).
    int e0 = i1 + 1, e1 = i1;
    if (r >= q0 && r < q1) {
      double na, nb;
      const int n0 = nlo[r], n1 = nhi[r];
      const int c0 = std::max(i0, n0), c1 = std::min(i1, n1);
      if (c1 - c0 >= 4) {
        // Within both moves' cells (the window only picks the longest piece).
        na = g.x0_mm + c0 * g.cell_mm;
        nb = g.x0_mm + (c1 + 1) * g.cell_mm;
        double ol[2] = {ol0[r], ol1[r]}, orr[2] = {or0[r], or1[r]};
        const double nl[2] = {pl0[r], pl1[r]}, nr[2] = {pr0[r], pr1[r]};
        if (handoff_pieces(*h, wys[r], na, nb, 4 * g.cell_mm, 2, ol, orr, 2, nl, nr)) inner(na, nb, c0, c1, e0, e1);
      }
    }
    const int n = i1 - i0 + 1;
    float* buf = stack_buf;
    if (n > stack_cells) {
      heap_buf.resize(static_cast<std::size_t>(n));
      buf = heap_buf.data();
    }
    // The left-out cells get +inf (lower_row keeps them); a gap of a few cells
    // costs more (a second row_heights call) than it saves.
    if (e1 - e0 < 4 || (e0 > i0 && e1 < i1 && e1 - e0 < 12)) {
      s.row_heights(y, g.x0_mm, g.cell_mm, i0, n, buf);
      removed += z.lower_row(j, i0, n, buf);
    } else {
      s.row_heights(y, g.x0_mm, g.cell_mm, i0, e0 - i0, buf);
      s.row_heights(y, g.x0_mm, g.cell_mm, e1 + 1, i1 - e1, buf + (e1 + 1 - i0));
      // Only the evaluated cells reach lower_row (the gap may be most of the row),
      // as one call across a short gap.
      const int lead = e0 - i0, tail = i1 - e1;
      if (lead > 0 && tail > 0 && e1 - e0 + 1 <= 16) {
        std::fill(buf + lead, buf + (e1 - i0 + 1), std::numeric_limits<float>::infinity());
        removed += z.lower_row(j, i0, n, buf);
      } else {
        if (lead > 0) removed += z.lower_row(j, i0, lead, buf);
        if (tail > 0) removed += z.lower_row(j, e1 + 1, tail, buf + (e1 + 1 - i0));
      }
    }
   }
  }
  return removed;
}

}  // namespace

double sweep_line(ZMap& z, const LineSweep& s, bool start_cut) {
  return sweep_rows(z, s, 0, z.grid().ny - 1, start_cut);
}

double sweep_line_reference(ZMap& z, const LineSweep& s) {
  const GridSpec& g = z.grid();
  const int j0 = std::max(0, z.iy(s.y_min())), j1 = std::min(g.ny - 1, z.iy(s.y_max()));
  std::vector<float> buf;
  double removed = 0;
  for (int j = j0; j <= j1; ++j) {
    const double y = z.cy(j);
    const int i0 = std::max(0, z.ix(s.x_min())), i1 = std::min(g.nx - 1, z.ix(s.x_max()));
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
  // Move k leaves cells to move k + 1 when that one is chained (the last move of
  // the batch leaves nothing: the next batch may not come).
  std::vector<Handoff> hand(s.size());
  std::vector<char> has(s.size(), 0);
  for (std::size_t k = 0; k + 1 < s.size(); ++k) has[k] = chained(k + 1) && make_handoff(s[k], s[k + 1], hand[k]);
  // One task per tile row: lower_row on different tile rows never shares a tile.
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(j0 / T, j1 / T + 1, 1), 0.0,
      [&](const tbb::blocked_range<int>& r, double acc) {
        RowCache cache[2];
        for (int band = r.begin(); band != r.end(); ++band) {
          const RowCache* mine = nullptr;
          for (std::size_t k = 0; k < s.size(); ++k) {
            if (!has[k]) {
              acc += sweep_rows(z, s[k], band * T, band * T + T - 1, chained(k), nullptr, nullptr, mine);
              mine = nullptr;
              continue;
            }
            RowCache* theirs = &cache[k % 2];
            theirs->reset(band * T);
            acc += sweep_rows(z, s[k], band * T, band * T + T - 1, chained(k), &s[k + 1], &hand[k], mine, theirs);
            mine = theirs;
          }
        }
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

double sweep_arc(ZMap& z, const ToolProfile& tool, const interp::Arc& a, double chord_tol_mm) {
  const auto pts = interp::arc_polyline(a, interp::arc_chord_count(a, chord_tol_mm));
  return sweep_polyline(z, tool, pts);
}

}  // namespace deflex::stock
