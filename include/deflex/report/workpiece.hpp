// The workpiece's compliance (`deflex stiffness --part`) as text or JSON.
#pragma once
#include <string>
#include <vector>

#include "deflex/stiffness/workpiece.hpp"

namespace deflex::report {

// What the output names besides the points and the mesh.
struct WorkpieceTitle {
  std::string part;
  std::vector<std::string> fixtures;  // as given
  std::string material;
  stiffness::Material elastic;
};

// {"part", "material", "E_MPa", "poisson", "fixtures", "mesh": {...},
//  "points": [{"point_mm", "surface_mm", "load_centroid_mm",
//  "compliance_mm_per_N": [[..],[..],[..]], "principal": [{"compliance_mm_per_N", "direction"}]}]}
std::string workpiece_json(const WorkpieceTitle& t, const stiffness::WorkpieceInfo& mesh,
                           const std::vector<stiffness::PointCompliance>& points);

// The matrix of each point with its units, its principal compliances (most
// compliant first) and directions, and the mesh's figures.
std::string workpiece_text(const WorkpieceTitle& t, const stiffness::WorkpieceInfo& mesh,
                           const std::vector<stiffness::PointCompliance>& points);

}  // namespace deflex::report
