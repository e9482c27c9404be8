// The workpiece's own compliance in the cut. deflex compensates the relative
// displacement of tool and workpiece at the contact: the tool gives way by
// delta_t = C_t F under the cutting force F on it, the part by
// delta_w = C_w (-F) under the force on it, and the surface lands off by
// (delta_t - delta_w) . n = n . (C_t + C_w) F: the two compliances add
// (Budak & Altintas, "Modeling and avoidance of static form errors in
// peripheral milling of plates", IJMTM 35, 1995; the thin-wall literature
// since). Where the part is stiff C_w is zero and nothing changes.
#pragma once
#include <Eigen/Core>
#include <cstddef>

namespace deflex::compensate {

// How far the workpiece gives way at a point of its surface under a unit force
// there: a 3x3 compliance in mm/N, machine axes. `normal` is the part's
// outward unit normal there: it tells the faces of a thin wall apart, whose
// points lie a wall's thickness apart and give way alike but not the same.
// `motion` is the index, in program order, of the move cutting there: the
// in-process workpiece changes as the program removes material (staged models
// answer for the stage the move is in). Asked from the simulation's threads
// at once (const, thread-safe). The workpiece FEM implements it
// (stiffness/workpiece.hpp); the tests give closed forms.
class WorkpieceCompliance {
 public:
  virtual ~WorkpieceCompliance() = default;
  virtual Eigen::Matrix3d at(const Eigen::Vector3d& point_mm, const Eigen::Vector3d& normal, std::size_t motion) const = 0;
};

}  // namespace deflex::compensate
