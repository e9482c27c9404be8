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
    throw Error(ErrorKind::settings, "{workpiece_spacing_mm} must be >= 0 mm (0: the coarsest of 12, 6 and 3 mm whose field holds against the FEM)");
  if (w.stages < 0 || w.stages > kMaxWorkpieceStages)
    throw Error(ErrorKind::settings, "{workpiece_stages} must be 0 (the finished part) to " +
                                         std::to_string(kMaxWorkpieceStages) + " (each stage is a mesh and a factorisation)");
}

// The reached points where the field is least sure and matters most: the
// distance to the nearest node of the face times the compliance there. The
// farthest alone would pick the floor beside a thin wall, two orders stiffer.
std::vector<compensate::FacetPoint> least_sure(const std::vector<compensate::FacetPoint>& reached,
                                               const st::WorkpieceField& field, std::size_t n) {
  std::vector<std::pair<double, std::size_t>> d;
  for (std::size_t i = 0; i < reached.size(); ++i) {
    // Beyond twice the spacing from every node of its face: as far as counts.
    const double far = std::min(field.node_distance_mm(reached[i].point_mm, reached[i].normal), 2 * field.spacing_mm());
    const double c = field.at(reached[i].point_mm, reached[i].normal).cwiseAbs().maxCoeff();
    d.emplace_back(far * c, i);
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
                 const std::vector<compensate::FacetPoint>& reached, st::SolvedCompliances& solved, WorkpieceFigures& f) {
  const std::vector<compensate::FacetPoint> at = least_sure(reached, field, st::WorkpieceModel::kBatchPoints);
  std::vector<V3> points;
  for (const compensate::FacetPoint& p : at) points.push_back(p.point_mm);
  const std::vector<st::Compliance> exact = st::compliances(model, points, &solved);
  f.largest_mm_per_N = field.largest_entry_mm_per_N();
  f.check_max_mm_per_N = 0;
  for (std::size_t i = 0; i < at.size(); ++i) {
    const st::Compliance& c = exact[i];
    const double d = (field.at(at[i].point_mm, at[i].normal) - c).cwiseAbs().maxCoeff();
    if (d > f.check_max_mm_per_N || i == 0) f.check_max_mm_per_N = d, f.check_worst_mm = at[i].point_mm;
  }
  f.checked = at.size();
}

// A field that strays from the FEM by more than this is warned about.
constexpr double kFieldWarnRel = 0.05;
// A coarser spacing is kept where its field is within this of the FEM: 2 %
// of 3 um/N under 20 N is 1.2 um, a tenth of a finishing tolerance.
constexpr double kFieldAcceptRel = 0.02;
// Or within this absolutely, mm/N (0.01 um/N: 1 um under 100 N, more than a
// finishing cut's force): on a bulky part the compliance is the local
// indentation, a thousandth of a thin wall's, whose FEM value scatters by
// some 10 % from point to point with the mesh.
constexpr double kFieldAcceptMmPerN = 1e-5;
// The most boxes a stage's stock may be: the thin-wall sample's are 12,
// united in 0.3 s; a curved stock's run to thousands, which OpenCASCADE's
// fuse did not unite in 5 minutes.
constexpr std::size_t kMaxStageBoxes = 2000;
bool holds(const WorkpieceFigures& f, double rel) { return f.check_rel() <= rel || f.check_max_mm_per_N <= kFieldAcceptMmPerN; }

// A warning where one model's field strays from its FEM by more than
// kFieldWarnRel of its own largest entry (staged, each stage's: a stiff
// stage's field is not held to a compliant one's largest).
void warn_field(const WorkpieceFigures& f, Io& io) {
  char b[400];
  std::snprintf(b, sizeof b,
                "deflex: warning: the workpiece's compliance between its nodes differs from the FEM by %.1f %% of its "
                "largest at X%.3f Y%.3f Z%.3f: give a smaller {workpiece_spacing_mm} (now %.3g mm)\n",
                100 * f.check_rel(), f.check_worst_mm.x(), f.check_worst_mm.y(), f.check_worst_mm.z(), f.spacing_mm);
  io.err << io.named(b);
}

// What the model is and how well its field holds: a note.
void print_workpiece(const WorkpieceFigures& f, Io& io) {
  char b[600];
  std::snprintf(b, sizeof b,
                "deflex: workpiece: %zu dofs (%.3g mm elements, meshed %.1f s, factorised %.1f s); its compliance "
                "in nodes %.3g mm apart, %zu of them (%zu points solved, %.1f s), over the %zu surface points the "
                "tools reach, largest %.3g um/N; between nodes within %.3g um/N (%.1f %%%s) of the FEM at the %zu "
                "points least sure\n",
                f.mesh.dofs, f.mesh.mesh_mm, f.mesh.mesh_seconds, f.mesh.solve_seconds, f.spacing_mm, f.nodes,
                f.solved, f.nodes_seconds, f.reached_points, 1000 * f.largest_mm_per_N, 1000 * f.check_max_mm_per_N,
                100 * f.check_rel(), f.check_rel() > kFieldAcceptRel ? "; under 0.01 um/N, 1 um at 100 N" : "", f.checked);
  io.info() << b;
}

// One line per stage: where it begins and what its mesh cost.
void print_stage(const WorkpieceStage& s, std::size_t k, std::size_t n, Io& io) {
  char b[400];
  std::snprintf(b, sizeof b,
                "deflex: workpiece stage %zu of %zu, the in-process stock at line %u (%zu boxes): %zu dofs, meshed "
                "%.1f s, factorised %.1f s; %zu nodes over %zu points reached, largest %.3g um/N\n",
                k + 1, n, static_cast<unsigned>(s.first_line), s.boxes, s.mesh.dofs, s.mesh.mesh_seconds,
                s.mesh.solve_seconds, s.nodes, s.reached_points, 1000 * s.largest_mm_per_N);
  io.info() << b;
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
  if (w.spacing_mm > 0) p.spacing_mm = w.spacing_mm, p.spacing_given = true;
  return p;
}

namespace {

// One model's field over the points its moves reach: the coarsest spacing
// whose field holds the check (a bulky part's compliance is small and
// smooth: a few nodes carry it), down to the one asked; a spacing given is
// taken as it is. `f` gets the field's figures.
st::WorkpieceField field_over(const st::WorkpieceModel& model, const WorkpiecePlan& plan,
                              const std::vector<compensate::FacetPoint>& reached, const std::function<void(double)>& stage,
                              WorkpieceFigures& f) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<V3> points, normals;
  for (const compensate::FacetPoint& p : reached) points.push_back(p.point_mm), normals.push_back(p.normal);
  std::vector<double> spacings = {plan.spacing_mm};
  if (!plan.spacing_given) spacings = {4 * plan.spacing_mm, 2 * plan.spacing_mm, plan.spacing_mm};
  std::optional<st::WorkpieceField> field;
  st::SolvedCompliances solved;
  for (std::size_t k = 0; k < spacings.size(); ++k) {
    const double f0 = static_cast<double>(k) / spacings.size(), f1 = static_cast<double>(k + 1) / spacings.size();
    field.emplace(model, points, normals, spacings[k], [&](double x) { stage(f0 + (f1 - f0) * x); }, &solved);
    check_field(model, *field, reached, solved, f);
    if (holds(f, kFieldAcceptRel)) break;
  }
  f.reached_points = reached.size();
  f.spacing_mm = field->spacing_mm();
  f.nodes = field->nodes();
  f.solved = solved.size();
  f.nodes_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return std::move(*field);
}

// The stages' figures as one: the largest mesh, the sums of the times and
// nodes, the worst check (relative to the largest compliance of all).
void add_stage(WorkpieceFigures& all, const WorkpieceFigures& one) {
  all.mesh.dofs = std::max(all.mesh.dofs, one.mesh.dofs);
  all.mesh.nodes = std::max(all.mesh.nodes, one.mesh.nodes);
  all.mesh.elements = std::max(all.mesh.elements, one.mesh.elements);
  all.mesh.mesh_mm = one.mesh.mesh_mm;
  all.mesh.patch_radius_mm = one.mesh.patch_radius_mm;
  all.mesh.mesh_seconds += one.mesh.mesh_seconds;
  all.mesh.solve_seconds += one.mesh.solve_seconds;
  all.reached_points += one.reached_points;
  all.nodes += one.nodes;
  all.solved += one.solved;
  all.nodes_seconds += one.nodes_seconds;
  all.spacing_mm = all.spacing_mm > 0 ? std::min(all.spacing_mm, one.spacing_mm) : one.spacing_mm;
  all.checked += one.checked;
  if (one.check_rel() >= all.check_rel() || all.largest_mm_per_N == 0) {
    all.check_max_mm_per_N = one.check_max_mm_per_N;
    all.check_worst_mm = one.check_worst_mm;
  }
  all.largest_mm_per_N = std::max(all.largest_mm_per_N, one.largest_mm_per_N);
}

}  // namespace

std::shared_ptr<const WorkpieceInCut> build_workpiece(Run& j, const WorkpiecePlan& plan, Io& io,
                                                      const compensate::Progress& progress) {
  auto stage = [&progress](double f) {
    if (progress) progress("workpiece", f);
  };
  stage(0);
  // Where the tools reach the part, widened by a spacing: the interpolation
  // then has nodes round every contact. Staged, each stage's moves apart.
  const int asked = j.given.workholding.stages;
  const bool staged = asked > 0;
  // Staged, every stage at the part's element size (the stock's surface has
  // ledges a finishing allowance wide, whose "thinnest wall" would ask for
  // elements that small), its heights to a quarter of an element, and the
  // load at the stock's surface point nearest the part's, however deep the
  // material still on it.
  st::WorkpieceOptions options = plan.options;
  if (staged && options.mesh_mm <= 0)
    options.mesh_mm = st::default_workpiece_mesh_mm(plan.surface, st::thinnest_wall_mm(plan.surface));
  if (staged) options.on_part_mm = std::numeric_limits<double>::infinity();
  StagePlan sp = plan_stages(j, asked, plan.spacing_mm, 0.25 * options.mesh_mm);
  const std::size_t n = sp.first_motion.size();
  std::vector<std::vector<compensate::FacetPoint>> reached(n);
  std::size_t reached_total = 0;
  for (std::size_t k = 0; k < n; ++k) {
    reached[k] = sp.reach[k].reached_points(plan.surface.triangles, 0.5 * plan.spacing_mm);
    reached_total += reached[k].size();
  }
  if (reached_total == 0) {
    io.err << "deflex: warning: no cutting move reaches the part " << plan.surface.file
           << ": the workpiece's compliance is left out (a rigid workpiece)\n";
    return nullptr;
  }
  WorkpieceFigures all;
  all.fixtures = j.given.workholding.fixtures;
  all.material = plan.elastic.name;
  all.elastic = plan.elastic;
  std::vector<std::optional<st::WorkpieceField>> fields(n);
  std::vector<WorkpieceFigures> strays;  // the fields warned about, after the note
  for (std::size_t k = 0; k < n; ++k) {
    if (reached[k].empty()) continue;
    const double f0 = static_cast<double>(k) / n, f1 = static_cast<double>(k + 1) / n;
    st::PartSurface stock_surface;
    if (staged && sp.solids[k].size() > kMaxStageBoxes)
      throw Error(ErrorKind::settings,
                  "{workpiece_stages}: the in-process stock at line " + std::to_string(sp.first_line[k]) + " is " +
                      std::to_string(sp.solids[k].size()) + " boxes of one height, more than " +
                      std::to_string(kMaxStageBoxes) +
                      " (a curved stock; uniting them would take long): stages suit stock left in flat steps, pockets "
                      "and walls; give {workpiece_stages} 0 (the finished part)");
    if (staged) {
      stock_surface.file = "the in-process stock at line " + std::to_string(sp.first_line[k]);
      stock_surface.triangles = std::move(sp.surfaces[k]);
      stock_surface.boxes = std::move(sp.solids[k]);
      stock_surface.stl = true;
    }
    const st::WorkpieceModel model(staged ? stock_surface : plan.surface, plan.fixtures, plan.elastic, options);
    WorkpieceFigures f;
    f.mesh = model.info();
    stage(f0 + 0.2 * (f1 - f0));
    fields[k] = field_over(model, plan, reached[k], [&](double x) { stage(f0 + (0.2 + 0.8 * x) * (f1 - f0)); }, f);
    if (staged) {
      WorkpieceStage ws;
      ws.first_motion = sp.first_motion[k];
      ws.first_line = sp.first_line[k];
      ws.mesh = f.mesh;
      ws.boxes = stock_surface.boxes.size();
      ws.reached_points = f.reached_points;
      ws.nodes = f.nodes;
      ws.largest_mm_per_N = f.largest_mm_per_N;
      all.stages.push_back(ws);
      print_stage(ws, k, n, io);
    }
    if (!holds(f, kFieldWarnRel)) strays.push_back(f);
    add_stage(all, f);
  }
  stage(1);
  print_workpiece(all, io);
  for (const WorkpieceFigures& f : strays) warn_field(f, io);
  return std::make_shared<const WorkpieceInCut>(std::move(fields), std::move(sp.first_motion), std::move(all));
}

}  // namespace deflex::job::detail

namespace deflex::job {

Eigen::Matrix3d WorkpieceInCut::at(const Eigen::Vector3d& p, const Eigen::Vector3d& n, std::size_t motion) const {
  // The last stage beginning at or before the move.
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(first_.begin(), first_.end(), motion) - first_.begin());
  const std::optional<stiffness::WorkpieceField>& field = fields_[k == 0 ? 0 : k - 1];
  bool covered = field.has_value();
  const stiffness::Compliance c = field ? field->at(p, n, &covered) : stiffness::Compliance::Zero();
  if (!covered) uncovered_.fetch_add(1, std::memory_order_relaxed);
  return c;
}

}  // namespace deflex::job

namespace deflex::job::detail {

namespace {
report::Json share_json(const report::RunFigures::Share& s) {
  return {{"largest_mm", report::fixed(s.largest_mm, 6)}, {"line", s.line}};
}
std::string share_text(const report::RunFigures::Share& s) {
  char b[80];
  std::snprintf(b, sizeof b, "%.4f mm (line %u)", s.largest_mm, static_cast<unsigned>(s.line));
  return b;
}
}  // namespace

report::Json workpiece_json(const Run& j, const report::RunFigures& f) {
  if (!j.workpiece) return report::Json();
  const WorkpieceFigures& w = j.workpiece->figures();
  report::Json js{{"fixtures", w.fixtures},
                  {"material", w.material},
                  {"E_MPa", w.elastic.E_MPa},
                  {"poisson", w.elastic.poisson},
                  {"dofs", w.mesh.dofs},
                  {"mesh_mm", report::fixed(w.mesh.mesh_mm, 4)},
                  {"mesh_s", report::fixed(w.mesh.mesh_seconds, 2)},
                  {"factorise_s", report::fixed(w.mesh.solve_seconds, 2)},
                  {"reached_points", w.reached_points},
                  {"nodes", w.nodes},
                  {"spacing_mm", report::fixed(w.spacing_mm, 4)},
                  {"solved_points", w.solved},
                  {"nodes_s", report::fixed(w.nodes_seconds, 2)},
                  {"largest_mm_per_N", w.largest_mm_per_N}};
  js["field_check"] = {{"points", w.checked},
                       {"largest_difference_mm_per_N", w.check_max_mm_per_N},
                       {"relative", report::fixed(w.check_rel(), 4)},
                       {"at_mm", {report::fixed(w.check_worst_mm.x(), 4), report::fixed(w.check_worst_mm.y(), 4),
                                  report::fixed(w.check_worst_mm.z(), 4)}}};
  report::Json stages = report::Json::array();
  for (const WorkpieceStage& s : w.stages)
    stages.push_back({{"first_line", s.first_line},
                      {"boxes", s.boxes},
                      {"dofs", s.mesh.dofs},
                      {"mesh_s", report::fixed(s.mesh.mesh_seconds, 2)},
                      {"factorise_s", report::fixed(s.mesh.solve_seconds, 2)},
                      {"reached_points", s.reached_points},
                      {"nodes", s.nodes},
                      {"largest_mm_per_N", s.largest_mm_per_N}});
  js["stages"] = stages;
  js["contacts_outside_field"] = j.workpiece->uncovered();
  js["share"] = {{"workpiece", share_json(f.workpiece_share)}, {"tool", share_json(f.tool_share)}};
  return js;
}

void print_workpiece_shares(const Run& j, const report::RunFigures& f, Io& io) {
  if (!j.workpiece) return;
  io.info() << "deflex: of the deflection along the normal, the workpiece's share reaches "
            << share_text(f.workpiece_share) << ", the tool's " << share_text(f.tool_share) << "\n";
  if (const std::size_t n = j.workpiece->uncovered())
    io.err << "deflex: warning: " << n << " contact" << (n == 1 ? "" : "s")
           << " lay farther than twice the node spacing from every node of the workpiece's field: their "
              "compliance is the nearest node's\n";
}

std::vector<std::vector<std::string>> workpiece_facts(const Run& j, const report::RunFigures& f) {
  if (!j.workpiece) return {};
  return {{"largest share of the workpiece / the tool", share_text(f.workpiece_share) + " / " + share_text(f.tool_share),
           "workpiece"}};
}

}  // namespace deflex::job::detail
