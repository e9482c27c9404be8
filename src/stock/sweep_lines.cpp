// The driver of the line sweep: moves cut into the Z-map row by row, one band of
// tile rows per task (TBB), each move handing cells off to the chained move after
// it (handoff.cpp); and the polylines and arcs swept as chained lines.
#include "deflex/stock/sweep.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "deflex/diag/parallel_trace.hpp"
#include "handoff.hpp"
#include "kernels.hpp"

namespace deflex::stock {

namespace {

using detail::Handoff;

// A band's row is left alone when its stock lies this far below the tool's lowest
// possible surface on it (float rounding at |z| = 1000 mm: 6e-5 mm).
constexpr double kRowSkipMargin_mm = 1e-3;
// Cells per span of the span skip (cut_cells): a span's test (its floor, a scan
// of its stock) costs about what computing a few cells does.
constexpr int kSpanCells = 32;

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

// One move cut into rows [j0, j1] (within one band when a cache is given); with a
// hand-off, the cells `next` (swept right after it on the same rows) lowers further
// are left out. mine: this move's cells if known; theirs: next's, filled here.
class RowSweep {
 public:
  RowSweep(ZMap& z, const LineSweep& s, bool start_cut, const LineSweep* next, const Handoff* h, const RowCache* mine,
           RowCache* theirs)
      : z_(z),
        g_(z.grid()),
        s_(s),
        start_cut_(start_cut),
        next_(next),
        h_(h),
        mine_(mine),
        theirs_(theirs),
        nj0_(next ? z.iy(next->y_min()) : 0),
        nj1_(next ? z.iy(next->y_max()) : -1) {}

  // The removed volume, mm^3.
  double rows(int j0, int j1);
  std::uint64_t cells() const { return cells_; }  // heights computed so far

 private:
  static constexpr int chunk = ZMap::tile_cells;
  // Row heights: on the stack for rows of up to 1024 cells (D 51 mm at 0.05 mm).
  static constexpr int stack_cells = 1024;

  // Cells whose centre lies in [xa, xb]: [first(xa), last(xb)].
  int first(double xa) const {
    return std::max(0, static_cast<int>(std::ceil((xa - g_.x0_mm) / g_.cell_mm - 0.5)));
  }
  int last(double xb) const {
    return std::min(g_.nx - 1, static_cast<int>(std::floor((xb - g_.x0_mm) / g_.cell_mm - 0.5)));
  }
  void inner(double xa, double xb, int lo, int hi, int& c0, int& c1) const;
  void next_ranges(int jc, int jn);
  bool row_cells(int r, int j, int& i0, int& i1) const;
  bool chunk_below(int jc, int jn) const;
  void left_out(int r, int i0, int i1, int& e0, int& e1) const;
  void cut_row(int j, double y, int i0, int i1, int e0, int e1, double& removed);
  void cut_cells(int j, double y, int a, int b, float* buf, double& removed);

  ZMap& z_;
  const GridSpec& g_;
  const LineSweep& s_;
  const bool start_cut_;
  const LineSweep* next_;
  const Handoff* h_;
  const RowCache* mine_;
  RowCache* theirs_;
  const int nj0_, nj1_;  // next's rows (sweep_rows of next clips to these)
  // The rows of the chunk: y, this move's row ranges (unless mine_ knows them).
  double ys_[chunk], sa_[chunk], sb_[chunk];
  unsigned char sok_[chunk];
  // next's rows in this chunk, [q0_, q1_): its cells and the hand-off conditions'
  // pieces (cond_rows), own's, then next's.
  int q0_ = 0, q1_ = 0;
  int nlo_[chunk], nhi_[chunk];
  double wys_[chunk], ol0_[chunk], or0_[chunk], ol1_[chunk], or1_[chunk], pl0_[chunk], pr0_[chunk], pl1_[chunk],
      pr1_[chunk];
  float stack_buf_[stack_cells];
  std::uint64_t cells_ = 0;
};

// first and last for the left-out cells, inside [lo, hi]: by a multiplication (the
// regions have margins far above its rounding).
void RowSweep::inner(double xa, double xb, int lo, int hi, int& c0, int& c1) const {
  const double inv_cell = 1 / g_.cell_mm;
  const double t0 = std::clamp((xa - g_.x0_mm) * inv_cell - 0.5, lo - 1.0, hi + 1.0);
  const double t1 = std::clamp((xb - g_.x0_mm) * inv_cell - 0.5, lo - 1.0, hi + 1.0);
  const int k0 = static_cast<int>(t0), k1 = static_cast<int>(t1);  // toward zero: ceil and floor below
  c0 = std::max(lo, k0 + (k0 < t0));
  c1 = std::min(hi, k1 - (k1 > t1));
}

// next's row ranges and the hand-off pieces on the rows [q0_, q1_) of the chunk
// from row jc (jn rows), several rows per step; copied to theirs_ for next.
void RowSweep::next_ranges(int jc, int jn) {
  q0_ = std::clamp(nj0_ - jc, 0, jn);
  q1_ = std::clamp(nj1_ - jc + 1, 0, jn);
  if (q1_ <= q0_) return;
  double ra[chunk], rb[chunk];
  unsigned char rok[chunk];
  const int q0 = q0_, nq = q1_ - q0_;
  next_->row_ranges(ys_ + q0, nq, ra + q0, rb + q0, rok + q0, true);
  for (int r = q0; r < q1_; ++r) wys_[r] = ys_[r] - h_->by;
  detail::cond_rows(h_->own, h_->bx, wys_ + q0, nq, ol0_ + q0, or0_ + q0, ol1_ + q0, or1_ + q0);
  detail::cond_rows(h_->next, h_->bx, wys_ + q0, nq, pl0_ + q0, pr0_ + q0, pl1_ + q0, pr1_ + q0);
  for (int r = q0; r < q1_; ++r) {
    nlo_[r] = rok[r] ? first(ra[r]) : 0;
    nhi_[r] = rok[r] ? last(rb[r]) : -1;
    if (theirs_) {
      const int t = jc + r - theirs_->j0;
      theirs_->known[t] = true;
      theirs_->lo[t] = nlo_[r];
      theirs_->hi[t] = nhi_[r];
    }
  }
}

// This move's cells [i0, i1] on row r of the chunk (row j); false if none.
bool RowSweep::row_cells(int r, int j, int& i0, int& i1) const {
  if (mine_ && mine_->known[j - mine_->j0]) {
    i0 = mine_->lo[j - mine_->j0];
    i1 = mine_->hi[j - mine_->j0];
    return true;
  }
  double xa, xb;
  if (mine_) {
    if (!s_.row_range(ys_[r], xa, xb, start_cut_)) return false;
  } else {
    if (!sok_[r]) return false;
    xa = sa_[r];
    xb = sb_[r];
  }
  i0 = first(xa);
  i1 = last(xb);
  return true;
}

// Cells [e0, e1] of [i0, i1] on row r of the chunk left to next (inside next's
// cells on this row); e0 > e1 when none.
void RowSweep::left_out(int r, int i0, int i1, int& e0, int& e1) const {
  e0 = i1 + 1;
  e1 = i1;
  if (r < q0_ || r >= q1_) return;
  const int c0 = std::max(i0, nlo_[r]), c1 = std::min(i1, nhi_[r]);
  if (c1 - c0 < 4) return;
  // Within both moves' cells (the window only picks the longest piece).
  double na = g_.x0_mm + c0 * g_.cell_mm;
  double nb = g_.x0_mm + (c1 + 1) * g_.cell_mm;
  double ol[2] = {ol0_[r], ol1_[r]}, orr[2] = {or0_[r], or1_[r]};
  const double nl[2] = {pl0_[r], pl1_[r]}, nr[2] = {pr0_[r], pr1_[r]};
  if (detail::handoff_pieces(*h_, wys_[r], na, nb, 4 * g_.cell_mm, 2, ol, orr, 2, nl, nr))
    inner(na, nb, c0, c1, e0, e1);
}

// Lowers cells [i0, i1] of row j but [e0, e1]; adds the removed volume to removed.
void RowSweep::cut_row(int j, double y, int i0, int i1, int e0, int e1, double& removed) {
  thread_local std::vector<float> heap_buf;
  const int n = i1 - i0 + 1;
  float* buf = stack_buf_;
  if (n > stack_cells) {
    heap_buf.resize(static_cast<std::size_t>(n));
    buf = heap_buf.data();
  }
  // A gap of a few cells costs more (a second run of spans) than it saves.
  if (e1 - e0 < 4) {
    cut_cells(j, y, i0, i1, buf, removed);
    return;
  }
  cut_cells(j, y, i0, e0 - 1, buf, removed);
  cut_cells(j, y, e1 + 1, i1, buf, removed);
}

// Lowers cells [a, b] of row j, span by span: a span whose stock lies below the
// tool's lowest possible surface over it (LineSweep::span_floor, less the row
// skip's margin) is left alone, as the row skip leaves a row. In a finishing
// pass that is most of a row: under and behind the tool the moves before have
// cut deeper; only the cells ahead of it stand in its way. Runs of spans to cut
// go to the row kernels in one call each.
void RowSweep::cut_cells(int j, double y, int a, int b, float* buf, double& removed) {
  auto reaches = [&](int k0, int k1) {
    const float floor = static_cast<float>(s_.span_floor(y, z_.cx(k0), z_.cx(k1)) - kRowSkipMargin_mm);
    return z_.cells_above(j, k0, k1, floor);
  };
  int k = a;
  while (k <= b) {
    int end = std::min(b, k + kSpanCells - 1);
    if (!reaches(k, end)) {
      k = end + 1;
      continue;
    }
    // Extend the run while the next span needs cutting too.
    int next_end = 0;
    while (end < b && reaches(end + 1, next_end = std::min(b, end + kSpanCells))) end = next_end;
    const int n = end - k + 1;
    cells_ += static_cast<std::uint64_t>(n);
    s_.row_heights(y, g_.x0_mm, g_.cell_mm, k, n, buf);
    removed += z_.lower_row(j, k, n, buf);
    // The span after the run (if any) was found not to need cutting.
    k = end < b ? std::min(b, end + kSpanCells) + 1 : end + 1;
  }
}

bool RowSweep::chunk_below(int jc, int jn) const {
  const double ya = z_.cy(jc), yb = z_.cy(jc + jn - 1);
  // The chunk's row nearest the segment's Y range has the lowest floor.
  const double nearest = std::clamp(std::min(s_.a()[1], s_.b()[1]), ya, yb);
  const double floor = s_.row_floor(nearest) - kRowSkipMargin_mm;
  return z_.none_above(s_.x_min(), ya, s_.x_max(), yb, static_cast<float>(floor));
}

double RowSweep::rows(int j0, int j1) {
  j0 = std::max({j0, 0, z_.iy(s_.y_min())});
  j1 = std::min({j1, g_.ny - 1, z_.iy(s_.y_max())});
  double removed = 0;
  // Rows in chunks: the row ranges of this move (unless known) and of next come
  // from row_ranges, several rows per step.
  for (int jc = j0; jc <= j1; jc += chunk) {
    const int jn = std::min(j1 - jc + 1, chunk);
    // The whole chunk left alone when no stock over the footprint's width
    // stands above the tool's lowest possible surface on its rows (the floor of
    // its row nearest the segment): no row ranges are computed for it. A ball
    // reaches few rows far from its path; a finishing pass has cut the rest.
    if (chunk_below(jc, jn)) continue;
    for (int r = 0; r < jn; ++r) ys_[r] = z_.cy(jc + r);
    if (!mine_) s_.row_ranges(ys_, jn, sa_, sb_, sok_, start_cut_);
    q0_ = q1_ = 0;
    if (h_) next_ranges(jc, jn);
    for (int r = 0; r < jn; ++r) {
      const int j = jc + r;
      const double y = ys_[r];
      int i0, i1;
      if (!row_cells(r, j, i0, i1) || i1 < i0) continue;
      // Nothing on this row stands above the tool: in a finishing raster, the
      // rows on the side the pass before has cut (about half the footprint).
      // The margin is far above the rounding of the row kernels, so every height
      // they would compute stays above every cell and the row is left as it is.
      if (!z_.row_above(j, i0, i1, static_cast<float>(s_.row_floor(y) - kRowSkipMargin_mm))) continue;
      int e0, e1;
      left_out(r, i0, i1, e0, e1);
      cut_row(j, y, i0, i1, e0, e1, removed);
    }
  }
  return removed;
}

// The work of every sweep in the process (sweep_work()): one addition per
// sweep call, not per row, so that counting costs nothing measurable.
std::atomic<std::uint64_t> g_moves{0}, g_cells{0};

// A band's or a whole move's sweep: the removed volume and the cells computed.
struct Swept {
  double removed_mm3 = 0;
  std::uint64_t cells = 0;
  Swept& operator+=(const Swept& o) {
    removed_mm3 += o.removed_mm3;
    cells += o.cells;
    return *this;
  }
};

Swept sweep_rows(ZMap& z, const LineSweep& s, int j0, int j1, bool start_cut, const LineSweep* next = nullptr,
                 const Handoff* h = nullptr, const RowCache* mine = nullptr, RowCache* theirs = nullptr) {
  RowSweep sweep(z, s, start_cut, next, h, mine, theirs);
  const double removed = sweep.rows(j0, j1);
  return {removed, sweep.cells()};
}

double counted(const Swept& w, std::size_t moves) {
  g_moves.fetch_add(moves, std::memory_order_relaxed);
  g_cells.fetch_add(w.cells, std::memory_order_relaxed);
  return w.removed_mm3;
}

}  // namespace

SweepWork sweep_work() { return {g_moves.load(std::memory_order_relaxed), g_cells.load(std::memory_order_relaxed)}; }

double sweep_line(ZMap& z, const LineSweep& s, bool start_cut) {
  return counted(sweep_rows(z, s, 0, z.grid().ny - 1, start_cut), 1);
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
    for (int i = i0; i <= i1; ++i) buf[static_cast<std::size_t>(i - i0)] = detail::to_cell(s.lower_height(z.cx(i), y));
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
  for (std::size_t k = 0; k + 1 < s.size(); ++k)
    has[k] = chained(k + 1) && detail::make_handoff(s[k], s[k + 1], hand[k]);
  // One task per tile row: lower_row on different tile rows never shares a tile.
  diag::TracedLoop loop;
  const Swept w = tbb::parallel_reduce(
      tbb::blocked_range<int>(j0 / T, j1 / T + 1, 1), Swept{},
      [&](const tbb::blocked_range<int>& r, Swept acc) {
        RowCache cache[2];
        for (int band = r.begin(); band != r.end(); ++band) loop.task([&] {
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
        });
        return acc;
      },
      [](Swept a, const Swept& b) { return a += b; });
  return counted(w, s.size());
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
