// The Z-map as a closed, reduced triangle mesh and binary STL
// (include/deflex/stock/mesh_out.hpp).
#include "deflex/stock/mesh_out.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <span>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::stock {
namespace {

// The vertex grid: (nx + 2) x (ny + 2) positions, the cell centres plus a ring
// on the grid's outline; quads between them (nx + 1) x (ny + 1).
struct Vertices {
  const ZMap& z;
  int vx, vy;      // vertex counts
  double floor_z;  // where cells without material lie
  double x(int i) const {
    const GridSpec& g = z.grid();
    return i == 0 ? g.x0_mm : i == vx - 1 ? g.x0_mm + g.nx * g.cell_mm : z.cx(i - 1);
  }
  double y(int j) const {
    const GridSpec& g = z.grid();
    return j == 0 ? g.y0_mm : j == vy - 1 ? g.y0_mm + g.ny * g.cell_mm : z.cy(j - 1);
  }
  double h(int i, int j) const {
    const float v = z.at(std::clamp(i - 1, 0, z.grid().nx - 1), std::clamp(j - 1, 0, z.grid().ny - 1));
    return v == no_material || v < floor_z ? floor_z : static_cast<double>(v);
  }
  std::array<double, 3> p(int i, int j) const { return {x(i), y(j), h(i, j)}; }
};

struct Leaf {
  int i0, j0, s;  // quads [i0, i0 + s) x [j0, j0 + s)
};

struct Stats {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  bool inside = true;  // the node lies within the quad grid
};

using Corner = std::pair<int, int>;  // a vertex of the grid

// Whether the triangles `tris` (covering the square [i0, i0 + s]^2 of vertices)
// pass within `limit` of every vertex height in it; stops at the first that does not.
bool fits(const Vertices& v, int i0, int j0, int s, std::span<const std::array<Corner, 3>> tris, double limit) {
  struct Plane {
    std::array<double, 3> a, b, c;
    double d;
  };
  std::array<Plane, 4> planes;
  for (std::size_t k = 0; k < tris.size(); ++k) {
    const auto& t = tris[k];
    Plane& p = planes[k];
    p.a = v.p(t[0].first, t[0].second), p.b = v.p(t[1].first, t[1].second), p.c = v.p(t[2].first, t[2].second);
    p.d = (p.b[0] - p.a[0]) * (p.c[1] - p.a[1]) - (p.c[0] - p.a[0]) * (p.b[1] - p.a[1]);
  }
  for (int j = j0; j <= j0 + s; ++j)
    for (int i = i0; i <= i0 + s; ++i) {
      const double x = v.x(i), y = v.y(j);
      for (std::size_t k = 0; k < tris.size(); ++k) {
        const auto& [a, b, c, d] = planes[k];
        const double l1 = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / d;
        const double l2 = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / d;
        if (l1 < -1e-9 || l2 < -1e-9 || l1 + l2 > 1 + 1e-9) continue;
        if (std::fabs((1 - l1 - l2) * a[2] + l1 * b[2] + l2 * c[2] - v.h(i, j)) > limit) return false;
        break;
      }
    }
  return true;
}

// Whether a square of s >= 2 quads may be one leaf. Its triangles are two
// (split along the diagonal from (i0, j0)) where no neighbour puts a vertex on
// its sides, else a fan from its centre through every vertex on them. Flat
// within `tol`: any triangles over its vertices stay in that band. Else both
// forms must fit: the split within `tol`; the fan within tol / 2, because a
// vertex p a neighbour adds on a side lies within tol / 2 of the fan, and the
// finer fan differs from the coarse one by a function linear on each new
// triangle, zero at the centre and the corners, at most |h(p) - fan(p)| at p:
// within tol / 2 + tol / 2 of every height. So sloped and gently curved
// surfaces merge too, not only level ones.
bool one_leaf(const Vertices& v, int i0, int j0, int s, double lo, double hi, double tol) {
  if (hi - lo <= tol) return true;
  const Corner a{i0, j0}, b{i0 + s, j0}, c{i0 + s, j0 + s}, d{i0, j0 + s}, m{i0 + s / 2, j0 + s / 2};
  const std::array<std::array<Corner, 3>, 2> split{{{a, b, c}, {a, c, d}}};
  const std::array<std::array<Corner, 3>, 4> fan{{{m, a, b}, {m, b, c}, {m, c, d}, {m, d, a}}};
  return fits(v, i0, j0, s, split, tol) && fits(v, i0, j0, s, fan, tol / 2);
}

// Post-order quadtree: a node whose four children were leaves becomes one
// leaf where one_leaf() allows it.
Stats build(const Vertices& v, int i0, int j0, int s, double tol, std::vector<Leaf>& leaves) {
  const int qx = v.vx - 1, qy = v.vy - 1;
  Stats st;
  if (i0 >= qx || j0 >= qy) {
    st.inside = false;
    return st;
  }
  if (s == 1) {
    for (int dj = 0; dj <= 1; ++dj)
      for (int di = 0; di <= 1; ++di) {
        const double h = v.h(i0 + di, j0 + dj);
        st.lo = std::min(st.lo, h);
        st.hi = std::max(st.hi, h);
      }
    leaves.push_back({i0, j0, 1});
    return st;
  }
  const std::size_t before = leaves.size();
  const int h = s / 2;
  for (const auto& [di, dj] : {std::pair(0, 0), std::pair(h, 0), std::pair(0, h), std::pair(h, h)}) {
    const Stats c = build(v, i0 + di, j0 + dj, h, tol, leaves);
    st.lo = std::min(st.lo, c.lo);
    st.hi = std::max(st.hi, c.hi);
    st.inside = st.inside && c.inside;
  }
  if (st.inside && i0 + s <= qx && j0 + s <= qy && leaves.size() == before + 4 &&
      one_leaf(v, i0, j0, s, st.lo, st.hi, tol)) {
    leaves.resize(before);
    leaves.push_back({i0, j0, s});
  }
  return st;
}

}  // namespace

std::vector<Triangle> zmap_mesh(const ZMap& z, double tol) {
  const GridSpec& g = z.grid();
  Vertices v{z, g.nx + 2, g.ny + 2, 0};
  double lowest = z.base_z_mm();
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      if (const float h = z.at(i, j); h != no_material) lowest = std::min(lowest, static_cast<double>(h));
  v.floor_z = std::min(lowest, z.base_z_mm());
  const double bottom = v.floor_z - 0.01;
  const int qx = v.vx - 1, qy = v.vy - 1;
  int size = 1;
  while (size < std::max(qx, qy)) size *= 2;
  std::vector<Leaf> leaves;
  build(v, 0, 0, size, tol, leaves);
  // Every leaf corner is a vertex of the mesh; a leaf's fan takes all of them on its sides.
  std::vector<std::uint8_t> used(static_cast<std::size_t>(v.vx) * v.vy, 0);
  auto mark = [&](int i, int j) { used[static_cast<std::size_t>(j) * v.vx + i] = 1; };
  auto is_used = [&](int i, int j) { return used[static_cast<std::size_t>(j) * v.vx + i] != 0; };
  for (const Leaf& l : leaves) {
    mark(l.i0, l.j0), mark(l.i0 + l.s, l.j0), mark(l.i0, l.j0 + l.s), mark(l.i0 + l.s, l.j0 + l.s);
  }
  std::vector<Triangle> out;
  std::vector<std::pair<int, int>> ring;
  for (const Leaf& l : leaves) {
    // The perimeter counter-clockwise seen from above.
    ring.clear();
    for (int i = l.i0; i < l.i0 + l.s; ++i) if (is_used(i, l.j0)) ring.emplace_back(i, l.j0);
    for (int j = l.j0; j < l.j0 + l.s; ++j) if (is_used(l.i0 + l.s, j)) ring.emplace_back(l.i0 + l.s, j);
    for (int i = l.i0 + l.s; i > l.i0; --i) if (is_used(i, l.j0 + l.s)) ring.emplace_back(i, l.j0 + l.s);
    for (int j = l.j0 + l.s; j > l.j0; --j) if (is_used(l.i0, j)) ring.emplace_back(l.i0, j);
    if (ring.size() == 4) {
      out.push_back({{v.p(ring[0].first, ring[0].second), v.p(ring[1].first, ring[1].second), v.p(ring[2].first, ring[2].second)}});
      out.push_back({{v.p(ring[0].first, ring[0].second), v.p(ring[2].first, ring[2].second), v.p(ring[3].first, ring[3].second)}});
      continue;
    }
    const auto c = v.p(l.i0 + l.s / 2, l.j0 + l.s / 2);
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const auto& a = ring[k];
      const auto& b = ring[(k + 1) % ring.size()];
      out.push_back({{c, v.p(a.first, a.second), v.p(b.first, b.second)}});
    }
  }
  // The walls around the outline (counter-clockwise from above: outward to the right) and the bottom.
  ring.clear();
  for (int i = 0; i < qx; ++i) if (is_used(i, 0)) ring.emplace_back(i, 0);
  for (int j = 0; j < qy; ++j) if (is_used(qx, j)) ring.emplace_back(qx, j);
  for (int i = qx; i > 0; --i) if (is_used(i, qy)) ring.emplace_back(i, qy);
  for (int j = qy; j > 0; --j) if (is_used(0, j)) ring.emplace_back(0, j);
  const std::array<double, 3> centre{(v.x(0) + v.x(qx)) / 2, (v.y(0) + v.y(qy)) / 2, bottom};
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const auto a = v.p(ring[k].first, ring[k].second);
    const auto b = v.p(ring[(k + 1) % ring.size()].first, ring[(k + 1) % ring.size()].second);
    const std::array<double, 3> A{a[0], a[1], bottom}, B{b[0], b[1], bottom};
    out.push_back({{a, A, B}});
    out.push_back({{a, B, b}});
    out.push_back({{centre, B, A}});
  }
  return out;
}

void write_binary_stl(std::ostream& out, const std::vector<Triangle>& tris, const std::string& header) {
  char head[80] = {};
  std::memcpy(head, header.data(), std::min<std::size_t>(header.size(), 79));
  out.write(head, 80);
  const std::uint32_t n = static_cast<std::uint32_t>(tris.size());
  char b[4];
  std::memcpy(b, &n, 4);  // STL is little-endian, as x86-64 and arm64 are
  out.write(b, 4);
  std::vector<char> buf;
  buf.reserve(tris.size() * 50);
  auto put = [&](float f) {
    char c[4];
    std::memcpy(c, &f, 4);
    buf.insert(buf.end(), c, c + 4);
  };
  for (const Triangle& t : tris) {
    const Eigen::Vector3d a(t.p[0][0], t.p[0][1], t.p[0][2]), bb(t.p[1][0], t.p[1][1], t.p[1][2]),
        c(t.p[2][0], t.p[2][1], t.p[2][2]);
    const Eigen::Vector3d nrm = (bb - a).cross(c - a).normalized();
    for (int k = 0; k < 3; ++k) put(static_cast<float>(nrm[k]));
    for (const auto& p : t.p)
      for (int k = 0; k < 3; ++k) put(static_cast<float>(p[k]));
    buf.push_back(0), buf.push_back(0);
  }
  out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  if (!out) throw Error(ErrorKind::io, "writing the STL failed");
}

std::vector<BoxSpec> zmap_boxes(const ZMap& z, double step_mm) {
  const GridSpec& g = z.grid();
  const double base = z.base_z_mm();
  // The rounded height of a cell in steps above the base; 0: no box.
  auto level = [&](int i, int j) -> long {
    const double h = z.at(i, j);
    if (!(h > base)) return 0;
    return std::max(1L, std::lround((h - base) / step_mm));
  };
  std::vector<char> done(static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny), 0);
  auto taken = [&](int i, int j) -> char& { return done[static_cast<std::size_t>(j) * static_cast<std::size_t>(g.nx) + static_cast<std::size_t>(i)]; };
  std::vector<BoxSpec> boxes;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const long l = taken(i, j) ? 0 : level(i, j);
      if (l == 0) continue;
      int w = 1;
      while (i + w < g.nx && !taken(i + w, j) && level(i + w, j) == l) ++w;
      int rows = 1;
      for (; j + rows < g.ny; ++rows) {
        bool same = true;
        for (int k = i; k < i + w && same; ++k) same = !taken(k, j + rows) && level(k, j + rows) == l;
        if (!same) break;
      }
      for (int r = 0; r < rows; ++r)
        for (int k = i; k < i + w; ++k) taken(k, j + r) = 1;
      boxes.push_back({g.x0_mm + i * g.cell_mm, g.y0_mm + j * g.cell_mm, base, g.x0_mm + (i + w) * g.cell_mm,
                       g.y0_mm + (j + rows) * g.cell_mm, base + static_cast<double>(l) * step_mm});
    }
  return boxes;
}

}  // namespace deflex::stock
