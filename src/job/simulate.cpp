// job::simulate() (job.hpp): the surface error of a program, against its own
// path or against a reference's (the design intent of a compensated program).
#include "deflex/compensate/pairing.hpp"
#include "deflex/compensate/pipeline.hpp"
#include "deflex/report/summary.hpp"
#include "internal.hpp"
#include "workpiece_run.hpp"

namespace deflex::job {
namespace {

using compensate::V3;

// With a reference, the offset of each motion is how far this program's end
// point lies from the reference's: the design intent is the reference.
std::vector<V3> intent_offsets(const Run& j, Io& io) {
  const std::string& file = j.given.reference;
  gcode::Program ref(gcode::read_source(file, &io.in));
  Diagnostics diags = io.diagnostics(j.setup.max_errors);
  std::vector<interp::Motion> rm;
  interp::MotionList c(rm);
  interp::Options ro = j.setup.interp();
  ro.repeated_lines = nullptr;  // another program's lines
  interp::interpret(ref, ro, diags, c);
  if (diags.errors()) throw Error(ErrorKind::input, file + ": error: the reference program has errors").with_errors_of(diags);
  // Paired by the program structure (compensate/pairing.hpp): a motion the
  // compensation left alone has an intent offset of exactly zero; a block
  // deflex inserted is meant to lie on the move or arc it splits. F words
  // are left out of the skeletons: a feed limit changes them.
  const compensate::LinePairing lines =
      compensate::pair_lines(compensate::line_facts(ref, rm, true), compensate::line_facts(j.prog, j.motions, true),
                             compensate::pairing_options(j.setup.machine->max_offset_mm));
  return compensate::intent_offsets(lines, rm, j.motions, j.given.program);
}

// The design path: the program's motions less the intent offsets (the
// surface normals follow it), run with those offsets.
std::vector<interp::Motion> design_path(const std::vector<interp::Motion>& motions, const std::vector<V3>& intent) {
  std::vector<interp::Motion> moved = motions;
  for (std::size_t i = 0; i < intent.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      moved[i].start_mm[c] -= i ? intent[i - 1][c] : 0.0;
      moved[i].end_mm[c] -= intent[i][c];
      moved[i].center_mm[c] -= intent[i][c];
    }
  return moved;
}

report::Json summary_of(const Run& j, const SimulateResult& s) {
  report::Json js{{"file", j.prog.source().name()}, {"surface_error_mm", report::to_json(s.figures.error)},
                  {"cl_points", s.figures.error.points}, {"tolerance_mm", report::fixed(j.settings.tolerance_mm, 6)},
                  {"reference_file", j.given.reference.empty() ? report::Json() : report::Json(j.given.reference)}};
  js["cusp_height_mm"] = report::cusp_json(s.figures.cusp);
  js["machining_time"] = report::to_json(s.time);
  js["spindle"] = detail::spindle_json(s.figures, j.physics.spindle);
  js["stability"] = detail::stability_json(s.figures);
  js["warnings"] = detail::warnings_json(s.plausibility);
  js["used"] = s.used.json;
  js["workpiece"] = detail::workpiece_json(j, s.figures);
  return js;
}

}  // namespace

SimulateResult simulate(Run& j, Io& io, Observer* obs, const std::string& command) {
  std::vector<V3> intent;
  if (!j.given.reference.empty()) intent = intent_offsets(j, io);
  const compensate::Progress progress = detail::progress_of(obs);
  // No reference: the program itself, not a copy.
  std::vector<interp::Motion> moved;
  if (!intent.empty()) moved = design_path(j.motions, intent);
  const std::vector<interp::Motion>& design = intent.empty() ? j.motions : moved;
  // Nothing reads the initial stock after the simulation: it may cut it.
  j.physics.consumable_stock = j.stock.get();
  // Measured points are held against each flank slice's e(z), not only the mid-range.
  if (!j.measured.empty()) j.settings.flank_profiles = true;
  const std::unique_ptr<fit::Nearest> nearest = detail::nearest_of(j);
  // The points go to the recorder as they are produced; nothing keeps them.
  detail::Recording rec(j, false, obs);
  compensate::PlausibilityScan scan(j.physics.tools, j.settings, !j.given.stock_from.empty(), &j.physics.spindle);
  compensate::CollisionScan collisions(j.physics.tools);
  const compensate::PointSink sink = [&](const compensate::Point& p) {
    scan.add(p);
    collisions.add(p, compensate::tool_id(p.tool, j.settings));
    const V3 offset = report::offset_at(p, intent);
    rec.rec->point(p, offset, p.motion);
    if (nearest) nearest->add(p, offset);
  };
  if (j.pieces) {
    compensate::PipelineInput in = detail::pipeline_input(j, progress);
    in.sinks.nominal = sink;
    compensate::simulate_in_pieces(in);
  } else {
    compensate::simulate(design, intent, j.physics, j.settings, sink, progress);
  }
  j.physics.stock = j.physics.consumable_stock = nullptr;
  detail::end_progress(progress);
  // The holder or the shank in the material: the machine crashes there, so the
  // program is in error as a simulation of it (no report is written).
  detail::refuse_collisions(j, collisions, io, "no report written");
  SimulateResult s;
  s.figures = rec.rec->finish();
  s.plausibility = scan.finish(false);
  detail::print_plausibility(j, s.plausibility, io);
  detail::print_workpiece_shares(j, s.figures, io);
  s.time = j.pieces ? j.time_as_written : process::machining_time(j.motions, j.setup.machine->axis_limits);
  s.used = used(j);
  s.summary = summary_of(j, s);
  if (nearest) {
    s.measured = detail::held_against(j, *nearest);
    detail::print_measured(j, *s.measured, io);
    s.summary["measured"] = detail::measured_json(*s.measured, j);
    if (!rec.dir.empty()) detail::write_measured_csv(rec.dir, *s.measured);
  }
  if (!rec.dir.empty()) {
    std::vector<std::vector<std::string>> facts = {
        {"CL points in material", std::to_string(s.figures.error.points), "cl_points"},
        {"machining time", report::clock(s.time.program.total_s), "machining_time"}};
    for (auto& w : detail::workpiece_facts(j, s.figures)) facts.push_back(std::move(w));
    rec.finish(j, s.figures, s.summary, std::move(facts), "simulate", command, s.measured ? &*s.measured : nullptr);
  }
  return s;
}

}  // namespace deflex::job
