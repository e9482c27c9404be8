// job::compensate() (job.hpp): the mirror pass over a program read whole or
// in pieces, the output written whole or not at all, the figures and the report.
#include <functional>
#include <ostream>

#include "deflex/compensate/apply.hpp"
#include "deflex/compensate/pipeline.hpp"
#include "deflex/report/summary.hpp"
#include "internal.hpp"
#include "workpiece_run.hpp"

namespace deflex::job {
namespace {

using compensate::V3;

// What a compensation ends with, read whole or in pieces.
struct Outcome {
  compensate::Result r;
  compensate::WriteStats ws;
  process::MachiningTime t0, t1;  // as written, compensated
};

bool to_stream(const Run& j) { return j.given.output.empty() || j.given.output == "-"; }

// On a program read in pieces: the same messages and output as on the whole
// program, memory bounded by a piece.
Outcome compensate_in_pieces(Run& j, std::ostream& out, const compensate::Progress& progress,
                             const compensate::PointSinks& sinks, compensate::PlausibilityScan& scan,
                             const std::function<void()>& refuse) {
  compensate::PipelineInput in = detail::pipeline_input(j, progress);
  in.sinks = sinks;
  in.on_piece = [&scan](const compensate::Result& r) { scan.capped(r.capped_lines); };
  // Nothing reads the initial stock after this: the mirror pass may cut it.
  j.physics.consumable_stock = j.stock.get();
  compensate::PipelineResult res;
  // The output appears whole or not at all: through a temporary file.
  // A collision found on the way refuses it inside the write: the temporary goes.
  auto fill = [&](std::ostream& o) {
    res = compensate::compensate_in_pieces(in, o);
    refuse();
  };
  if (to_stream(j)) writer::write_through_temporary(out, fill);
  else writer::write_file_atomically(j.given.output, j.given.program, fill);
  j.physics.stock = j.physics.consumable_stock = nullptr;
  return {std::move(res.totals), res.written, j.time_as_written, res.time};
}

// On the whole program (the input stream, subprograms, gain 0 with a feed limit).
Outcome compensate_whole(Run& j, std::ostream& out, const compensate::Progress& progress,
                         const compensate::PointSinks& sinks, compensate::PlausibilityScan& scan,
                         const std::function<void()>& refuse) {
  const std::vector<bool> split_ok = compensate::splittable(j.prog, j.motions);
  // Nothing reads the initial stock after this: the mirror pass may cut it.
  j.physics.consumable_stock = j.stock.get();
  Outcome o;
  o.r = compensate::compensate(j.motions, j.physics, j.settings, progress, &split_ok, &sinks);
  compensate::Result& r = o.r;
  j.physics.stock = j.physics.consumable_stock = nullptr;
  refuse();
  std::vector<bool> can = compensate::movable(r.motions);
  const std::vector<double>* feeds = j.settings.feed_limit_N > 0 ? &r.feeds_mm_per_min : nullptr;
  // The written program read back holds the only copy of the text.
  const gcode::Program written(
      SourceText(j.prog.source().name() + " (compensated)",
                 compensate::apply_offsets(j.prog, j.setup.dialect, r.motions, r.offsets, &o.ws, &r.inserted, feeds)));
  compensate::safety_check(j.prog, r.motions, written, j.setup.interp(), can, j.settings.max_offset_mm, &r.inserted, feeds);
  scan.capped(r.capped_lines);
  const profile::AxisLimits& lim = j.setup.machine->axis_limits;
  o.t0 = process::machining_time(j.motions, lim);
  o.t1 = process::machining_time(r.motions, lim, r.feeds_mm_per_min);
  const std::string& text = written.bytes();
  if (to_stream(j)) out << text;
  else writer::write_file_atomically(j.given.output, j.given.program, [&](std::ostream& f) { f << text; });
  return o;
}

// summary.json of a compensation.
report::Json summary_of(const Run& j, const CompensateResult& c) {
  const compensate::Result& r = c.result;
  const report::RunFigures& f = c.figures;
  report::Json js{{"file", j.prog.source().name()}, {"surface_error_mm", report::to_json(f.error)},
                  {"surface_error_as_written_mm", report::to_json(f.error_as_written)}, {"cl_points", f.error.points},
                  {"tolerance_mm", report::fixed(j.settings.tolerance_mm, 6)}, {"iterations", r.iterations},
                  {"evaluations", r.evaluations}, {"converged", r.converged},
                  {"compensated_points", r.compensated_points}, {"inserted_blocks", c.written.blocks_inserted},
                  {"capped_points", r.capped_lines.size()}, {"feed_lowered_blocks", r.feed_lowered_lines.size()}};
  js["cusp_height_mm"] = report::cusp_json(f.cusp);
  js["machining_time"] = {{"as_written", report::to_json(c.time_as_written)},
                          {"compensated", report::to_json(c.time_compensated)}};
  js["spindle"] = detail::spindle_json(f, j.physics.spindle);
  js["stability"] = detail::stability_json(f);
  js["warnings"] = detail::warnings_json(c.plausibility);
  js["left_alone"] = detail::left_alone_json(f);
  js["used"] = c.used.json;
  js["workpiece"] = detail::workpiece_json(j, f);
  return js;
}

// The key figures at the top of report.html, each with its summary.json key.
std::vector<std::vector<std::string>> facts_of(const Run& j, const CompensateResult& c) {
  const compensate::Result& r = c.result;
  std::vector<std::vector<std::string>> facts = {{"points compensated", std::to_string(r.compensated_points) + " of " + std::to_string(c.figures.error.points),
           "compensated_points"},
          {"points at the offset cap", std::to_string(r.capped_lines.size()), "capped_points"},
          {"blocks inserted to split moves", std::to_string(c.written.blocks_inserted), "inserted_blocks"},
          {"blocks with a lowered feed", std::to_string(r.feed_lowered_lines.size()), "feed_lowered_blocks"},
          {"machining time as written / compensated",
           report::clock(c.time_as_written.program.total_s) + " / " + report::clock(c.time_compensated.program.total_s),
           "machining_time"}};
  for (auto& w : detail::workpiece_facts(j, c.figures)) facts.push_back(std::move(w));
  return facts;
}

}  // namespace

namespace detail {

compensate::PipelineInput pipeline_input(Run& j, const compensate::Progress& progress) {
  compensate::PipelineInput in;
  in.path = j.given.program;
  in.lines_per_read = j.pieces->max_lines();
  in.motions_per_piece = j.pieces->max_lines();
  in.interp = j.setup.interp();
  in.fix = [&j](interp::Motion& m) {
    fill_cut_defaults(j.given, m);
    leave_gouge(m, j.gouge_lines);
  };
  in.physics = &j.physics;
  in.settings = &j.settings;
  in.progress = progress;
  in.total_motions = j.motion_count;
  in.limits = j.setup.machine->axis_limits;
  return in;
}

}  // namespace detail

CompensateResult compensate(Run& j, std::ostream& out, Io& io, Observer* obs, const std::string& command) {
  detail::Recording rec(j, true, obs);
  // The figures, the plausibility scan and the report take the points as the
  // simulations produce them; nothing keeps them (a million points are 270 MB).
  compensate::PlausibilityScan scan(j.physics.tools, j.settings, !j.given.stock_from.empty(), &j.physics.spindle);
  // Measured points are held against the program as written (the cut that was measured).
  if (!j.measured.empty()) j.settings.flank_profiles = true;
  const std::unique_ptr<fit::Nearest> nearest = detail::nearest_of(j);
  compensate::PointSinks sinks;
  compensate::CollisionScan collisions(j.physics.tools);
  sinks.nominal = [&](const compensate::Point& p) {
    scan.add(p);
    collisions.add(p, compensate::tool_id(p.tool, j.settings));
    rec.rec->as_written(p);
    if (nearest) nearest->add(p);
  };
  sinks.final = [&](const compensate::Point& p, const V3& off, std::size_t original) { rec.rec->point(p, off, original); };
  const compensate::Progress progress = detail::progress_of(obs);
  // The holder or the shank in the material (the program as written): an
  // error, and nothing is written.
  const std::function<void()> refuse = [&] {
    detail::refuse_collisions(j, collisions, io, "nothing compensated, nothing written");
  };
  Outcome o = j.pieces ? compensate_in_pieces(j, out, progress, sinks, scan, refuse)
                       : compensate_whole(j, out, progress, sinks, scan, refuse);
  detail::end_progress(progress);
  CompensateResult c;
  c.result = std::move(o.r);
  c.written = o.ws;
  c.time_as_written = o.t0;
  c.time_compensated = o.t1;
  c.figures = rec.rec->finish();
  c.plausibility = scan.finish(true);
  detail::print_left_alone(j, c.figures, io);
  detail::print_compensation(j, c.result, c.plausibility, io);
  detail::print_workpiece_shares(j, c.figures, io);
  c.used = used(j);
  c.summary = summary_of(j, c);
  if (nearest) {
    c.measured = detail::held_against(j, *nearest);
    detail::print_measured(j, *c.measured, io);
    c.summary["measured"] = detail::measured_json(*c.measured, j);
    if (!rec.dir.empty()) detail::write_measured_csv(rec.dir, *c.measured);
  }
  if (!rec.dir.empty())
    rec.finish(j, c.figures, c.summary, facts_of(j, c), "compensate", command, c.measured ? &*c.measured : nullptr);
  return c;
}

}  // namespace deflex::job
