// `deflex stiffness --part` as a call: the workpiece's own compliance at
// points of its surface, held by fixture boxes (stiffness/workpiece.hpp).
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "deflex/stiffness/workpiece.hpp"

namespace deflex::job {

struct WorkpieceSettings {
  std::string part;                   // STEP, IGES or a closed STL, mm
  std::vector<std::string> fixtures;  // box:X0,Y0,Z0,X1,Y1,Z1 each, mm: surface inside is held
  std::vector<Eigen::Vector3d> points_mm;  // where the compliance is asked, on the surface
  std::string material;               // by name or alias ("": config material)
  std::string material_file;          // the library ("": config material_file, else the installed one)
  double mesh_mm = 0;                 // element size (0: half the thinnest wall)
};

struct WorkpieceResult {
  std::string part;
  std::string material;       // the entry's name
  std::string material_file;  // the library it came from
  stiffness::Material elastic;  // E_MPa and poisson of the entry's `elastic:`
  std::vector<stiffness::PointCompliance> points;  // one per point asked, in order
  stiffness::WorkpieceInfo mesh;
};

// Every check that can fail before the mesh is made, in this order: the
// settings (a part, a fixture, a point, mesh >= 0), the material and its
// `elastic:` (a config Error at the entry's line), the part (a closed solid),
// each fixture box touching its surface, each point within 1 mm of it; then
// one mesh and one factorisation for all the points.
WorkpieceResult workpiece_compliance(const WorkpieceSettings& s);

}  // namespace deflex::job
