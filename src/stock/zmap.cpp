#include "deflex/stock/zmap.hpp"

#include <cstdio>

#include <algorithm>
#include <cmath>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "deflex/diag/diagnostics.hpp"

namespace deflex::stock {

namespace {
constexpr int T = ZMap::tile_cells;
constexpr std::size_t tile_floats = static_cast<std::size_t>(T) * T + T;  // cells + row maxima
}  // namespace

std::string too_many_cells(double dx_mm, double dy_mm, double cell_mm) {
  char b[256];
  std::snprintf(b, sizeof b, "stock: %.6g x %.6g mm at %.6g mm cells is %.3g cells, more than the limit of %.3g "
                "(a stock far larger than the part, or inches read as mm?)", dx_mm, dy_mm, cell_mm,
                std::ceil(dx_mm / cell_mm) * std::ceil(dy_mm / cell_mm), max_cells);
  return b;
}

GridSpec grid_covering(double x0_mm, double y0_mm, double x1_mm, double y1_mm, double cell_mm) {
  if (!(cell_mm > 0)) throw Error(ErrorKind::config, "stock: cell size must be > 0");
  if (!(x1_mm > x0_mm) || !(y1_mm > y0_mm)) throw Error(ErrorKind::config, "stock: empty XY extent");
  GridSpec g;
  g.x0_mm = x0_mm;
  g.y0_mm = y0_mm;
  g.cell_mm = cell_mm;
  // At least one cell per axis: an extent thinner than 1e-9 cells rounded to 0,
  // and 0 x 5e36 passed the product check below (a fuzzed STL).
  const double nx = std::max(1.0, std::ceil((x1_mm - x0_mm) / cell_mm - 1e-9));
  const double ny = std::max(1.0, std::ceil((y1_mm - y0_mm) / cell_mm - 1e-9));
  // Checked before any allocation, and before the counts become ints; written
  // so that NaN and infinity fail too.
  if (!(nx * ny <= max_cells)) throw Error(ErrorKind::config, too_many_cells(x1_mm - x0_mm, y1_mm - y0_mm, cell_mm));
  g.nx = static_cast<int>(nx);
  g.ny = static_cast<int>(ny);
  return g;
}

ZMap::ZMap(const GridSpec& g, float height, double base_z_mm) : g_(g), base_z_(base_z_mm) {
  if (g.nx <= 0 || g.ny <= 0 || !(g.cell_mm > 0)) throw Error(ErrorKind::internal, "ZMap: empty grid");
  inv_cell_ = 1.0 / g.cell_mm;
  tiles_x_ = static_cast<std::size_t>((g.nx + T - 1) / T);
  tiles_y_ = static_cast<std::size_t>((g.ny + T - 1) / T);
  tiles_.resize(tiles_x_ * tiles_y_);
  for (Tile& t : tiles_) t.uniform = t.max = height;
}

ZMap ZMap::clone() const {
  ZMap z(g_, no_material, base_z_);
  for (std::size_t k = 0; k < tiles_.size(); ++k) {
    const Tile& from = tiles_[k];
    Tile& to = z.tiles_[k];
    to.uniform = from.uniform;
    to.max = from.max;
    if (from.cells) {
      to.cells.reset(new float[tile_floats]);
      std::copy(from.cells.get(), from.cells.get() + tile_floats, to.cells.get());
    }
  }
  return z;
}

float* ZMap::materialize(Tile& t) {
  if (!t.cells) {
    t.cells.reset(new float[tile_floats]);
    std::fill(t.cells.get(), t.cells.get() + tile_floats, t.uniform);
  }
  return t.cells.get();
}

double ZMap::height_smooth_general(double x_mm, double y_mm) const {
  const double u = (x_mm - g_.x0_mm) * inv_cell_ - 0.5, v = (y_mm - g_.y0_mm) * inv_cell_ - 0.5;
  const int i = fast_floor(u), j = fast_floor(v);
  if (i < 0 || j < 0 || i + 1 >= g_.nx || j + 1 >= g_.ny) return height_at(x_mm, y_mm);
  const float h00 = at(i, j), h10 = at(i + 1, j), h01 = at(i, j + 1), h11 = at(i + 1, j + 1);
  if (h00 == no_material || h10 == no_material || h01 == no_material || h11 == no_material)
    return height_at(x_mm, y_mm);
  return bilinear(u - i, v - j, h00, h10, h01, h11);
}

void ZMap::set(int i, int j, float h) {
  Tile& t = tiles_[tile_index(i, j)];
  if (!t.cells && t.uniform == h) return;
  float* c = materialize(t);
  c[local(i, j)] = h;
  const int r = j % T;
  float* row = c + static_cast<std::size_t>(r) * T;
  c[T * T + r] = *std::max_element(row, row + T);
  t.max = *std::max_element(c + T * T, c + T * T + T);
}

namespace {

// cur[k] = min(cur[k], h[k]) for k in [0, m) (no_material below the base);
// returns the removed height summed over the cells (cells at no_material or
// below the base contribute nothing).
// top: the max of the previous heights of the lowered cells (no_material if none).
double lower_span_scalar(float* cur, const float* h, int m, float base, double base_z, float& top) {
  double removed = 0;
  for (int k = 0; k < m; ++k) {
    const float old = cur[k];
    if (h[k] < old) {
      top = std::max(top, old);
      const float nw = h[k];
      if (old > base) removed += static_cast<double>(old) - std::max(static_cast<double>(nw), base_z);
      cur[k] = nw < base ? no_material : nw;
    }
  }
  return removed;
}

float max_of(const float* v, int n) {
  float m = no_material;
  for (int k = 0; k < n; ++k) m = std::max(m, v[k]);
  return m;
}

#if defined(__x86_64__) && defined(__GNUC__)
#define DEFLEX_ZMAP_AVX2 1

bool cpu_has_avx2() {
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return has;
}

// The same, 8 cells at a time; the per-cell removed heights are the scalar ones
// (only their summation order differs).
__attribute__((target("avx2"))) double lower_span_avx2(float* cur, const float* h, int m, float base, double base_z,
                                                       float& top) {
  const __m256 basef = _mm256_set1_ps(base), nomat = _mm256_set1_ps(no_material);
  const __m256d based = _mm256_set1_pd(base_z), basefd = _mm256_set1_pd(static_cast<double>(base));
  __m256d acc = _mm256_setzero_pd();
  __m256 tops = nomat;
  int any = 0, k = 0;
  for (; k + 8 <= m; k += 8) {
    const __m256 old = _mm256_loadu_ps(cur + k), nw = _mm256_loadu_ps(h + k);
    const __m256 low = _mm256_cmp_ps(nw, old, _CMP_LT_OQ);
    const int bits = _mm256_movemask_ps(low);
    if (!bits) continue;
    any |= bits;
    tops = _mm256_max_ps(tops, _mm256_blendv_ps(nomat, old, low));
    const __m256 val = _mm256_blendv_ps(nw, nomat, _mm256_cmp_ps(nw, basef, _CMP_LT_OQ));
    _mm256_storeu_ps(cur + k, _mm256_blendv_ps(old, val, low));
    for (int half = 0; half < 2; ++half) {
      const __m256d o = _mm256_cvtps_pd(half ? _mm256_extractf128_ps(old, 1) : _mm256_castps256_ps128(old));
      const __m256d w = _mm256_cvtps_pd(half ? _mm256_extractf128_ps(nw, 1) : _mm256_castps256_ps128(nw));
      const __m256d take = _mm256_and_pd(_mm256_cmp_pd(w, o, _CMP_LT_OQ), _mm256_cmp_pd(o, basefd, _CMP_GT_OQ));
      acc = _mm256_add_pd(acc, _mm256_and_pd(take, _mm256_sub_pd(o, _mm256_max_pd(w, based))));
    }
  }
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, acc);
  double removed = (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
  if (any) {
    alignas(32) float t[8];
    _mm256_store_ps(t, tops);
    top = std::max({top, t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7]});
  }
  removed += lower_span_scalar(cur + k, h + k, m - k, base, base_z, top);
  return removed;
}

__attribute__((target("avx2"))) float max_of_avx2(const float* v, int n) {  // n a multiple of 8
  __m256 m = _mm256_set1_ps(no_material);
  for (int k = 0; k < n; k += 8) m = _mm256_max_ps(m, _mm256_loadu_ps(v + k));
  alignas(32) float l[8];
  _mm256_store_ps(l, m);
  return std::max({l[0], l[1], l[2], l[3], l[4], l[5], l[6], l[7]});
}
#endif

}  // namespace

double ZMap::lower_row(int j, int i0, int n, const float* h) {
  if (j < 0 || j >= g_.ny) return 0;
  // Clip to the grid.
  if (i0 < 0) {
    h -= i0;
    n += i0;
    i0 = 0;
  }
  n = std::min(n, g_.nx - i0);
  double removed = 0;
  const float base = static_cast<float>(base_z_);
  const int r = j % T;
#ifdef DEFLEX_ZMAP_AVX2
  const bool avx2 = cpu_has_avx2();
#endif
  while (n > 0) {
    Tile& t = tiles_[tile_index(i0, j)];
    const int li = i0 % T;
    const int m = std::min(n, T - li);
    if (!t.cells) {
      // A uniform tile is materialised only when some cell goes lower.
      bool lower = false;
      for (int k = 0; k < m; ++k) lower |= h[k] < t.uniform;
      if (!lower) {
        h += m;
        i0 += m;
        n -= m;
        continue;
      }
    }
    float* cells = materialize(t);
    float* row = cells + static_cast<std::size_t>(r) * T;
    float top = no_material;  // the highest previous height of a lowered cell
#ifdef DEFLEX_ZMAP_AVX2
    if (avx2)
      removed += lower_span_avx2(row + li, h, m, base, base_z_, top);
    else
#endif
      removed += lower_span_scalar(row + li, h, m, base, base_z_, top);
    // Heights only go down: the row maximum changes only if a lowered cell held
    // it (top == row max), and the tile's only if that row held the tile's.
    float& row_max = cells[T * T + r];
    if (top != no_material && top >= row_max) {
      const float old_row_max = row_max;
#ifdef DEFLEX_ZMAP_AVX2
      if (avx2) {
        row_max = max_of_avx2(row, T);
        if (old_row_max >= t.max && row_max != old_row_max) t.max = max_of_avx2(cells + T * T, T);
      } else
#endif
      {
        row_max = max_of(row, T);
        if (old_row_max >= t.max && row_max != old_row_max) t.max = max_of(cells + T * T, T);
      }
    }
    h += m;
    i0 += m;
    n -= m;
  }
  return removed * g_.cell_mm * g_.cell_mm;
}

void ZMap::assign_tile(std::size_t tx, std::size_t ty, const float* src) {
  Tile& t = tiles_[ty * tiles_x_ + tx];
  // Cells past the grid edge take the first cell's value so they do not force an allocation.
  const int wi = std::min(T, g_.nx - static_cast<int>(tx) * T), wj = std::min(T, g_.ny - static_cast<int>(ty) * T);
  const float v0 = src[0];
  bool uniform = true;
  for (int r = 0; r < wj && uniform; ++r)
    for (int c = 0; c < wi; ++c)
      if (src[r * T + c] != v0) {
        uniform = false;
        break;
      }
  if (uniform) {
    t.cells.reset();
    t.uniform = t.max = v0;
    return;
  }
  float* cells = materialize(t);
  for (int r = 0; r < T; ++r) {
    float* row = cells + static_cast<std::size_t>(r) * T;
    for (int c = 0; c < T; ++c) row[c] = (r < wj && c < wi) ? src[r * T + c] : no_material;
    cells[T * T + r] = *std::max_element(row, row + T);
  }
  t.max = *std::max_element(cells + T * T, cells + T * T + T);
}

float ZMap::max_height_in(double x0_mm, double y0_mm, double x1_mm, double y1_mm) const {
  const int i0 = std::max(ix(x0_mm), 0), i1 = std::min(ix(x1_mm), g_.nx - 1);
  const int j0 = std::max(iy(y0_mm), 0), j1 = std::min(iy(y1_mm), g_.ny - 1);
  float m = no_material;
  if (i0 > i1 || j0 > j1) return m;
  for (int tj = j0 / T; tj <= j1 / T; ++tj)
    for (int ti = i0 / T; ti <= i1 / T; ++ti) {
      const Tile& t = tiles_[static_cast<std::size_t>(tj) * tiles_x_ + static_cast<std::size_t>(ti)];
      if (t.max <= m) continue;
      if (!t.cells) {
        m = t.uniform;
        continue;
      }
      // Row maxima of the rows inside the rectangle.
      const int r0 = std::max(j0 - tj * T, 0), r1 = std::min(j1 - tj * T, T - 1);
      for (int r = r0; r <= r1; ++r) m = std::max(m, t.cells[static_cast<std::size_t>(T) * T + r]);
    }
  return m;
}

bool ZMap::cells_above(int j, int i0, int i1, float h) const {
  i0 = std::max(i0, 0);
  i1 = std::min(i1, g_.nx - 1);
  if (j < 0 || j >= g_.ny || i1 < i0) return false;
  const std::size_t r = static_cast<std::size_t>(j % T);
  while (i0 <= i1) {
    const Tile& t = tiles_[tile_index(i0, j)];
    const int last = std::min(i1, (i0 / T) * T + T - 1);
    if (t.max > h) {
      if (!t.cells) return true;
      const float* row = t.cells.get() + r * T;
      if (t.cells[static_cast<std::size_t>(T) * T + r] > h) {  // the row's maximum (after the heights)
        // Counted rather than returned at the first: the compiler vectorises this.
        int above = 0;
        for (int i = i0 % T; i <= last % T; ++i) above += row[i] > h;
        if (above) return true;
      }
    }
    i0 = last + 1;
  }
  return false;
}

bool ZMap::none_above(double x0_mm, double y0_mm, double x1_mm, double y1_mm, float h) const {
  const int i0 = std::max(ix(x0_mm), 0), i1 = std::min(ix(x1_mm), g_.nx - 1);
  const int j0 = std::max(iy(y0_mm), 0), j1 = std::min(iy(y1_mm), g_.ny - 1);
  if (i0 > i1 || j0 > j1) return true;
  for (int tj = j0 / T; tj <= j1 / T; ++tj) {
    const int r0 = std::max(j0 - tj * T, 0), r1 = std::min(j1 - tj * T, T - 1);
    for (int ti = i0 / T; ti <= i1 / T; ++ti) {
      const Tile& t = tiles_[static_cast<std::size_t>(tj) * tiles_x_ + static_cast<std::size_t>(ti)];
      if (t.max <= h) continue;
      if (!t.cells) return false;
      // Counted rather than returned at the first: the compiler vectorises this.
      const float* row_max = t.cells.get() + static_cast<std::size_t>(T) * T;
      int above = 0;
      for (int r = r0; r <= r1; ++r) above += row_max[r] > h;
      if (above) return false;
    }
  }
  return true;
}

std::size_t ZMap::allocated_tiles() const {
  return static_cast<std::size_t>(std::count_if(tiles_.begin(), tiles_.end(), [](const Tile& t) { return t.cells != nullptr; }));
}

std::size_t ZMap::allocated_bytes() const {
  return allocated_tiles() * tile_floats * sizeof(float) + tiles_.size() * sizeof(Tile) + sizeof(*this);
}

std::size_t ZMap::worst_case_bytes() const {
  return tiles_.size() * (tile_floats * sizeof(float) + sizeof(Tile)) + sizeof(*this);
}

}  // namespace deflex::stock
