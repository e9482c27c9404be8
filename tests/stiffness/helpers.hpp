// Shared fixtures of the stiffness tests.
#pragma once
#include <string>

#include <Eigen/Dense>

#include "deflex/stiffness/tool.hpp"

namespace deflex::stiffness::testing {

// A plain solid cylinder of diameter d and length L as a flat tool fluted over
// its whole length with ratio 1: the textbook cantilever.
inline Tool cylinder(double d_mm, double L_mm, Material m = {"steel", 210000.0, 0.3}) {
  Tool t;
  t.id = "cyl";
  t.type = stock::EndShape::flat;
  t.diameter_mm = d_mm;
  t.shank_diameter_mm = d_mm;
  t.flute_length_mm = L_mm;
  t.stickout_mm = L_mm;
  t.flute_diameter_ratio = 1.0;
  t.material = m;
  return t;
}

// A file of the source tree (samples/...).
inline std::string sample_path(const std::string& rel) { return std::string(DEFLEX_SOURCE_DIR) + "/" + rel; }

inline bool symmetric_positive_definite(const Eigen::Matrix3d& c, double rel_tol = 1e-9) {
  if ((c - c.transpose()).norm() > rel_tol * c.norm()) return false;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(c).eigenvalues().minCoeff() > 0;
}

// Smallest eigenvalue of the symmetric part of a - b (>= 0: a >= b in the
// positive semi-definite order).
inline double min_eig_difference(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const Eigen::Matrix3d d = a - b;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(0.5 * (d + d.transpose()))
      .eigenvalues()
      .minCoeff();
}

}  // namespace deflex::stiffness::testing
