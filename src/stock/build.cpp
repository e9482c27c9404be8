#include "deflex/stock/build.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stock/zmap_file.hpp"

namespace deflex::stock {

namespace {
constexpr int T = ZMap::tile_cells;

double parse_number(std::string_view s, std::string_view whole) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  double v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v))
    throw Error(ErrorKind::settings, "stock: bad number '" + std::string(s) + "' in '" + std::string(whole) +
                                 "' (expected box:X0,Y0,Z0,X1,Y1,Z1 in mm)");
  return v;
}
}  // namespace

BoxSpec parse_box(std::string_view spec) {
  const std::string_view whole = spec;
  if (spec.substr(0, 4) != "box:")
    throw Error(ErrorKind::settings, "stock: '" + std::string(whole) + "' is not box:X0,Y0,Z0,X1,Y1,Z1");
  spec.remove_prefix(4);
  double v[6];
  for (int k = 0; k < 6; ++k) {
    const auto comma = spec.find(',');
    if ((k < 5) != (comma != std::string_view::npos))
      throw Error(ErrorKind::settings, "stock: '" + std::string(whole) + "' needs exactly six numbers X0,Y0,Z0,X1,Y1,Z1");
    v[k] = parse_number(spec.substr(0, comma), whole);
    spec.remove_prefix(comma == std::string_view::npos ? spec.size() : comma + 1);
  }
  BoxSpec b{std::min(v[0], v[3]), std::min(v[1], v[4]), std::min(v[2], v[5]),
            std::max(v[0], v[3]), std::max(v[1], v[4]), std::max(v[2], v[5])};
  if (b.x1_mm - b.x0_mm <= 0 || b.y1_mm - b.y0_mm <= 0 || b.z1_mm - b.z0_mm <= 0)
    throw Error(ErrorKind::settings, "stock: box '" + std::string(whole) + "' has zero size");
  return b;
}

ZMap zmap_from_box(const BoxSpec& b, double cell_mm) {
  // A box from the command line: its size is a usage error, found before allocating.
  const double nx = std::ceil((b.x1_mm - b.x0_mm) / cell_mm), ny = std::ceil((b.y1_mm - b.y0_mm) / cell_mm);
  if (!(nx * ny <= max_cells)) throw Error(ErrorKind::settings, too_many_cells(b.x1_mm - b.x0_mm, b.y1_mm - b.y0_mm, cell_mm));
  const GridSpec g = grid_covering(b.x0_mm, b.y0_mm, b.x1_mm, b.y1_mm, cell_mm);
  const float top = static_cast<float>(b.z1_mm);
  ZMap z(g, top, b.z0_mm);
  // Overhanging last column / row: empty where the centre is outside the box.
  if (z.cx(g.nx - 1) > b.x1_mm)
    for (int j = 0; j < g.ny; ++j) z.set(g.nx - 1, j, no_material);
  if (z.cy(g.ny - 1) > b.y1_mm)
    for (int i = 0; i < g.nx; ++i) z.set(i, g.ny - 1, no_material);
  return z;
}

namespace {

// The triangles whose XY box meets each tile of z (indices, tiles row by row).
std::vector<std::vector<std::uint32_t>> tile_bins(std::span<const Triangle> tris, const ZMap& z) {
  const GridSpec& g = z.grid();
  const std::size_t tx = z.tiles_x(), ty = z.tiles_y();
  std::vector<std::vector<std::uint32_t>> bins(tx * ty);
  for (std::size_t k = 0; k < tris.size(); ++k) {
    const Triangle& t = tris[k];
    const double x0 = std::min({t.p[0][0], t.p[1][0], t.p[2][0]}), x1 = std::max({t.p[0][0], t.p[1][0], t.p[2][0]});
    const double y0 = std::min({t.p[0][1], t.p[1][1], t.p[2][1]}), y1 = std::max({t.p[0][1], t.p[1][1], t.p[2][1]});
    const int i0 = std::clamp(z.ix(x0), 0, g.nx - 1) / T, i1 = std::clamp(z.ix(x1), 0, g.nx - 1) / T;
    const int j0 = std::clamp(z.iy(y0), 0, g.ny - 1) / T, j1 = std::clamp(z.iy(y1), 0, g.ny - 1) / T;
    for (int tj = j0; tj <= j1; ++tj)
      for (int ti = i0; ti <= i1; ++ti)
        bins[static_cast<std::size_t>(tj) * tx + ti].push_back(static_cast<std::uint32_t>(k));
  }
  return bins;
}

// Raises the cells of the tile from cell (ci0, cj0) (buf, T x T) under the
// triangle t to its height, skipped when its highest vertex top_mm is not above
// any cell of its box.
void raise_under(const ZMap& z, const Triangle& t, double top_mm, int ci0, int cj0, std::vector<float>& buf) {
  const GridSpec& g = z.grid();
  const auto& p = t.p;
  // Barycentric coordinates over the XY projection; vertical facets
  // (zero projected area) are covered by their neighbours.
  const double d = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
  if (std::fabs(d) < 1e-18) return;
  const double x0 = std::min({p[0][0], p[1][0], p[2][0]}), x1 = std::max({p[0][0], p[1][0], p[2][0]});
  const double y0 = std::min({p[0][1], p[1][1], p[2][1]}), y1 = std::max({p[0][1], p[1][1], p[2][1]});
  const int i0 = std::max(ci0, static_cast<int>(std::ceil((x0 - g.x0_mm) / g.cell_mm - 0.5)));
  const int i1 = std::min({ci0 + T - 1, g.nx - 1, static_cast<int>(std::floor((x1 - g.x0_mm) / g.cell_mm - 0.5))});
  const int j0 = std::max(cj0, static_cast<int>(std::ceil((y0 - g.y0_mm) / g.cell_mm - 0.5)));
  const int j1 = std::min({cj0 + T - 1, g.ny - 1, static_cast<int>(std::floor((y1 - g.y0_mm) / g.cell_mm - 0.5))});
  if (i0 > i1 || j0 > j1) return;
  float lowest = std::numeric_limits<float>::infinity();
  for (int j = j0; j <= j1; ++j) {
    const float* row = buf.data() + static_cast<std::size_t>(j - cj0) * T - ci0;
    for (int i = i0; i <= i1; ++i) lowest = std::min(lowest, row[i]);
  }
  // The interpolated height exceeds the highest vertex by rounding at most
  // (1e-12 barycentric slack): with this margin, and float rounding being
  // monotone, it cannot exceed `lowest`, so the skip is exact.
  if (top_mm + 1e-9 * (1 + std::fabs(top_mm)) < static_cast<double>(lowest)) return;
  // A tiny tolerance so that a centre on a shared edge belongs to both triangles.
  constexpr double eps = -1e-12;
  for (int j = j0; j <= j1; ++j) {
    const double y = z.cy(j);
    for (int i = i0; i <= i1; ++i) {
      const double x = z.cx(i);
      const double l1 = ((x - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (y - p[0][1])) / d;
      const double l2 = ((p[1][0] - p[0][0]) * (y - p[0][1]) - (x - p[0][0]) * (p[1][1] - p[0][1])) / d;
      const double l0 = 1 - l1 - l2;
      if (l0 < eps || l1 < eps || l2 < eps) continue;
      const float h = static_cast<float>(l0 * p[0][2] + l1 * p[1][2] + l2 * p[2][2]);
      float& c = buf[static_cast<std::size_t>(j - cj0) * T + (i - ci0)];
      c = std::max(c, h);
    }
  }
}

}  // namespace

ZMap zmap_from_triangles(std::span<const Triangle> tris, double cell_mm) {
  if (tris.empty()) throw Error(ErrorKind::config, "stock: the solid has no triangles");
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::numeric_limits<double>::infinity();
    hi[a] = -lo[a];
  }
  for (const Triangle& t : tris)
    for (const auto& p : t.p)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], p[a]);
        hi[a] = std::max(hi[a], p[a]);
      }
  ZMap z(grid_covering(lo[0], lo[1], hi[0], hi[1], cell_mm), no_material, lo[2]);
  // Bin the triangles by tile, then rasterise one tile at a time, so the only
  // dense memory is one tile (a 500 x 500 mm part never needs a full raster).
  std::vector<std::vector<std::uint32_t>> bins = tile_bins(tris, z);
  std::vector<float> buf(static_cast<std::size_t>(T) * T);
  // Highest vertex per triangle: a tile's triangles go highest first, and one
  // whose highest vertex is not above any cell of its box cannot raise a cell
  // (the bottom and the sides of a closed solid, under its top): skipped after
  // a float-only scan of the box instead of a barycentric test per cell.
  std::vector<double> top(tris.size());
  for (std::size_t k = 0; k < tris.size(); ++k) top[k] = std::max({tris[k].p[0][2], tris[k].p[1][2], tris[k].p[2][2]});
  const std::size_t tx = z.tiles_x(), ty = z.tiles_y();
  for (std::size_t by = 0; by < ty; ++by)
    for (std::size_t bx = 0; bx < tx; ++bx) {
      auto& bin = bins[by * tx + bx];
      if (bin.empty()) continue;  // stays empty
      std::sort(bin.begin(), bin.end(), [&](std::uint32_t a, std::uint32_t b) { return top[a] > top[b]; });
      std::fill(buf.begin(), buf.end(), no_material);
      for (std::uint32_t k : bin)
        raise_under(z, tris[k], top[k], static_cast<int>(bx) * T, static_cast<int>(by) * T, buf);
      z.assign_tile(bx, by, buf.data());
    }
  return z;
}

ZMap zmap_from_solid_file(const std::string& path, const SolidOptions& o) {
  const std::vector<Triangle> tris = read_solid_triangles(path, o.mesh_deflection_mm);
  return zmap_from_triangles(tris, o.cell_mm);
}

ZMap make_stock(const std::string& spec, const SolidOptions& o) {
  if (spec.rfind("box:", 0) == 0) return zmap_from_box(parse_box(spec), o.cell_mm);
  if (is_zmap_path(spec)) return zmap_from_file(spec, o.cell_mm);
  return zmap_from_solid_file(spec, o);
}

}  // namespace deflex::stock
