// The part's surface for the workpiece model's checks before meshing: closed,
// held by the fixtures, the points on it, and its thinnest wall (the default
// mesh size). Brute force over the triangles: a check asks a few points, and
// a part model for a compliance has some thousands of triangles at most.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stiffness/workpiece.hpp"

namespace deflex::stiffness {

namespace {

using V3 = Eigen::Vector3d;

V3 vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

std::string fmt_point(const V3& p) {
  char b[96];
  std::snprintf(b, sizeof b, "(%.3f, %.3f, %.3f)", p(0), p(1), p(2));
  return b;
}

// The point of triangle abc closest to p (Ericson, Real-Time Collision
// Detection, 2005, section 5.1.5).
V3 closest_on_triangle(const V3& p, const V3& a, const V3& b, const V3& c) {
  const V3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const V3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const V3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Triangle-box overlap by the separating axis theorem (Akenine-Moeller 2001,
// "Fast 3D triangle-box overlap testing"): the box's 3 axes, the triangle's
// normal and the 9 cross products of edges and axes.
bool triangle_meets_box(const std::array<V3, 3>& t, const V3& centre, const V3& half) {
  const std::array<V3, 3> v{t[0] - centre, t[1] - centre, t[2] - centre};
  const std::array<V3, 3> e{v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  const auto separated = [&](const V3& axis) {
    if (axis.squaredNorm() < 1e-30) return false;
    const double p0 = axis.dot(v[0]), p1 = axis.dot(v[1]), p2 = axis.dot(v[2]);
    const double r = half.dot(axis.cwiseAbs());
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  for (int k = 0; k < 3; ++k)
    if (separated(V3::Unit(k))) return false;
  if (separated(e[0].cross(e[1]))) return false;
  for (const V3& edge : e)
    for (int k = 0; k < 3; ++k)
      if (separated(edge.cross(V3::Unit(k)))) return false;
  return true;
}

// Distance along the ray o + t d (t > 0) to triangle abc, or infinity
// (Moeller and Trumbore 1997).
double ray_hit(const V3& o, const V3& d, const V3& a, const V3& b, const V3& c) {
  const V3 e1 = b - a, e2 = c - a, pv = d.cross(e2);
  const double det = e1.dot(pv);
  if (std::abs(det) < 1e-14) return std::numeric_limits<double>::infinity();
  const V3 tv = o - a;
  const double u = tv.dot(pv) / det;
  if (u < 0 || u > 1) return std::numeric_limits<double>::infinity();
  const V3 qv = tv.cross(e1);
  const double v = d.dot(qv) / det;
  if (v < 0 || u + v > 1) return std::numeric_limits<double>::infinity();
  const double t = e2.dot(qv) / det;
  return t > 0 ? t : std::numeric_limits<double>::infinity();
}

// Edges that border one triangle only (vertices matched exactly, as an STL
// repeats them); the first such edge's midpoint for the message.
std::size_t open_edges(const std::vector<stock::Triangle>& tris, V3& where) {
  std::map<std::pair<std::array<double, 3>, std::array<double, 3>>, int> count;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      auto a = t.p[k], b = t.p[(k + 1) % 3];
      if (b < a) std::swap(a, b);
      ++count[{a, b}];
    }
  std::size_t n = 0;
  for (const auto& [e, c] : count)
    if (c == 1 && n++ == 0) where = 0.5 * (vec(e.first) + vec(e.second));
  return n;
}

}  // namespace

PartSurface read_part_surface(const std::string& path) {
  PartSurface s;
  s.file = path;
  const std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  s.stl = ext == ".stl" || ext == ".STL" || ext == ".Stl";
  s.triangles = stock::read_solid_triangles(path, 0.01);
  // STEP and IGES solids are checked on their topology when meshed
  // (src/stiffness/occt/part_solid.cpp); their faces' meshes are separate.
  V3 where = V3::Zero();
  if (s.stl)
    if (const std::size_t n = open_edges(s.triangles, where))
      throw Error(ErrorKind::config, path + ": error: the part is not a closed solid: " + std::to_string(n) +
                                         " edges of its surface border one triangle only (the first at " +
                                         fmt_point(where) + " mm): the workpiece model needs the volume it bounds");
  return s;
}

SurfacePoint nearest_surface_point(const PartSurface& s, const V3& p) {
  SurfacePoint best;
  best.distance_mm = std::numeric_limits<double>::infinity();
  for (const auto& t : s.triangles) {
    const V3 q = closest_on_triangle(p, vec(t.p[0]), vec(t.p[1]), vec(t.p[2]));
    const double d = (q - p).norm();
    if (d < best.distance_mm) best = {q, d};
  }
  return best;
}

bool touches(const PartSurface& s, const stock::BoxSpec& b) {
  const V3 lo(std::min(b.x0_mm, b.x1_mm), std::min(b.y0_mm, b.y1_mm), std::min(b.z0_mm, b.z1_mm));
  const V3 hi(std::max(b.x0_mm, b.x1_mm), std::max(b.y0_mm, b.y1_mm), std::max(b.z0_mm, b.z1_mm));
  const V3 centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  return std::any_of(s.triangles.begin(), s.triangles.end(), [&](const stock::Triangle& t) {
    return triangle_meets_box({vec(t.p[0]), vec(t.p[1]), vec(t.p[2])}, centre, half);
  });
}

double thinnest_wall_mm(const PartSurface& s) {
  const std::size_t n = s.triangles.size(), step = std::max<std::size_t>(1, n / 2000);
  double thinnest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; i += step) {
    const auto& t = s.triangles[i];
    const V3 a = vec(t.p[0]), b = vec(t.p[1]), c = vec(t.p[2]);
    const V3 normal = (b - a).cross(c - a);
    if (normal.norm() < 1e-14) continue;
    const V3 inward = -normal.normalized(), o = (a + b + c) / 3;
    for (const auto& u : s.triangles) {
      const double d = ray_hit(o, inward, vec(u.p[0]), vec(u.p[1]), vec(u.p[2]));
      if (d > 1e-6 && d < thinnest) thinnest = d;
    }
  }
  return thinnest;
}

double default_workpiece_mesh_mm(const PartSurface& s, double wall) {
  V3 lo = V3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& t : s.triangles)
    for (const auto& p : t.p) {
      lo = lo.cwiseMin(vec(p));
      hi = hi.cwiseMax(vec(p));
    }
  const double diag = (hi - lo).norm();
  return std::max(std::isfinite(wall) ? wall / 2 : diag / 20, diag / 150);
}

double enclosed_volume_mm3(const PartSurface& s) {
  double v = 0;
  for (const auto& t : s.triangles) v += vec(t.p[0]).dot(vec(t.p[1]).cross(vec(t.p[2])));
  return std::abs(v) / 6;
}

Fixture parse_fixture(const std::string& spec) {
  if (!spec.starts_with("box:"))
    throw Error(ErrorKind::settings, "the fixture '" + spec + "' must be a box: box:X0,Y0,Z0,X1,Y1,Z1 (mm)");
  return {stock::parse_box(spec), spec};
}

void check_fixtures(const PartSurface& s, const std::vector<Fixture>& fixtures) {
  if (fixtures.empty())
    throw Error(ErrorKind::settings, "no fixture holds the part: give at least one box:X0,Y0,Z0,X1,Y1,Z1 around "
                                     "the faces the vice or clamps hold");
  for (const auto& f : fixtures)
    if (!touches(s, f.box))
      throw Error(ErrorKind::settings, "the fixture box " + f.spec + " touches no part of the surface of " + s.file +
                                           ": nothing would hold it");
}

SurfacePoint check_on_part(const PartSurface& s, const V3& p, double max_mm) {
  const SurfacePoint q = nearest_surface_point(s, p);
  if (q.distance_mm > max_mm) {
    char b[96];
    std::snprintf(b, sizeof b, " at %.3f mm (more than %g mm)", q.distance_mm, max_mm);
    throw Error(ErrorKind::settings, "the point " + fmt_point(p) + " is not on the part " + s.file +
                                         ": nearest surface point " + fmt_point(q.point_mm) + b);
  }
  return q;
}

}  // namespace deflex::stiffness
