// `deflex stiffness --part` as a call: the workpiece's own compliance at
// points of its surface, held by fixture boxes (stiffness/workpiece.hpp).
#pragma once
#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "deflex/compensate/workpiece.hpp"
#include "deflex/stiffness/workpiece.hpp"
#include "deflex/stiffness/workpiece_field.hpp"

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

// One stage of a staged workpiece (Workholding::stages): the in-process
// stock when its first pass begins, meshed and asked by that stage's passes.
struct WorkpieceStage {
  std::size_t first_motion = 0;  // program order: the moves from here on (to the next stage) see it
  std::uint32_t first_line = 0;  // that move's line
  stiffness::WorkpieceInfo mesh;
  std::size_t boxes = 0;         // of the stock's solid meshed (stock::zmap_boxes)
  std::size_t reached_points = 0, nodes = 0;
  double largest_mm_per_N = 0;
};

// The workpiece in a simulation or compensation (Settings::workholding):
// how it was modelled, for the report. Staged, the mesh figures are the
// largest stage's dofs and the sums of the times, the field's the sums of the
// nodes and the worst check; `stages` says each.
struct WorkpieceFigures {
  std::vector<std::string> fixtures;
  std::string material;          // the entry's name
  stiffness::Material elastic;
  stiffness::WorkpieceInfo mesh;
  std::size_t reached_points = 0;  // surface points the program's tools reach
  std::size_t nodes = 0;           // of the field kept
  std::size_t solved = 0;          // points the FEM was solved at: the nodes of every spacing tried, the checks
  double spacing_mm = 0;
  double nodes_seconds = 0;        // solving the nodes
  double largest_mm_per_N = 0;  // the field's largest entry
  // The field held against the FEM at the reached points farthest from
  // every node: the largest difference of an entry, where it was.
  std::size_t checked = 0;
  double check_max_mm_per_N = 0;
  Eigen::Vector3d check_worst_mm = Eigen::Vector3d::Zero();
  double check_rel() const { return largest_mm_per_N > 0 ? check_max_mm_per_N / largest_mm_per_N : 0; }
  std::vector<WorkpieceStage> stages;  // empty: the finished part throughout
};

// The workpiece's compliance at a contact: the field's (stiffness/
// workpiece_field.hpp), built from the FEM over the surface the program
// reaches; staged, the field of the stage the move is in.
class WorkpieceInCut final : public compensate::WorkpieceCompliance {
 public:
  // fields[k] answers the moves from first_motions[k] on (ascending, the
  // first 0); a stage no tool reaches has none (a contact there is uncovered).
  WorkpieceInCut(std::vector<std::optional<stiffness::WorkpieceField>> fields, std::vector<std::size_t> first_motions,
                 WorkpieceFigures figures)
      : fields_(std::move(fields)), first_(std::move(first_motions)), figures_(std::move(figures)) {}
  Eigen::Matrix3d at(const Eigen::Vector3d& point_mm, const Eigen::Vector3d& normal, std::size_t motion) const override;
  const WorkpieceFigures& figures() const { return figures_; }
  // Contacts asked farther than twice the spacing from every node (their
  // compliance was the nearest node's), since the model was built.
  std::size_t uncovered() const { return uncovered_.load(std::memory_order_relaxed); }

 private:
  std::vector<std::optional<stiffness::WorkpieceField>> fields_;
  std::vector<std::size_t> first_;
  WorkpieceFigures figures_;
  mutable std::atomic<std::size_t> uncovered_{0};
};

}  // namespace deflex::job
