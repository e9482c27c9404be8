// Pieces of the solid model shared by solid*.cpp. Private to src/stiffness/.
#pragma once
#include <array>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "deflex/stiffness/compliance.hpp"
#include "deflex/stiffness/tool.hpp"

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
