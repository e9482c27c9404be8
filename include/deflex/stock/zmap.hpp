// Z-map stock model: a heightfield over a regular XY grid, exact for 3-axis
// milling with a vertical tool (every removal is "the material above the tool's
// lower surface goes away", so a column of material stays a column).
//
// Frame: the active work frame of the program (X, Y, Z in mm, Z up). Cell (i, j)
// covers x in [x0 + i c, x0 + (i+1) c), y in [y0 + j c, y0 + (j+1) c) and stores the
// height of the material at its centre; material fills [base_z, height] there.
// A height of -inf means "no material" (outside the blank or cut through).
//
// Storage: square tiles of tile_cells x tile_cells floats, allocated on the first
// write that changes a tile; an untouched tile is one float (its uniform height).
// Floats keep 0.03 µm resolution at |z| = 500 mm, half the memory of doubles.
//
// Resolution: default_cell_mm = 0.05 mm. That resolves a finishing step-over of
// 0.3-0.5 mm with 6-10 cells and scallop walls to +-0.025 mm, at 4 bytes per
// cell: a fully cut 500 x 500 mm stock is 10^8 cells = 400 MB (worst case, every
// tile allocated). 0.1 mm (100 MB, 4x faster sweeps) suits roughing; 0.02 mm
// (2.5 GB for 500 x 500) only small parts. Memory and sweep time grow as 1/c^2.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace deflex::stock {

inline constexpr double default_cell_mm = 0.05;
inline constexpr float no_material = -std::numeric_limits<float>::infinity();

struct GridSpec {
  double x0_mm = 0, y0_mm = 0;  // lower-left corner of cell (0, 0)
  double cell_mm = default_cell_mm;
  int nx = 0, ny = 0;           // cell counts
};

// A grid of cell size cell_mm covering [x0, x1] x [y0, y1] (cells overhang x1, y1).
// Most cells a Z-map may have: 2^30 (1.6 m x 1.6 m at 0.05 mm). Tiles are
// allocated as the tool reaches them, but a cut across a larger map would not fit
// in memory, and the counts must stay ints.
inline constexpr double max_cells = 1073741824.0;
// Why a grid is refused: its size, cell count and the limit.
std::string too_many_cells(double dx_mm, double dy_mm, double cell_mm);
// Throws Error(config) for an empty extent or more than max_cells cells.
GridSpec grid_covering(double x0_mm, double y0_mm, double x1_mm, double y1_mm, double cell_mm);

class ZMap {
 public:
  static constexpr int tile_cells = 64;  // tile side, cells (16 KiB of floats)

  // Every cell starts at `height` (no_material for an empty map); material rests on base_z_mm.
  ZMap(const GridSpec& g, float height, double base_z_mm);

  const GridSpec& grid() const { return g_; }
  double base_z_mm() const { return base_z_; }

  // An independent copy, every cell as it is (the map is move-only: a copy
  // of a large stock is never made by accident).
  ZMap clone() const;

  // Cell index of a coordinate (may be outside [0, n)).
  int ix(double x_mm) const { return fast_floor((x_mm - g_.x0_mm) * inv_cell_); }
  int iy(double y_mm) const { return fast_floor((y_mm - g_.y0_mm) * inv_cell_); }
  double cx(int i) const { return g_.x0_mm + (i + 0.5) * g_.cell_mm; }  // cell centre
  double cy(int j) const { return g_.y0_mm + (j + 0.5) * g_.cell_mm; }
  bool inside(int i, int j) const { return i >= 0 && j >= 0 && i < g_.nx && j < g_.ny; }

  float at(int i, int j) const {  // requires inside(i, j)
    const Tile& t = tiles_[tile_index(i, j)];
    return t.cells ? t.cells[local(i, j)] : t.uniform;
  }
  // Height of the cell containing (x, y); no_material outside the grid.
  float height_at(double x_mm, double y_mm) const {
    const int i = ix(x_mm), j = iy(y_mm);
    return inside(i, j) ? at(i, j) : no_material;
  }
  // Bilinear interpolation between the four nearest cell centres, so smooth cut
  // surfaces (ball scallops) are resolved to O(c^2) instead of O(c); falls back to
  // the containing cell next to empty cells (a vertical wall stays a step).
  // Inline for the common case, four cells of one tile (the engagement calls it
  // tens of millions of times per program); height_smooth_general does the rest.
  // Both read the same cells and blend them with bilinear(), so the result does
  // not depend on the path.
  double height_smooth(double x_mm, double y_mm) const {
    const double u = (x_mm - g_.x0_mm) * inv_cell_ - 0.5, v = (y_mm - g_.y0_mm) * inv_cell_ - 0.5;
    const int i = fast_floor(u), j = fast_floor(v);
    if (i >= 0 && j >= 0 && i + 1 < g_.nx && j + 1 < g_.ny) {
      const unsigned li = static_cast<unsigned>(i) % tile_cells, lj = static_cast<unsigned>(j) % tile_cells;
      if (li + 1 < tile_cells && lj + 1 < tile_cells) {
        const Tile& t = tiles_[tile_index(i, j)];
        if (const float* c = t.cells.get()) {
          c += lj * tile_cells + li;
          const float h00 = c[0], h10 = c[1], h01 = c[tile_cells], h11 = c[tile_cells + 1];
          if (h00 != no_material && h10 != no_material && h01 != no_material && h11 != no_material)
            return bilinear(u - i, v - j, h00, h10, h01, h11);
        } else if (t.uniform != no_material) {
          return bilinear(u - i, v - j, t.uniform, t.uniform, t.uniform, t.uniform);
        }
      }
    }
    return height_smooth_general(x_mm, y_mm);
  }
  // Asks the cache for the cells height_smooth(x, y) reads (a hint, no effect on
  // any result), so that a batch of lookups waits for memory once, not per lookup.
  void prefetch_smooth(double x_mm, double y_mm) const {
#ifdef __GNUC__
    const int i = fast_floor((x_mm - g_.x0_mm) * inv_cell_ - 0.5), j = fast_floor((y_mm - g_.y0_mm) * inv_cell_ - 0.5);
    if (i < 0 || j < 0 || i + 1 >= g_.nx || j + 1 >= g_.ny) return;
    if (const float* c = tiles_[tile_index(i, j)].cells.get()) {
      c += local(i, j);
      __builtin_prefetch(c);
      __builtin_prefetch(c + tile_cells + 1);
    }
#else
    (void)x_mm;
    (void)y_mm;
#endif
  }
  void set(int i, int j, float h);

  // Lowers row j, cells [i0, i0 + n), to min(current, h[k]). Returns the removed
  // volume, mm^3 (cells at no_material contribute nothing; the base clips).
  // Touches only the tiles of row j's tile row: calls on different tile rows
  // (j / tile_cells) may run concurrently.
  double lower_row(int j, int i0, int n, const float* h);

  // An upper bound of the heights in the cells overlapping [x0,x1] x [y0,y1]
  // (exact per tile row band; no_material when the rectangle misses the grid).
  float max_height_in(double x0_mm, double y0_mm, double x1_mm, double y1_mm) const;
  // Whether any cell of row j in [i0, i1] may stand above h, by the row maxima
  // of the tiles the range touches (an upper bound: false proves none does).
  bool row_above(int j, int i0, int i1, float h) const {
    const Tile* t = &tiles_[tile_index(i0, j)];
    const Tile* end = t + (i1 / tile_cells - i0 / tile_cells) + 1;
    const std::size_t r = static_cast<std::size_t>(j % tile_cells);
    for (; t != end; ++t) {
      if (t->max <= h) continue;
      if (!t->cells || t->cells[static_cast<std::size_t>(tile_cells) * tile_cells + r] > h) return true;
    }
    return false;
  }
  // Whether any cell of row j in [i0, i1] stands above h, cell by cell (exact;
  // row_above first, when the tile's row maximum settles it).
  bool cells_above(int j, int i0, int i1, float h) const;
  // max_height_in(...) <= h, stopping at the first tile above h: the cheap way to
  // prove that a region is above the stock.
  bool none_above(double x0_mm, double y0_mm, double x1_mm, double y1_mm, float h) const;

  // Tiles: tile (tx, ty) holds cells [tx T, tx T + T) x [ty T, ty T + T), T = tile_cells.
  std::size_t tiles_x() const { return tiles_x_; }
  std::size_t tiles_y() const { return tiles_y_; }
  // Replaces a tile's heights (T x T, row-major by j then i; entries outside the
  // grid are ignored); a tile whose cells are all equal stays unallocated.
  void assign_tile(std::size_t tx, std::size_t ty, const float* cells);

  std::size_t tile_count() const { return tiles_.size(); }
  std::size_t allocated_tiles() const;  // counted (no shared counter: bands of tile rows may be cut in parallel)
  std::size_t allocated_bytes() const;   // tiles + bookkeeping, bytes
  std::size_t worst_case_bytes() const;  // every tile allocated

 private:
  struct Tile {
    // null: every cell equals `uniform`; else tile_cells^2 heights (row-major)
    // followed by tile_cells row maxima.
    std::unique_ptr<float[]> cells;
    float uniform = no_material;
    float max = no_material;  // max of the heights (exact)
  };
  double height_smooth_general(double x_mm, double y_mm) const;  // every case
  static double bilinear(double fu, double fv, float h00, float h10, float h01, float h11) {
    return (1 - fv) * ((1 - fu) * h00 + fu * h10) + fv * ((1 - fu) * h01 + fu * h11);
  }
  static int fast_floor(double v) {
    const int i = static_cast<int>(v);
    return i - (v < i);
  }
  std::size_t tile_index(int i, int j) const {
    return static_cast<std::size_t>(j / tile_cells) * tiles_x_ + static_cast<std::size_t>(i / tile_cells);
  }
  static std::size_t local(int i, int j) {
    return static_cast<std::size_t>(j % tile_cells) * tile_cells + static_cast<std::size_t>(i % tile_cells);
  }
  float* materialize(Tile& t);

  GridSpec g_;
  double inv_cell_ = 1;
  double base_z_ = 0;
  std::size_t tiles_x_ = 0, tiles_y_ = 0;
  std::vector<Tile> tiles_;
};

}  // namespace deflex::stock
