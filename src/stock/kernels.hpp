// The row kernels of the line sweep that more than one file of src/stock needs:
// the per-row constants of the ball and flat kernels, the start_cut window, and
// the AVX2 versions of the kernels (sweep_avx2.cpp). Every AVX2 kernel does the
// operations of its scalar twin in the same order (IEEE division and square root,
// std::min / std::max as min_pd / max_pd with the same operand order, no FMA), so
// every lane equals the scalar result bit for bit and the Z-map does not depend on
// the CPU.
#pragma once
#include <limits>

#include "deflex/stock/sweep.hpp"
#include "handoff.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#define DEFLEX_SWEEP_AVX2 1
#endif

namespace deflex::stock::detail {

constexpr double inf = std::numeric_limits<double>::infinity();

// A height of the swept surface as the Z-map stores it (+inf: the footprint misses).
inline float to_cell(double h) { return h == inf ? std::numeric_limits<float>::infinity() : static_cast<float>(h); }

// One row of the ball and flat kernels: cell centre x = gx0 + (i + 0.5) cell,
// wx = x - ax, along / across the move wx ex + wyey, wx ey - wyex; R2 = R^2, L the
// XY length, m the slope, k the ball's contact offset per unit half-chord.
struct RowConsts {
  double gx0, cell, ax, ex, ey, wyey, wyex, R2, L, m, k, az, azR;
};

// The part of the footprint a move with start_cut may lower (LineSweep::row_range
// in the header): keep par >= -back, plus for a descending bull nose the disc of
// radius r1 about a. cut: whether anything is cut away at all.
struct StartCut {
  bool cut = false;
  double back = 0, r1 = 0;
};
StartCut start_cut_of(const LineSweep& s, bool start_cut);

bool cpu_has_avx2();

#ifdef DEFLEX_SWEEP_AVX2
// Cells [i0, i0 + n) of one row in blocks of 4, the last one partly (n >= 4; fewer
// are left to the scalar path); return how many were done.
__attribute__((target("avx2"))) int ball_row_avx2(const RowConsts& c, int i0, int n, float* out);
__attribute__((target("avx2"))) int flat_row_avx2(const RowConsts& c, bool rising, int i0, int n, float* out);
// All n cells of a row of a bull nose's line (len > 0, y inside the footprint's box).
__attribute__((target("avx2"))) void bull_row_avx2(const LineSweep& sw, double y, double gx0, double cell, int i0,
                                                   int n, float* out);
// LineSweep::row_range on rows y[0, n) four at a time; returns how many rows were done.
__attribute__((target("avx2"))) int row_ranges_avx2(const LineSweep& s, const double* ys, int n, double* x0,
                                                    double* x1, unsigned char* ok, bool start_cut);
// cond_row on rows wys[0, n) four at a time, into cond_rows' slots; returns how many rows were done.
__attribute__((target("avx2"))) int cond_rows_avx2(const Cond& q, double bx, const double* wys, int n, double* L0,
                                                   double* R0, double* L1, double* R1);
#endif

}  // namespace deflex::stock::detail
