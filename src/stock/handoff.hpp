// The hand-off between chained moves (LineSweep::end_handoff, sweep_lines): the
// cells a move may leave to the move after it. Why that changes no cell:
// handoff.cpp.
#pragma once
#include <cmath>

#include "deflex/stock/sweep.hpp"

namespace deflex::stock::detail {

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
  Cond own, next;         // (i), (ii) of handoff.cpp
  double r_out = 0;       // and |p - b| >= r_out (0: no disc)
};

// The conditions under which k leaves cells to n; false when it leaves none.
bool make_handoff(const LineSweep& k, const LineSweep& n, Handoff& h);

// The cells of row y (wy = y - b_y) meeting a condition: up to two intervals.
int cond_row(const Cond& q, double bx, double wy, double* l, double* r);

// cond_row on rows wy[0, n) into two fixed slots per row (l0, r0), (l1, r1), in
// cond_row's order, an absent piece as (inf, -inf); four rows at a time with AVX2,
// the same operations, so the same doubles.
void cond_rows(const Cond& q, double bx, const double* wy, int n, double* L0, double* R0, double* L1, double* R1);

// Narrows [x0, x1] (cells both moves evaluate on row y) to one interval of cells
// move k may leave out (the longest where the conditions split it), given the
// pieces of h.own (no of them) and of h.next (nn) on the row; a piece with l > r
// is none.
bool handoff_pieces(const Handoff& h, double wy, double& x0, double& x1, double min_len, int no, double* ol,
                    double* orr, int nn, const double* nl, const double* nr);

}  // namespace deflex::stock::detail
