// The workpiece's compliance over the part of its surface a program machines:
// computed once at nodes (the points asked, thinned to one per cell of a
// grid, solved in batches by WorkpieceModel) and interpolated between them.
// Asking the FEM at every CL point - 0.1 to 0.4 s a point on a wall's mesh -
// would take hours on a finishing program of tens of thousands of points;
// the compliance varies smoothly over a wall, so a few hundred nodes carry it.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "deflex/stiffness/compliance.hpp"
#include "deflex/stiffness/workpiece.hpp"

namespace deflex::stiffness {

// Compliances solved already, by point: a field at a finer spacing, or a
// check of one, solves only what no earlier one did (the first point of a
// coarse cell is the first of its fine cell too: the nodes nest).
using SolvedCompliances = std::map<std::tuple<double, double, double>, Compliance>;

// The model's compliance at each point, those in `solved` (may be null) taken
// from it and the others solved and added.
std::vector<Compliance> compliances(const WorkpieceModel& model, const std::vector<Eigen::Vector3d>& points_mm,
                                    SolvedCompliances* solved, const std::function<void(double)>& progress = {});

class WorkpieceField {
 public:
  // One node per occupied cell of spacing_mm and face among `points_mm`
  // (the first point in it; `normals`: the part's outward unit normal at
  // each; a face: normals within kSameFaceDeg), its compliance from the model
  // (check_on_part is the caller's: every point must lie within the model's
  // on_part_mm). `progress` (may be empty) gets the fraction of the nodes solved.
  // `solved` (may be null): compliances solved before, and those solved here added.
  WorkpieceField(const WorkpieceModel& model, const std::vector<Eigen::Vector3d>& points_mm,
                 const std::vector<Eigen::Vector3d>& normals, double spacing_mm,
                 const std::function<void(double)>& progress = {}, SolvedCompliances* solved = nullptr);
  // Nodes interpolate only among their face: the two faces of a thin wall lie
  // in one cell, and a wall's foot beside the floor; across them the
  // compliance jumps (the off-diagonal terms change sign across a wall).
  static constexpr double kSameFaceDeg = 30;

  // The compliance at p on the face of outward normal n: a weighted linear
  // fit (moving least squares) of the nodes of that face within twice the
  // spacing - exact at a node, and on a smooth field second-order accurate
  // between nodes; the nearest node's where fewer than four are near.
  // `covered` (may be null): whether a node lies within twice the spacing;
  // where none does the nearest of the face (else of all) is taken. Thread-safe (const).
  Compliance at(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& n, bool* covered = nullptr) const;
  // The distance from p to the nearest node of the face of normal n within
  // twice the spacing; infinity where there is none.
  double node_distance_mm(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& n) const;
  // The nodes, where the compliance is the FEM's.
  const std::vector<Eigen::Vector3d>& node_points() const { return node_mm_; }

  std::size_t nodes() const { return node_mm_.size(); }
  // The largest |entry| over the nodes, mm/N.
  double largest_entry_mm_per_N() const;
  double spacing_mm() const { return h_; }

 private:
  using Key = std::int64_t;
  Key key(const Eigen::Vector3d& p) const;
  Key key(std::int64_t i, std::int64_t j, std::int64_t k) const;
  // The nodes of the face within twice the spacing of p.
  void near_nodes(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, std::vector<std::size_t>& near) const;
  double h_ = 1;
  std::vector<Eigen::Vector3d> node_mm_, normal_;
  std::vector<Compliance> c_;
  std::unordered_map<Key, std::vector<std::size_t>> cells_;  // nodes by cell of h_
};

}  // namespace deflex::stiffness
