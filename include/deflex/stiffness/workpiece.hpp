// The workpiece's own compliance: the part model (STEP, IGES or a closed STL)
// meshed with quadratic tetrahedra by gmsh, held where its surface lies inside
// fixture boxes, and solved by the solid tool model's linear-elastic FEM
// (solid.hpp; src/stiffness/solid_fem.cpp). A thin wall bends under the
// cutting force as the tool does: the two compliances add along the normal.
//
// The clamp: every mesh node on the part's surface inside a fixture box is
// fixed in x, y and z (a rigid vice jaw or a bolted face; the fixture's own
// compliance is not modelled). The load: a unit force in x, y, z spread over
// a small patch around the surface point nearest the point asked (the smooth
// weight of the tool model, a ball of radius patch_radius_mm cut by the
// body), the displacement read back with the same weights: C = W^T K^-1 W,
// 3x3, machine axes, mm/N, symmetric positive definite (Maxwell-Betti).
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "deflex/stiffness/compliance.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/build.hpp"

namespace deflex::stiffness {

// The part's surface, read once for the checks made before meshing.
struct PartSurface {
  std::string file;
  std::vector<stock::Triangle> triangles;  // outward, as stock::read_solid_triangles gives them
  bool stl = false;
  // Non-empty: the solid is the union of these boxes, meshed from them (the
  // triangles are its surface, for the nearest points and the fixtures): the
  // in-process stock, a heightfield, at a stage.
  std::vector<stock::BoxSpec> boxes;
};

// Reads an STL, STEP or IGES part (stock::read_solid_triangles). Throws
// Error(ErrorKind::config) when an STL's surface is open (an edge that borders
// one triangle only): it bounds no volume to mesh.
PartSurface read_part_surface(const std::string& path);

struct SurfacePoint {
  Eigen::Vector3d point_mm = Eigen::Vector3d::Zero();
  double distance_mm = 0;
};
SurfacePoint nearest_surface_point(const PartSurface& s, const Eigen::Vector3d& p_mm);

// Whether some triangle of the surface meets the box (its faces included).
bool touches(const PartSurface& s, const stock::BoxSpec& b);

// The thinnest wall: the least distance from a surface point inward, along
// the inner normal, to the opposite surface (over up to 2000 triangles' centroids).
double thinnest_wall_mm(const PartSurface& s);

// The volume the (closed, outward) surface bounds, mm^3 (divergence theorem).
double enclosed_volume_mm3(const PartSurface& s);

// A fixture box as given ("box:X0,Y0,Z0,X1,Y1,Z1", mm, work frame).
struct Fixture {
  stock::BoxSpec box;
  std::string spec;
};
Fixture parse_fixture(const std::string& spec);  // Error(ErrorKind::settings) when malformed

// What can fail before meshing, in this order: no fixture, a fixture box that
// touches no part of the surface. Error(ErrorKind::settings) naming the box as given.
void check_fixtures(const PartSurface& s, const std::vector<Fixture>& fixtures);

// The surface point nearest p; Error(ErrorKind::settings) when it is farther
// than max_mm, naming it and the distance.
SurfacePoint check_on_part(const PartSurface& s, const Eigen::Vector3d& p_mm, double max_mm);

struct WorkpieceOptions {
  double mesh_mm = 0;          // largest element edge; 0: default_workpiece_mesh_mm()
  double patch_radius_mm = 0;  // load patch radius; 0: a quarter of the thinnest wall or of mesh_mm, the larger
  double on_part_mm = 1.0;     // a point farther than this from the surface is refused
};

// Half the thinnest wall (thinnest_wall_mm(s); two quadratic elements across
// it carry its bending: the refinement test), at least a 150th of the part's
// bounding-box diagonal.
double default_workpiece_mesh_mm(const PartSurface& s, double thinnest_wall_mm);

struct WorkpieceInfo {
  std::size_t nodes = 0;
  std::size_t elements = 0;     // 10-node tetrahedra
  std::size_t dofs = 0;         // free degrees of freedom
  std::size_t fixed_nodes = 0;  // held by the fixtures
  std::size_t straightened = 0; // curved elements made straight-sided (folded on a small fillet)
  double mesh_mm = 0;
  double patch_radius_mm = 0;
  double thinnest_wall_mm = 0;
  double mesh_seconds = 0;      // gmsh
  double solve_seconds = 0;     // assembly and factorisation
};

struct PointCompliance {
  Eigen::Vector3d point_mm = Eigen::Vector3d::Zero();    // as asked
  Eigen::Vector3d surface_mm = Eigen::Vector3d::Zero();  // nearest surface point: the patch centre
  Eigen::Vector3d load_centroid_mm = Eigen::Vector3d::Zero();  // weighted centroid of the patch
  Compliance matrix_mm_per_N = Compliance::Zero();  // rows displacement x, y, z; columns force
};

// Built once (mesh, clamp, factorisation), asked at many points.
class WorkpieceModel {
 public:
  // Checks the fixtures (check_fixtures), meshes the part, holds it and
  // factorises its stiffness. Throws Error(ErrorKind::settings) when a box
  // holds no mesh node or all of them hold too few (fewer than three not in
  // a line) to stop the part turning, Error(ErrorKind::config) for a part
  // that bounds no volume, Error(ErrorKind::internal) when meshing fails.
  WorkpieceModel(const PartSurface& part, const std::vector<Fixture>& fixtures, const Material& m,
                 const WorkpieceOptions& o = {});
  WorkpieceModel(WorkpieceModel&&) noexcept;
  WorkpieceModel& operator=(WorkpieceModel&&) noexcept;
  ~WorkpieceModel();

  // The compliance at the surface point nearest p (check_on_part first).
  // Thread-safe (const).
  PointCompliance compliance_at(const Eigen::Vector3d& p_mm) const;
  // The same at several points, their loads solved together (kBatchPoints at
  // a time): the same matrices, far less time per point than one by one.
  std::vector<PointCompliance> compliance_at(const std::vector<Eigen::Vector3d>& points_mm) const;
  static constexpr std::size_t kBatchPoints = 16;  // 48 right-hand sides: 115 MB at 300,000 dofs
  // The displacement at the patch of read_mm under a unit force at the patch
  // of load_mm (columns: force x, y, z): transfer(a, b) = transfer(b, a)^T.
  Compliance transfer(const Eigen::Vector3d& load_mm, const Eigen::Vector3d& read_mm) const;
  const WorkpieceInfo& info() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace deflex::stiffness
