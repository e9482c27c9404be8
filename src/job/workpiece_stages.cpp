// The stages of the in-process workpiece (workpiece_run.hpp): the program's
// passes in equal groups, each seeing the stock as it is when its first
// pass begins.
//
// Why stages, and why at passes: the material still to come off stiffens the
// part (a thin wall finished in Z levels still has its roughing allowance
// below the level being cut). Re-meshing at every move is the exact model and
// costs a mesh and a factorisation each; material removal by element deletion
// on one fixed mesh (Ratchev et al., "Milling error prediction and
// compensation in machining of low-rigidity parts", IJMTM 44, 2004) cannot
// resolve an allowance thinner than an element, which a finishing allowance
// always is. So the stock itself is meshed at chosen moments: the Z-map as
// boxes united by OpenCASCADE (stock::zmap_boxes; exact faces, a 0.1 mm
// ledge stays one), its faceted surface (stock::zmap_mesh) for the nearest
// points and the clamp. The moments are the starts of passes (a cutting run
// between rapids) because there the tool is out of the material, and because
// a compensated program, whose inserted blocks fall inside passes, then has
// the same stages as its original: the judge sees the workpiece the
// compensation saw.
#include <algorithm>
#include <cmath>

#include "checks.hpp"
#include "workpiece_run.hpp"
#include "deflex/job/earlier.hpp"
#include "deflex/stock/mesh_out.hpp"

namespace deflex::job::detail {

namespace {

// The stock's surface (nearest points, the clamp) is within this of every
// cell's height, far below a finishing allowance.
constexpr double kStockMeshToleranceMm = 0.001;

bool starts_pass(const interp::Motion& m, bool after_rapid) { return m.kind != interp::MotionKind::rapid && after_rapid; }

// Walks the program's moves once in order, whole or piece by piece, with
// each move's index in program order.
void each_motion_batch(Run& j, const std::function<void(std::vector<interp::Motion>&, std::size_t first)>& fn) {
  std::size_t next = 0;
  auto one = [&](std::vector<interp::Motion>& ms) {
    fn(ms, next);
    next += ms.size();
  };
  if (j.pieces) each_piece(j, one);
  else one(j.motions);
}

}  // namespace

StagePlan plan_stages(Run& j, int stages, double margin_mm, double height_step_mm) {
  // The passes, counted first: the stages are equal groups of them.
  std::size_t passes = 0;
  bool after_rapid = true;
  each_motion_batch(j, [&](std::vector<interp::Motion>& ms, std::size_t) {
    for (const interp::Motion& m : ms) {
      if (starts_pass(m, after_rapid)) ++passes;
      after_rapid = m.kind == interp::MotionKind::rapid;
    }
  });
  const bool staged = stages > 0;
  const std::size_t n = staged ? std::max<std::size_t>(1, std::min<std::size_t>(static_cast<std::size_t>(stages), passes)) : 1;
  // Stage k begins at pass floor(k P / n): the groups differ by one pass at most.
  std::vector<std::size_t> first_pass(n);
  for (std::size_t k = 0; k < n; ++k) first_pass[k] = k * passes / n;

  StagePlan plan;
  std::unique_ptr<stock::ZMap> z;
  if (staged) z = std::make_unique<stock::ZMap>(j.physics.stock->clone());
  engage::PathOptions po;
  po.cl_spacing_mm = j.settings.cl_spacing_mm;
  const auto tool_of = [&j](const interp::Motion& m) { return compensate::tool_id(m, j.settings); };
  // Moves of the current stage: reached, and staged, swept into the stock
  // (with a profile per tool change, as an earlier operation's).
  auto add = [&](const std::vector<interp::Motion>& ms) {
    plan.reach.back().add(ms, j.physics.tools, tool_of, po);
    if (z) sweep_earlier(ms, *z, j.physics.tools, j.settings.cl_spacing_mm, j.settings.tool_override);
  };
  auto begin_stage = [&](std::size_t motion, std::uint32_t line) {
    plan.first_motion.push_back(motion);
    plan.first_line.push_back(line);
    plan.reach.emplace_back(margin_mm);
    if (!z) return;
    plan.surfaces.push_back(stock::zmap_mesh(*z, kStockMeshToleranceMm));
    plan.solids.push_back(stock::zmap_boxes(*z, height_step_mm));
  };
  // The first stage from the first move (the stock as given), named by its first pass.
  begin_stage(0, 0);
  std::size_t pass = 0;
  after_rapid = true;
  each_motion_batch(j, [&](std::vector<interp::Motion>& ms, std::size_t first) {
    // A piece goes to its stage whole (no copy) unless a stage begins inside it.
    std::size_t from = 0;
    auto to_stage = [&](std::size_t to) {
      if (to == from) return;
      if (from == 0 && to == ms.size()) add(ms);
      else add(std::vector<interp::Motion>(ms.begin() + static_cast<std::ptrdiff_t>(from), ms.begin() + static_cast<std::ptrdiff_t>(to)));
      from = to;
    };
    for (std::size_t i = 0; i < ms.size(); ++i) {
      const interp::Motion& m = ms[i];
      if (starts_pass(m, after_rapid)) {
        if (pass == 0) {
          plan.first_line.front() = m.line;
        } else if (plan.first_motion.size() < n && pass == first_pass[plan.first_motion.size()]) {
          to_stage(i);
          begin_stage(first + i, m.line);
        }
        ++pass;
      }
      after_rapid = m.kind == interp::MotionKind::rapid;
    }
    to_stage(ms.size());
  });
  return plan;
}

}  // namespace deflex::job::detail
