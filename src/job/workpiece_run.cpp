// The workpiece's own compliance in a run (workpiece_run.hpp).
#include "workpiece_run.hpp"

#include "checks.hpp"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>

#include "deflex/compensate/reach.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/job/setup.hpp"

namespace deflex::job::detail {

namespace st = deflex::stiffness;
using V3 = Eigen::Vector3d;

namespace {

void check_sizes(const Workholding& w) {
  if (!(w.mesh_mm >= 0) || !std::isfinite(w.mesh_mm))
    throw Error(ErrorKind::settings, "{workpiece_mesh_mm} must be >= 0 mm (0: half the part's thinnest wall)");
  if (!(w.spacing_mm >= 0) || !std::isfinite(w.spacing_mm))
    throw Error(ErrorKind::settings, "{workpiece_spacing_mm} must be >= 0 mm (0: the default, 3 mm)");
}

// The reached points where the field is least sure and matters most: the
// distance to the nearest node of the face times the compliance there. The
// farthest alone would pick the floor beside a thin wall, two orders stiffer.
std::vector<compensate::FacetPoint> least_sure(const std::vector<compensate::FacetPoint>& reached,
                                               const st::WorkpieceField& field, std::size_t n) {
  std::vector<std::pair<double, std::size_t>> d;
  const std::vector<V3>& nodes = field.node_points();
  for (std::size_t i = 0; i < reached.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (const V3& q : nodes) best = std::min(best, (q - reached[i].point_mm).norm());
    const double c = field.at(reached[i].point_mm, reached[i].normal).cwiseAbs().maxCoeff();
    d.emplace_back(best * c, i);
  }
  const std::size_t k = std::min(n, d.size());
  std::partial_sort(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(k), d.end(), std::greater<>());
  std::vector<compensate::FacetPoint> out;
  for (std::size_t i = 0; i < k && d[i].first > 0; ++i) out.push_back(reached[d[i].second]);
  return out;
}

// The field against the FEM at those points: the largest difference of an
// entry, relative to the field's largest entry (the compliance that sets the
// error: on a bulky floor beside a thin wall the compliance is two orders
// smaller, mostly the local indentation under the load patch, whose FEM
// value scatters by some 10 % from point to point with the mesh).
void check_field(const st::WorkpieceModel& model, const st::WorkpieceField& field,
                 const std::vector<compensate::FacetPoint>& reached, WorkpieceFigures& f) {
  const std::vector<compensate::FacetPoint> at = least_sure(reached, field, st::WorkpieceModel::kBatchPoints);
  std::vector<V3> points;
  for (const compensate::FacetPoint& p : at) points.push_back(p.point_mm);
  const std::vector<st::PointCompliance> exact = model.compliance_at(points);
  f.largest_mm_per_N = field.largest_entry_mm_per_N();
  for (std::size_t i = 0; i < at.size(); ++i) {
    const st::Compliance& c = exact[i].matrix_mm_per_N;
    const double d = (field.at(at[i].point_mm, at[i].normal) - c).cwiseAbs().maxCoeff();
    if (d > f.check_max_mm_per_N || i == 0) f.check_max_mm_per_N = d, f.check_worst_mm = at[i].point_mm;
  }
  f.checked = at.size();
}

// What the model is, and how well its field holds: a note; a warning where
// the field strays from the FEM by more than kFieldWarnRel.
constexpr double kFieldWarnRel = 0.05;
void print_workpiece(const WorkpieceFigures& f, Io& io) {
  char b[600];
  std::snprintf(b, sizeof b,
                "deflex: workpiece: %zu dofs (%.3g mm elements, meshed %.1f s, factorised %.1f s); its compliance "
                "solved at %zu nodes %.3g mm apart (%.1f s) over the %zu surface points the tools reach, largest "
                "%.3g um/N; between nodes within %.3g um/N (%.1f %%) of the FEM at the %zu points least sure\n",
                f.mesh.dofs, f.mesh.mesh_mm, f.mesh.mesh_seconds, f.mesh.solve_seconds, f.nodes, f.spacing_mm,
                f.nodes_seconds, f.reached_points, 1000 * f.largest_mm_per_N, 1000 * f.check_max_mm_per_N,
                100 * f.check_rel(), f.checked);
  io.info() << b;
  if (f.check_rel() <= kFieldWarnRel) return;
  std::snprintf(b, sizeof b,
                "deflex: warning: the workpiece's compliance between its nodes differs from the FEM by %.1f %% of its "
                "largest at X%.3f Y%.3f Z%.3f: give a smaller {workpiece_spacing_mm} (now %.3g mm)\n",
                100 * f.check_rel(), f.check_worst_mm.x(), f.check_worst_mm.y(), f.check_worst_mm.z(), f.spacing_mm);
  io.err << io.named(b);
}

}  // namespace

std::optional<WorkpiecePlan> plan_workpiece(const Run& j) {
  const Settings& s = j.given;
  const Workholding& w = s.workholding;
  if (w.fixtures.empty() || j.purpose == Purpose::check) return std::nullopt;
  check_sizes(w);
  WorkpiecePlan p;
  for (const std::string& f : w.fixtures) p.fixtures.push_back(st::parse_fixture(f));
  const std::string part = !s.part.part.empty() ? s.part.part : config_path(j.setup.config, "part");
  if (part.empty())
    throw Error(ErrorKind::settings, "{fixture}: the workpiece's compliance needs the part model, {part} P (STEP, "
                                     "IGES or a closed STL)");
  if (s.material.material.empty() && s.material.kt)
    throw Error(ErrorKind::settings, "{fixture}: the workpiece's compliance needs a material by name, {material} M, "
                                     "whose entry has elastic: {E_MPa: .., poisson: ..}; coefficients alone have none");
  const std::string name = !s.material.material.empty() ? s.material.material : config_string(j.setup.config, "material");
  p.elastic = elastic_of(name, material_library_path(s.material.material_file, j.setup.config));
  p.surface = st::read_part_surface(part);
  st::check_fixtures(p.surface, p.fixtures);
  p.options.mesh_mm = w.mesh_mm;
  if (w.spacing_mm > 0) p.spacing_mm = w.spacing_mm;
  return p;
}

std::shared_ptr<const WorkpieceInCut> build_workpiece(Run& j, const WorkpiecePlan& plan, Io& io,
                                                      const compensate::Progress& progress) {
  auto stage = [&progress](double f) {
    if (progress) progress("workpiece", f);
  };
  stage(0);
  // Where the tools reach the part, widened by a spacing: the interpolation
  // then has nodes round every contact.
  compensate::ToolReach reach(plan.spacing_mm);
  engage::PathOptions po;
  po.cl_spacing_mm = j.settings.cl_spacing_mm;
  const auto tool_of = [&j](const interp::Motion& m) { return compensate::tool_id(m, j.settings); };
  if (j.pieces) each_piece(j, [&](std::vector<interp::Motion>& ms) { reach.add(ms, j.physics.tools, tool_of, po); });
  else reach.add(j.motions, j.physics.tools, tool_of, po);
  const std::vector<compensate::FacetPoint> reached = reach.reached_points(plan.surface.triangles, 0.5 * plan.spacing_mm);
  if (reached.empty()) {
    io.err << "deflex: warning: no cutting move reaches the part " << plan.surface.file
           << ": the workpiece's compliance is left out (a rigid workpiece)\n";
    return nullptr;
  }
  WorkpieceFigures f;
  f.fixtures = j.given.workholding.fixtures;
  f.material = plan.elastic.name;
  f.elastic = plan.elastic;
  f.reached_points = reached.size();
  f.spacing_mm = plan.spacing_mm;
  const st::WorkpieceModel model(plan.surface, plan.fixtures, plan.elastic, plan.options);
  f.mesh = model.info();
  stage(0.2);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<V3> points, normals;
  for (const compensate::FacetPoint& p : reached) points.push_back(p.point_mm), normals.push_back(p.normal);
  st::WorkpieceField field(model, points, normals, plan.spacing_mm, [&](double x) { stage(0.2 + 0.75 * x); });
  f.nodes = field.nodes();
  f.nodes_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  check_field(model, field, reached, f);
  stage(1);
  print_workpiece(f, io);
  return std::make_shared<const WorkpieceInCut>(std::move(field), std::move(f));
}

}  // namespace deflex::job::detail

namespace deflex::job {

Eigen::Matrix3d WorkpieceInCut::at(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const {
  bool covered = true;
  const stiffness::Compliance c = field_.at(p, n, &covered);
  if (!covered) uncovered_.fetch_add(1, std::memory_order_relaxed);
  return c;
}

}  // namespace deflex::job
