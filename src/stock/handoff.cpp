#include "handoff.hpp"

#include <algorithm>

#include "kernels.hpp"

namespace deflex::stock {

// Move k leaves cells to the chained move n after it (make_handoff); why that
// changes no cell:
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

namespace detail {

namespace {

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

}  // namespace

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
    case EndShape::ball:
      h.own = ball_cond(k, 0, R);
      h.next = ball_cond(n, mu, R);
      break;
    case EndShape::bull:
      if (m > 0) {
        h.own.c += s3 * r1 * m;
        h.r_out = r1 * (1 + 1e-9) + tiny_mm;
      }
      h.next.c += std::max(mn, 0.0) * s3 * r1;
      if (!(-mn >= mu / (2 * s3 * r1))) h.r_out = std::max(h.r_out, r1 + mu);
      break;
    case EndShape::flat:
      if (m > 0 || !(-mn >= mu / (2 * R))) return false;
      break;
  }
  h.own.prepare();
  h.next.prepare();
  return true;
}

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

void cond_rows(const Cond& q, double bx, const double* wy, int n, double* L0, double* R0, double* L1, double* R1) {
  int k = 0;
#ifdef DEFLEX_SWEEP_AVX2
  if (cpu_has_avx2()) k = cond_rows_avx2(q, bx, wy, n, L0, R0, L1, R1);
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

namespace {

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

}  // namespace

}  // namespace detail

bool LineSweep::end_handoff(const LineSweep& next, double y, double& x0, double& x1) const {
  detail::Handoff h;
  double na, nb;
  if (!detail::make_handoff(*this, next, h) || !next.row_range(y, na, nb, true)) return false;
  x0 = std::max(x0, na);
  x1 = std::min(x1, nb);
  return detail::handoff_row(h, y, x0, x1);
}

}  // namespace deflex::stock
