// Pieces of the solid model shared by solid*.cpp. Private to src/stiffness/.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "deflex/stiffness/compliance.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/build.hpp"

namespace deflex::stiffness::solid {

// Quadratic tetrahedra. Node order of each element: corners 0-3, then the
// mid-edge nodes of edges (0,1) (1,2) (0,2) (0,3) (1,3) (2,3).
struct TetMesh {
  std::vector<Eigen::Vector3d> node_mm;
  std::vector<std::array<int, 10>> tet;
};

// The corner pairs of mid-edge nodes 4..9.
inline constexpr std::array<std::array<int, 2>, 6> kEdges{
    {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}}};

// Writes the tool solid (revolved equivalent profile, see shape.hpp) as an
// OpenCASCADE .brep file, or converts tool.step_file to .brep.
void write_tool_brep(const Tool& t, const std::string& brep_path);

// Meshes a .brep with gmsh (quadratic tets, max edge mesh_size_mm); moves the
// lowest point to z = 0 when move_tip_to_origin.
TetMesh mesh_brep(const std::string& brep_path, double mesh_size_mm, bool move_tip_to_origin);
// Meshes the volume a closed STL bounds, its surface remeshed at mesh_size_mm
// (gmsh's classifySurfaces and createGeometry).
TetMesh mesh_stl(const std::string& stl_path, double mesh_size_mm);
// The union of axis-aligned boxes (OpenCASCADE's fuse, exact faces: nothing
// to reparametrise, unlike a faceted surface with ledges a cell wide).
TetMesh mesh_boxes(const std::vector<stock::BoxSpec>& boxes, double mesh_size_mm);

// A load patch around a point c: the smooth weight phi = (1 - d^2/r^2)^2 for
// d < r over the part of the ball inside the body, as nodal weights
// w_a = int N_a phi dV / int phi dV (they sum to 1), and its weighted centroid.
// A point load is singular in 3D elasticity (infinite displacement under it);
// a smooth patch converges with the mesh. Throws Error(ErrorKind::internal)
// when the ball holds no part of the body.
struct Patch {
  std::vector<std::pair<int, double>> weight;  // (node, w_a)
  Eigen::Vector3d centroid_mm = Eigen::Vector3d::Zero();
};
Patch patch_weights(const TetMesh& mesh, const Eigen::Vector3d& c, double r_mm);

// The linear-elastic FEM of a meshed body with some nodes fixed (all three
// components), its stiffness factorised once: any number of patch loads then
// cost a forward and back substitution each. A direct sparse Cholesky: K is
// symmetric positive definite once the body is held, and one factorisation
// serves every load, where an iterative solver would start again for each.
// CHOLMOD's supernodal LL^T (SuiteSparse, nested-dissection ordering, dense
// BLAS kernels; in a plugin, cholmod_api.hpp) where deflex was built with it:
// on a wall's mesh of 2.4e5 dofs it factorises 7 times faster than Eigen's
// SimplicialLDLT (AMD ordering, scalar kernels), the fallback.
class ElasticSolver {
 public:
  // fixed[a]: node a is held. Throws Error(ErrorKind::internal) when the
  // stiffness is singular (nothing, or too little, held).
  ElasticSolver(const TetMesh& mesh, const Material& m, const std::vector<char>& fixed);
  std::size_t dofs() const { return static_cast<std::size_t>(3 * nfree_); }
  // Displacements (3 columns: unit force x, y, z spread by the patch weights).
  // Thread-safe.
  Eigen::MatrixXd solve(const Patch& load) const;
  // The same for several patches in one solve (3 columns each, in order):
  // a supernodal factor solves many right-hand sides at once far faster per
  // column than one at a time (dense blocks, BLAS 3).
  Eigen::MatrixXd solve(const std::vector<Patch>& loads) const;
  // The patch-weighted mean of displacements u (3 columns): rows x, y, z.
  Compliance read(const Patch& at, const Eigen::Ref<const Eigen::MatrixXd>& u) const;
  // read(p, solve(p)) = W^T K^-1 W: symmetric by construction.
  Compliance compliance(const Patch& p) const { return read(p, solve(p)); }

 private:
  std::vector<int> free_index_;
  int nfree_ = 0;
  struct Factor;  // CHOLMOD's or Eigen's (solid_fem.cpp)
  std::shared_ptr<Factor> factor_;
};

// Moves the mid-edge nodes of every element whose Jacobian is not positive at
// some Gauss point to the middle of their straight edges, until none is (a
// mid-edge node gmsh put on a curved face of a small fillet can fold a coarse
// element inside out; a straight-sided element is valid when its corners
// are). Returns the number of elements straightened.
std::size_t straighten_inverted(TetMesh& mesh);

// Load stations: a smooth load patch centred on the axis at each height.
struct Station {
  double centre_z_mm = 0;  // where the patch is centred
  double height_mm = 0;    // weighted centroid height of the patch (the row's h)
  Compliance c = Compliance::Zero();
};

// Solves the clamped FEM (nodes with z >= clamp_z_mm fixed) for a unit force
// spread over each patch; fills height_mm and c of each station.
struct FemStats {
  std::size_t dofs = 0;
};
FemStats solve_stations(const TetMesh& mesh, const Material& m, double clamp_z_mm,
                        double patch_radius_mm, std::vector<Station>& stations);

}  // namespace deflex::stiffness::solid
