// The AVX2 kernels of the line sweep (kernels.hpp): four cells or four rows per
// step, each the operations of its scalar twin in line_sweep.cpp, row_kernels.cpp
// and handoff.cpp, in the same order.
#include "kernels.hpp"

#ifdef DEFLEX_SWEEP_AVX2
#include <immintrin.h>

#include <algorithm>
#include <cmath>

namespace deflex::stock::detail {

bool cpu_has_avx2() {
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return has;
}

namespace {

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

// RowConsts in four lanes.
struct RowV {
  __m256d gx0, cell, half, ax, ex, ey, wyey, wyex, R2, L, m, k, az, azR, zero, dinf;
};

__attribute__((target("avx2"), always_inline)) inline RowV broadcast(const RowConsts& c) {
  return {_mm256_set1_pd(c.gx0), _mm256_set1_pd(c.cell), _mm256_set1_pd(0.5),  _mm256_set1_pd(c.ax),
          _mm256_set1_pd(c.ex),  _mm256_set1_pd(c.ey),   _mm256_set1_pd(c.wyey), _mm256_set1_pd(c.wyex),
          _mm256_set1_pd(c.R2),  _mm256_set1_pd(c.L),    _mm256_set1_pd(c.m),    _mm256_set1_pd(c.k),
          _mm256_set1_pd(c.az),  _mm256_set1_pd(c.azR),  _mm256_setzero_pd(),    _mm256_set1_pd(inf)};
}

// ball_cell, four cells (par and cr^2 of row_blocks); +inf where the footprint misses.
struct BallLanes {
  __attribute__((target("avx2"), always_inline)) __m256d operator()(const RowV& v, __m256d par, __m256d cr2) const {
    const __m256d rho2 = _mm256_sub_pd(v.R2, cr2);
    const __m256d rho = _mm256_sqrt_pd(_mm256_max_pd(rho2, v.zero));
    const __m256d s = _mm256_min_pd(_mm256_max_pd(_mm256_sub_pd(par, _mm256_mul_pd(v.k, rho)), v.zero), v.L);
    const __m256d q = _mm256_sub_pd(s, par);
    const __m256d t = _mm256_sub_pd(rho2, _mm256_mul_pd(q, q));
    const __m256d h =
        _mm256_sub_pd(_mm256_add_pd(v.azR, _mm256_mul_pd(v.m, s)), _mm256_sqrt_pd(_mm256_max_pd(t, v.zero)));
    const __m256d miss = _mm256_or_pd(_mm256_cmp_pd(cr2, v.R2, _CMP_GT_OQ), _mm256_cmp_pd(t, v.zero, _CMP_LT_OQ));
    return _mm256_blendv_pd(h, v.dinf, miss);
  }
};

// flat_cell<Rising>, four cells.
template <bool Rising>
struct FlatLanes {
  __attribute__((target("avx2"), always_inline)) __m256d operator()(const RowV& v, __m256d par, __m256d cr2) const {
    const __m256d rho = _mm256_sqrt_pd(_mm256_max_pd(_mm256_sub_pd(v.R2, cr2), v.zero));
    const __m256d lo = _mm256_sub_pd(par, rho), hi = _mm256_add_pd(par, rho);
    const __m256d s = Rising ? _mm256_max_pd(lo, v.zero) : _mm256_min_pd(hi, v.L);
    const __m256d h = _mm256_add_pd(v.az, _mm256_mul_pd(v.m, s));
    const __m256d miss = _mm256_or_pd(
        _mm256_or_pd(_mm256_cmp_pd(cr2, v.R2, _CMP_GT_OQ), _mm256_cmp_pd(lo, v.L, _CMP_GT_OQ)),
        _mm256_cmp_pd(hi, v.zero, _CMP_LT_OQ));
    return _mm256_blendv_pd(h, v.dinf, miss);
  }
};

// Cells [i0, i0 + n) in blocks of 4, the last one partly (n >= 4; fewer are left
// to the scalar path); returns how many were done. The last block partly: short
// pieces of rows (the hand-off splits them) would otherwise spend more on the
// scalar tail than here. Per cell, par and cr^2 as in cell_frame (row_kernels.cpp).
template <class Lanes>
__attribute__((target("avx2"), always_inline)) inline int row_blocks(const RowConsts& c, int i0, int n, float* out) {
  const RowV v = broadcast(c);
  const Lanes lanes;
  __m256d idx = _mm256_setr_pd(i0, i0 + 1.0, i0 + 2.0, i0 + 3.0);
  const __m256d four = _mm256_set1_pd(4.0);
  int done = 0;
  for (const int stop = n >= 4 ? n : 0; done < stop; done += 4, idx = _mm256_add_pd(idx, four)) {
    const __m256d x = _mm256_add_pd(v.gx0, _mm256_mul_pd(_mm256_add_pd(idx, v.half), v.cell));
    const __m256d wx = _mm256_sub_pd(x, v.ax);
    const __m256d par = _mm256_add_pd(_mm256_mul_pd(wx, v.ex), v.wyey);
    const __m256d cr = _mm256_sub_pd(_mm256_mul_pd(wx, v.ey), v.wyex);
    store_lanes(out + done, _mm256_cvtpd_ps(lanes(v, par, _mm256_mul_pd(cr, cr))), std::min(4, n - done));
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

// row_range's constants, broadcast to four rows.
struct RowRangeV {
  double ex, ey, len, r1;
  __m256d Rv, R2, sign, dinf, dninf, ca0, ca1, cb0, cb1, vex, vey, c1x, c2x, vzero, vlen, vmR, mback, vr1, r1sq;
};

__attribute__((target("avx2"))) RowRangeV row_range_consts(const LineSweep& s, const StartCut& sc) {
  const double R = s.tool().radius_mm, ex = s.dir_x(), ey = s.dir_y();
  const Point3 &a = s.a(), &b = s.b();
  return {ex,
          ey,
          s.xy_length(),
          sc.r1,
          _mm256_set1_pd(R),
          _mm256_set1_pd(R * R),
          _mm256_set1_pd(-0.0),
          _mm256_set1_pd(inf),
          _mm256_set1_pd(-inf),
          _mm256_set1_pd(a[0]),
          _mm256_set1_pd(a[1]),
          _mm256_set1_pd(b[0]),
          _mm256_set1_pd(b[1]),
          _mm256_set1_pd(ex),
          _mm256_set1_pd(ey),
          _mm256_set1_pd(-a[0] * ex),
          _mm256_set1_pd(-a[0] * ey),
          _mm256_setzero_pd(),
          _mm256_set1_pd(s.xy_length()),
          _mm256_set1_pd(-R),
          _mm256_set1_pd(-sc.back),
          _mm256_set1_pd(sc.r1),
          _mm256_set1_pd(sc.r1 * sc.r1)};
}

// The footprint on four rows (wy = y - a_y): the discs about a and b and the band between.
__attribute__((target("avx2"), always_inline)) inline void rr_footprint(const RowRangeV& c, __m256d y, __m256d wy,
                                                                       __m256d& lo, __m256d& hi) {
  lo = c.dinf;
  hi = c.dninf;
  rr_disc(y, c.ca0, c.ca1, c.Rv, c.R2, c.sign, lo, hi);
  rr_disc(y, c.cb0, c.cb1, c.Rv, c.R2, c.sign, lo, hi);
  if (c.len > 0) {
    __m256d bl = c.dninf, bh = c.dinf;
    rr_clip(c.ex, _mm256_add_pd(c.c1x, _mm256_mul_pd(wy, c.vey)), c.vzero, c.vlen, c.dinf, bl, bh);
    rr_clip(c.ey, _mm256_sub_pd(c.c2x, _mm256_mul_pd(wy, c.vex)), c.vmR, c.Rv, c.dinf, bl, bh);
    const __m256d in = _mm256_cmp_pd(bl, bh, _CMP_LE_OQ);
    lo = _mm256_blendv_pd(lo, _mm256_min_pd(bl, lo), in);
    hi = _mm256_blendv_pd(hi, _mm256_max_pd(bh, hi), in);
  }
}

// start_cut's window (StartCut) on four rows, narrowing [lo, hi].
__attribute__((target("avx2"), always_inline)) inline void rr_start_cut(const RowRangeV& c, __m256d wy, __m256d& lo,
                                                                       __m256d& hi) {
  __m256d clo = lo, chi = hi;
  const __m256d par0 = _mm256_add_pd(c.c1x, _mm256_mul_pd(wy, c.vey));
  if (std::fabs(c.ex) < 1e-15) {
    chi = _mm256_blendv_pd(chi, c.dninf, _mm256_cmp_pd(par0, c.mback, _CMP_LT_OQ));
  } else if (c.ex > 0) {
    clo = _mm256_max_pd(_mm256_div_pd(_mm256_sub_pd(c.mback, par0), c.vex), clo);
  } else {
    chi = _mm256_min_pd(_mm256_div_pd(_mm256_sub_pd(c.mback, par0), c.vex), chi);
  }
  if (c.r1 > 0) {
    const __m256d in = _mm256_cmp_pd(_mm256_andnot_pd(c.sign, wy), c.vr1, _CMP_LE_OQ);
    const __m256d w = _mm256_sqrt_pd(_mm256_sub_pd(c.r1sq, _mm256_mul_pd(wy, wy)));
    clo = _mm256_blendv_pd(clo, _mm256_min_pd(_mm256_sub_pd(c.ca0, w), clo), in);
    chi = _mm256_blendv_pd(chi, _mm256_max_pd(_mm256_add_pd(c.ca0, w), chi), in);
  }
  lo = _mm256_max_pd(clo, lo);
  hi = _mm256_min_pd(chi, hi);
}

}  // namespace

__attribute__((target("avx2"))) int ball_row_avx2(const RowConsts& c, int i0, int n, float* out) {
  return row_blocks<BallLanes>(c, i0, n, out);
}

__attribute__((target("avx2"))) int flat_row_avx2(const RowConsts& c, bool rising, int i0, int n, float* out) {
  return rising ? row_blocks<FlatLanes<true>>(c, i0, n, out) : row_blocks<FlatLanes<false>>(c, i0, n, out);
}

__attribute__((target("avx2"))) void bull_row_avx2(const LineSweep& sw, double y, double gx0, double cell, int i0,
                                                   int n, float* out) {
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
        out[k + l] = to_cell(sw.lower_height(gx0 + (static_cast<double>(i0 + k + l) + 0.5) * cell, y));
      }
  }
  for (; k < n; ++k) {
    out[k] = to_cell(sw.lower_height(gx0 + (static_cast<double>(i0 + k) + 0.5) * cell, y));
  }
}

__attribute__((target("avx2"))) int row_ranges_avx2(const LineSweep& s, const double* ys, int n, double* x0,
                                                    double* x1, unsigned char* ok, bool start_cut) {
  const StartCut sc = start_cut_of(s, start_cut);
  const RowRangeV c = row_range_consts(s, sc);
  int k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256d y = _mm256_loadu_pd(ys + k);
    const __m256d wy = _mm256_sub_pd(y, c.ca1);
    __m256d lo, hi;
    rr_footprint(c, y, wy, lo, hi);
    if (sc.cut) rr_start_cut(c, wy, lo, hi);
    _mm256_storeu_pd(x0 + k, lo);
    _mm256_storeu_pd(x1 + k, hi);
    const int good = _mm256_movemask_pd(_mm256_cmp_pd(lo, hi, _CMP_NGT_UQ));  // !(lo > hi)
    for (int l = 0; l < 4; ++l) ok[k + l] = static_cast<unsigned char>(good >> l & 1);
  }
  return k;
}

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

}  // namespace deflex::stock::detail

#else

namespace deflex::stock::detail {

bool cpu_has_avx2() { return false; }

}  // namespace deflex::stock::detail

#endif
