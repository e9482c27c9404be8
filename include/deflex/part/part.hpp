// The design surface (the part model): where the cutter touches it and its
// outward normal there.
//
// The cutter's active surface, for contact queries, is the Minkowski sum of a
// convex "core" and a sphere of radius rho (CutterShape):
//   ball of radius R:          core = its centre (tip + R z),         rho = R;
//   bull nose, corner r:       core = solid cylinder of radius R - r from
//                              tip + r z up the flutes,              rho = r;
//   flat end:                  treated as a bull nose of corner eps (0.1 R,
//                              at most 0.2 mm): exact on faces (floor, wall),
//                              rounded by eps only where a part edge meets the
//                              cutter's corner.
// The contact is the part point q closest to the core; the gap (signed
// distance from the cutter surface to the part, mm) is |k - q| - rho for the
// core point k closest to q; where the core itself enters the part (a cut
// deeper than rho), minus the depth of the core's deepest point below the
// part's nearest surface, minus rho, and q is that point's nearest part point.
// The normal is the part's outward normal at q. The
// pair (k, q) is found by alternating projections (core convex, mesh through a
// CGAL AABB tree), starting from the core point on the side the caller expects
// the contact (the hint), which converges to the contact on that side.
//
// Normals on a triangulated part: a facet's own normal is off the smooth
// surface's by up to half the angle between neighbouring facets. Inside a facet
// or on a smooth edge the normal is interpolated from crease-aware vertex
// normals (angle-weighted, over the facets round the vertex within crease_deg
// of the facet: Phong-style, so exact to second order on a smooth surface); on
// a crease edge or vertex (a sharp ridge the ball rolls over) it is the
// direction from q to the core, which is the exact normal of the surface the
// cutter generates there.
#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/build.hpp"

namespace deflex::part {

using V3 = Eigen::Vector3d;

struct CutterShape {
  double core_radius_mm = 0;  // radius of the core cylinder (0: a point or a segment)
  double core_bottom_mm = 0;  // core's lowest height above the tip
  double core_top_mm = 0;     // core's highest height above the tip
  double rho_mm = 0;          // radius of the sphere swept over the core
};
CutterShape cutter_shape(const stiffness::Tool& t);

struct Contact {
  bool found = false;
  V3 point_mm = V3::Zero();  // on the part
  V3 normal = V3::UnitZ();   // outward unit normal of the part at point_mm
  double gap_mm = 0;         // > 0: the cutter stands off the part; < 0: it cuts into it, by -gap_mm
  bool on_face = true;       // inside a facet or on a smooth edge (not a crease)
  // -gap_mm only bounds the depth from below: the core's deepest point lies
  // midway between faces of the part (the cutter through more than half its
  // thickness), where the depth below the nearest surface stops growing.
  bool depth_at_least = false;
};

struct PartOptions {
  double crease_deg = 12;             // facets meeting at more than this form a sharp edge
  double mesh_deflection_mm = 0.002;  // chordal deflection of STEP/IGES meshing
};

class PartModel {
 public:
  // Triangles with outward orientation (counter-clockwise seen from outside,
  // as STL requires). Throws Error(ErrorKind::config) on an empty or degenerate soup.
  explicit PartModel(std::vector<stock::Triangle> tris, const PartOptions& o = {});
  // STL, STEP or IGES, read as the stock is (stock::read_solid_triangles).
  static PartModel load(const std::string& path, const PartOptions& o = {});
  PartModel(PartModel&&) noexcept;
  PartModel& operator=(PartModel&&) noexcept;
  ~PartModel();

  // The contact of a cutter whose tip stands at tip_mm (tool axis +Z). hint: a
  // horizontal or 3D direction towards the expected contact (zero: straight
  // down), used for the starting core point of flat and bull-nose cutters.
  // Thread-safe (const).
  Contact contact(const CutterShape& c, const V3& tip_mm, const V3& hint) const;

  // The part point closest to p and the part's outward normal there.
  Contact closest(const V3& p) const;

  std::size_t triangles() const;
  const std::string& name() const { return name_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string name_;
};

}  // namespace deflex::part
