// The row kernels of LineSweep: the heights of the swept surface over a run of
// cells of one Z-map row, and the footprint's cells on several rows at once (the
// AVX2 kernels in sweep_avx2.cpp, the scalar ones here).
#include "deflex/stock/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels.hpp"

namespace deflex::stock {

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

using detail::RowConsts;

// Cell i along (par) and across (cr2: the square of the signed perp) the move.
struct CellFrame {
  double par, cr2;
};
inline CellFrame cell_frame(const RowConsts& c, int i) {
  const double x = c.gx0 + (static_cast<double>(i) + 0.5) * c.cell;
  const double wx = x - c.ax;
  const double cr = wx * c.ey - c.wyex;
  return {wx * c.ex + c.wyey, cr * cr};
}

inline float ball_cell(const RowConsts& c, int i) {
  const auto [par, cr2] = cell_frame(c, i);
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
  const auto [par, cr2] = cell_frame(c, i);
  const double rho = std::sqrt(std::max(c.R2 - cr2, 0.0));
  const double lo = par - rho, hi = par + rho;
  const double s = Rising ? std::max(lo, 0.0) : std::min(hi, c.L);
  const double h = c.az + c.m * s;
  return (cr2 > c.R2 || lo > c.L || hi < 0) ? std::numeric_limits<float>::infinity() : static_cast<float>(h);
}

}  // namespace

void LineSweep::row_ranges(const double* y, int n, double* x0, double* x1, unsigned char* ok, bool start_cut) const {
  if (start_cut && len_ == 0 && b_[2] >= a_[2]) {  // a retract removes nothing new
    std::fill(ok, ok + std::max(n, 0), 0);
    return;
  }
  int k = 0;
#ifdef DEFLEX_SWEEP_AVX2
  if (detail::cpu_has_avx2()) k = detail::row_ranges_avx2(*this, y, n, x0, x1, ok, start_cut);
#endif
  for (; k < n; ++k) ok[k] = row_range(y[k], x0[k], x1[k], start_cut);
}

void LineSweep::row_heights(double y, double gx0, double cell, int i0, int n, float* out) const {
  if (n <= 0) return;
#ifdef DEFLEX_SWEEP_AVX2
  if (len_ > 0 && tool_.kind == EndShape::bull && detail::cpu_has_avx2() && y >= ymin_ && y <= ymax_) {
    detail::bull_row_avx2(*this, y, gx0, cell, i0, n, out);
    return;
  }
#endif
  const bool vec = len_ > 0 && (tool_.kind == EndShape::ball || tool_.kind == EndShape::flat);
  if (!vec) {  // plunges and bull noses: per cell
    for (int k = 0; k < n; ++k) {
      out[k] = detail::to_cell(lower_height(gx0 + (static_cast<double>(i0 + k) + 0.5) * cell, y));
    }
    return;
  }
  const double wy = y - a_[1], R = tool_.radius_mm;
  const detail::RowConsts c{gx0, cell, a_[0], ex_, ey_, wy * ey_, wy * ex_,
                            R * R, len_, slope_, ball_k_, a_[2], a_[2] + R};
  int done = 0;
  if (tool_.kind == EndShape::ball) {
#ifdef DEFLEX_SWEEP_AVX2
    if (detail::cpu_has_avx2()) done = detail::ball_row_avx2(c, i0, n, out);
#endif
    for (int k = done; k < n; ++k) out[k] = ball_cell(c, i0 + k);
  } else if (slope_ >= 0) {
#ifdef DEFLEX_SWEEP_AVX2
    if (detail::cpu_has_avx2()) done = detail::flat_row_avx2(c, true, i0, n, out);
#endif
    for (int k = done; k < n; ++k) out[k] = flat_cell<true>(c, i0 + k);
  } else {
#ifdef DEFLEX_SWEEP_AVX2
    if (detail::cpu_has_avx2()) done = detail::flat_row_avx2(c, false, i0, n, out);
#endif
    for (int k = done; k < n; ++k) out[k] = flat_cell<false>(c, i0 + k);
  }
}

}  // namespace deflex::stock
