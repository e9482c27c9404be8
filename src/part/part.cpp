// The part model: closest points through CGAL's AABB tree, crease-aware
// interpolated normals, and the cutter contact by alternating projections
// (include/deflex/part/part.hpp).
#include "deflex/part/part.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::part {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Tri3 = K::Triangle_3;
using TriIt = std::vector<Tri3>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, TriIt>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

V3 v3(const K::Point_3& p) { return {p.x(), p.y(), p.z()}; }
K::Point_3 pt(const V3& v) { return {v.x(), v.y(), v.z()}; }

// Barycentric coordinates of p (on the triangle's plane) in (a, b, c).
std::array<double, 3> barycentric(const V3& a, const V3& b, const V3& c, const V3& p) {
  const V3 v0 = b - a, v1 = c - a, v2 = p - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double den = d00 * d11 - d01 * d01;
  if (!(den > 0)) return {1.0, 0.0, 0.0};
  const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
  return {1.0 - v - w, v, w};
}

}  // namespace

struct PartModel::Impl {
  std::vector<Tri3> cgal;                    // the tree's primitives
  std::vector<std::array<std::uint32_t, 3>> face;  // vertex indices
  std::vector<V3> vertex;
  std::vector<V3> face_normal;               // geometric, outward, unit
  std::vector<std::array<V3, 3>> corner_normal;  // crease-aware vertex normals per face corner
  std::vector<std::uint8_t> crease_corner;   // bit i: a crease meets at corner i
  std::vector<std::uint8_t> crease_edge;     // bit i: the edge opposite corner i is a crease or a border
  // Angle-weighted pseudo-normals (Baerentzen & Aanaes 2005): the sign of a
  // distance whose closest point is on an edge or at a vertex is that of the
  // offset along the edge's (sum of its two facets' normals) or the vertex's
  // pseudo-normal; a facet's own normal there can give the wrong side.
  std::vector<std::array<V3, 3>> edge_pseudo;  // per face, the edge opposite corner i
  std::vector<V3> vertex_pseudo;
  Tree tree;
  double cos_crease = 0;
  double size_mm = 1;                        // bounding-box diagonal

  void build(const std::vector<stock::Triangle>& tris, double crease_deg);
  Contact closest(const V3& p) const;
  // The contact of the core point deepest in the part, from `best` on (see contact()).
  Contact deepest(const CutterShape& s, const V3& tip_mm, Contact best) const;
};

void PartModel::Impl::build(const std::vector<stock::Triangle>& tris, double crease_deg) {
  cos_crease = std::cos(crease_deg * std::numbers::pi / 180.0);
  // Shared vertices by exact coordinates: STL repeats each vertex per facet,
  // and the normals need the facets round a vertex. (A std::map over three
  // doubles is all that is needed; a mesh library's soup repair would also
  // reorient and stitch, which we do not want to happen silently.)
  std::map<std::array<double, 3>, std::uint32_t> index;
  for (const stock::Triangle& t : tris) {
    std::array<std::uint32_t, 3> f{};
    for (int c = 0; c < 3; ++c) {
      auto [it, fresh] = index.emplace(t.p[c], static_cast<std::uint32_t>(vertex.size()));
      if (fresh) vertex.emplace_back(t.p[c][0], t.p[c][1], t.p[c][2]);
      f[c] = it->second;
    }
    const V3 n = (vertex[f[1]] - vertex[f[0]]).cross(vertex[f[2]] - vertex[f[0]]);
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] || !(n.norm() > 1e-14)) continue;  // degenerate
    face.push_back(f);
    face_normal.push_back(n.normalized());
  }
  if (face.empty()) throw Error(ErrorKind::config, "part model: no triangles (or only degenerate ones)");
  std::vector<std::vector<std::uint32_t>> around(vertex.size());
  for (std::uint32_t i = 0; i < face.size(); ++i)
    for (std::uint32_t v : face[i]) around[v].push_back(i);
  // Angle of face f at its corner c (the weight of its normal at that vertex).
  auto angle = [&](std::uint32_t f, int c) {
    const V3 a = vertex[face[f][(c + 1) % 3]] - vertex[face[f][c]], b = vertex[face[f][(c + 2) % 3]] - vertex[face[f][c]];
    return std::atan2(a.cross(b).norm(), a.dot(b));
  };
  vertex_pseudo.assign(vertex.size(), V3::Zero());
  for (std::uint32_t f = 0; f < face.size(); ++f)
    for (int c = 0; c < 3; ++c) vertex_pseudo[face[f][c]] += angle(f, c) * face_normal[f];
  edge_pseudo.resize(face.size());
  corner_normal.resize(face.size());
  crease_corner.assign(face.size(), 0);
  crease_edge.assign(face.size(), 0);
  for (std::uint32_t f = 0; f < face.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      V3 sum = V3::Zero();
      for (std::uint32_t g : around[face[f][c]]) {
        if (face_normal[g].dot(face_normal[f]) >= cos_crease) {
          for (int cg = 0; cg < 3; ++cg)
            if (face[g][cg] == face[f][c]) sum += angle(g, cg) * face_normal[g];
        } else {
          crease_corner[f] |= static_cast<std::uint8_t>(1u << c);
        }
      }
      corner_normal[f][c] = sum.norm() > 0 ? V3(sum.normalized()) : face_normal[f];
      // The edge opposite corner c: a crease when the face across it turns by
      // more than crease_deg, a border when there is none.
      const std::uint32_t a = face[f][(c + 1) % 3], b = face[f][(c + 2) % 3];
      bool smooth = false;
      edge_pseudo[f][c] = face_normal[f];
      for (std::uint32_t g : around[a])
        if (g != f && std::find(face[g].begin(), face[g].end(), b) != face[g].end()) {
          smooth = face_normal[g].dot(face_normal[f]) >= cos_crease;
          edge_pseudo[f][c] += face_normal[g];
        }
      if (!smooth) crease_edge[f] |= static_cast<std::uint8_t>(1u << c);
    }
  }
  cgal.reserve(face.size());
  for (const auto& f : face) cgal.emplace_back(pt(vertex[f[0]]), pt(vertex[f[1]]), pt(vertex[f[2]]));
  tree.insert(cgal.begin(), cgal.end());
  tree.build();
  tree.accelerate_distance_queries();  // built now, not lazily on the first (threaded) query
  const auto bb = tree.bbox();
  size_mm = std::hypot(bb.xmax() - bb.xmin(), bb.ymax() - bb.ymin(), bb.zmax() - bb.zmin());
}

// The part point closest to p, its normal and whether it lies on a crease
// (there the normal is the direction from the part to p: p is a core point).
Contact PartModel::Impl::closest(const V3& p) const {
  const auto [qp, prim] = tree.closest_point_and_primitive(pt(p));
  const std::uint32_t f = static_cast<std::uint32_t>(prim - cgal.begin());
  Contact c;
  c.found = true;
  c.point_mm = v3(qp);
  const auto& fv = face[f];
  const std::array<double, 3> b = barycentric(vertex[fv[0]], vertex[fv[1]], vertex[fv[2]], c.point_mm);
  // On an edge or at a vertex (a barycentric coordinate ~0), is it sharp?
  const double eps = 1e-9;
  bool sharp = false;
  int zeros = 0;
  V3 pseudo = face_normal[f];
  for (int i = 0; i < 3; ++i)
    if (b[i] < eps) {
      ++zeros;
      pseudo = edge_pseudo[f][i];
      if (crease_edge[f] & (1u << i)) sharp = true;
    }
  if (zeros == 2)
    for (int i = 0; i < 3; ++i)
      if (b[i] >= eps) {
        pseudo = vertex_pseudo[fv[i]];
        if (crease_corner[f] & (1u << i)) sharp = true;
      }
  const V3 away = p - c.point_mm;
  const double dist = away.norm();
  const bool outside = away.dot(pseudo) >= 0;
  if (sharp && dist > 1e-9 * size_mm) {
    c.on_face = false;
    c.normal = outside ? V3(away / dist) : V3(-away / dist);
  } else {
    V3 n = V3::Zero();
    for (int i = 0; i < 3; ++i) n += std::max(b[i], 0.0) * corner_normal[f][i];
    c.normal = n.norm() > 0 ? V3(n.normalized()) : face_normal[f];
  }
  c.gap_mm = outside ? dist : -dist;
  return c;
}

CutterShape cutter_shape(const stiffness::Tool& t) {
  const double R = 0.5 * t.diameter_mm;
  const double top = std::max(t.flute_length_mm, R);
  CutterShape s;
  switch (t.type) {
    case stock::EndShape::ball:
      s = {0.0, R, R, R};
      break;
    case stock::EndShape::bull:
      s = {R - t.corner_radius_mm, t.corner_radius_mm, top, t.corner_radius_mm};
      break;
    case stock::EndShape::flat: {
      // A flat end as a bull nose of a small corner (see part.hpp): the core
      // then keeps a distance from the part, so the direction to it is defined.
      const double eps = std::min(0.1 * R, 0.2);
      s = {R - eps, eps, top, eps};
      break;
    }
  }
  return s;
}

PartModel::PartModel(std::vector<stock::Triangle> tris, const PartOptions& o) : impl_(std::make_unique<Impl>()) {
  impl_->build(tris, o.crease_deg);
}

PartModel PartModel::load(const std::string& path, const PartOptions& o) {
  PartModel m(stock::read_solid_triangles(path, o.mesh_deflection_mm), o);
  m.name_ = path;
  return m;
}

PartModel::PartModel(PartModel&&) noexcept = default;
PartModel& PartModel::operator=(PartModel&&) noexcept = default;
PartModel::~PartModel() = default;

std::size_t PartModel::triangles() const { return impl_->face.size(); }

Contact PartModel::closest(const V3& p) const { return impl_->closest(p); }

namespace {

// The core point nearest to x (the core is a solid cylinder about the axis).
V3 core_point(const CutterShape& s, const V3& tip_mm, const V3& x) {
  V3 k = x - tip_mm;
  k.z() = std::clamp(k.z(), s.core_bottom_mm, s.core_top_mm);
  const double r = std::hypot(k.x(), k.y());
  if (r > s.core_radius_mm) {
    const double f = r > 0 ? s.core_radius_mm / r : 0.0;
    k.x() *= f;
    k.y() *= f;
  }
  return tip_mm + k;
}

}  // namespace

// Where the core enters the part, the pair of closest points meets on the
// surface and |k - q| - rho says only -rho (0.2 mm for a flat D10), however
// deep the cutter is. The depth of the cutter is then that of its deepest core
// point below the part's nearest surface, plus rho: the distance that point
// must travel to leave the part, so a lower bound on the translation that frees
// the whole cutter (the penetration depth, Cameron & Culley, ICRA 1986), and
// equal to it for a plunge into a face or a flank into a wall. The depth below
// the surface is 1-Lipschitz and grows fastest along minus the part's outward
// normal at the nearest point: from the deepest of a few core points (bottom
// and flank, centre and rim) it climbs by projected steps along that direction.
Contact PartModel::Impl::deepest(const CutterShape& s, const V3& tip_mm, Contact best) const {
  V3 k = best.point_mm;
  auto try_point = [&](const V3& x) {
    const Contact c = closest(x);
    if (c.gap_mm >= best.gap_mm) return false;
    best = c;
    k = x;
    return true;
  };
  for (int h = 0; h <= 4; ++h) {
    const double z = s.core_bottom_mm + 0.25 * h * (s.core_top_mm - s.core_bottom_mm);
    try_point(tip_mm + V3(0, 0, z));
    for (int a = 0; a < 8 && s.core_radius_mm > 0; ++a) {
      const double t = a * std::numbers::pi / 4;
      try_point(tip_mm + V3(s.core_radius_mm * std::cos(t), s.core_radius_mm * std::sin(t), z));
    }
  }
  double step = std::max(0.5, -best.gap_mm);
  for (int it = 0; it < 64 && step > 1e-4; ++it)
    if (!try_point(core_point(s, tip_mm, k - step * best.normal))) step *= 0.5;
  // Stopped inside the core rather than at its end: midway between faces.
  const V3 beyond = k - 1e-3 * best.normal;
  best.depth_at_least = (core_point(s, tip_mm, beyond) - beyond).norm() < 1e-9;
  return best;
}

Contact PartModel::contact(const CutterShape& s, const V3& tip_mm, const V3& hint) const {
  // Alternating projections: core -> part -> core ... the distance between the
  // pair decreases at each step (the core is convex), to the contact on the
  // hint's side.
  V3 k = core_point(s, tip_mm, tip_mm + hint);
  Contact c;
  for (int it = 0; it < 24; ++it) {
    c = impl_->closest(k);
    const V3 next = core_point(s, tip_mm, c.point_mm);
    if ((next - k).norm() < 1e-7) break;
    k = next;
  }
  // The core on or in the part (a ball's core is a point: its signed distance
  // is already the depth).
  if (c.gap_mm < 1e-6 && (s.core_radius_mm > 0 || s.core_top_mm > s.core_bottom_mm)) c = impl_->deepest(s, tip_mm, c);
  c.gap_mm -= s.rho_mm;
  return c;
}

}  // namespace deflex::part
