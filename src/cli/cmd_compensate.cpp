// deflex compensate | simulate: the product. Read a program, simulate the cut
// on the stock, predict where the deflected tool lands, and (compensate) move
// the cutting points by the mirror method and write the program back.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/compensate/apply.hpp"
#include "deflex/compensate/pairing.hpp"
#include "deflex/compensate/pipeline.hpp"
#include "deflex/report/html.hpp"
#include "deflex/report/recorder.hpp"
#include "deflex/report/stats.hpp"
#include "deflex/report/summary.hpp"
#include "deflex/writer/writer.hpp"
#include "job.hpp"

namespace deflex::cli {
namespace {
namespace fs = std::filesystem;
using compensate::V3;

const char* kCompensateHelp =
    "Simulates the cut of the program on the stock - engagement of the cutter in the\n"
    "material as cut so far, mean cutting force over a revolution, deflection of tool,\n"
    "holder, spindle and machine C(h)F - and moves each cutting point by the mirror\n"
    "method (P_comp = P_nom - gain e n, iterated to a fixed point) so that the deflected\n"
    "tool lands on the programmed surface. The fixed point is found in one pass in\n"
    "program order: each move end is solved (secant steps, one engagement evaluation\n"
    "each) with the moves before it already cut where they will run.\n"
    "Only the X/Y/Z (and a re-aimed arc's I/J/K) numbers of cutting blocks change (an\n"
    "axis word is added where a modal value would carry an offset into the next\n"
    "block; a G1/G2/G3 in G91 gets the increments that reach the compensated\n"
    "points); rapids, canned cycles, subprograms that run more than once (see\n"
    "--expand-subprograms), G41/G42 start-up moves, and points predicted inside\n"
    "+-tolerance stay as programmed. Under G41/G42 deflex simulates the tool centre's\n"
    "path (as `deflex path --centre` prints it, the D radius from the profile's\n"
    "tool_offsets or the tool library) and moves the programmed contour, so that the\n"
    "control's own offset lands the tool where the compensation means; the D words\n"
    "and the G41/G42 blocks stay as written. A long G1 whose error varies\n"
    "along it gets G1 blocks inserted before it; an arc whose compensation varies is\n"
    "linearised (G1 chords within 1 um, the arc block keeps the last piece) when its\n"
    "block has its own G2/G3 and I/J/K, else moved whole with a warning. Offsets are\n"
    "capped at the machine profile's max_offset_mm. The written program is read back\n"
    "and checked against the original before anything is written; with --gain 0 the\n"
    "output is the input. A long program is read, compensated, written and checked\n"
    "in pieces of 16,384 lines, so memory does not grow with it; --report writes\n"
    "points.csv as the points come and keeps what report.html draws on disk.\n"
    "--report DIR writes report.html (open it in a browser: provenance, summary, the\n"
    "surface in 3D and top views coloured by the error as written and compensated,\n"
    "plots of force, deflection, engagement and cusp along the path, the worst lines),\n"
    "points.csv (one row per CL point), flank_profile.csv and summary.json.\n"
    "--feed-limit N also lowers F (by the ratio of N to the predicted peak force) on\n"
    "cutting blocks whose peak force would exceed N, restoring the programmed F after.\n"
    "The surface normal (points.csv normal_source) comes, best first, from the part\n"
    "model (--part): the cutter's contact with the design surface at the programmed\n"
    "tip, where it lies within reach; else, for a ball end, from the tip surface\n"
    "fitted through the CL points of the same and the adjacent passes, where they\n"
    "determine it (not on a lone pass, nor on an edge pass without two passes\n"
    "beside it: such points are left as programmed and counted in the [left_alone]\n"
    "warning, normal_source undetermined); for flat and bull-nose ends from the\n"
    "tool and the travel: the wall of a flank cut, else the normal to the travel\n"
    "in its vertical plane (blind to a slope across the feed).\n";

void summary_line(Io& io, const char* what, const report::ErrorStats& s, double tol) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "  %-28s max %.4f mm, rms %.4f mm, %.1f%% of %s outside +-%.4f mm\n", what,
                s.max_abs, s.rms, 100.0 * s.share_out, plural(s.points, "point").c_str(), tol);
  io.info() << buf;
}

// The recorder of a run's points and, with --report, the report folder's
// files it streams: points.csv and flank_profile.csv, each renamed into place
// when the run ends well (flank_profile.csv only when a flank point has a
// profile). The folder gets summary.json and report.html at the end (finish).
struct Recording {
  Recording(const Args& a, const Job& j, bool as_written) : dir(a.report) {
    report::RecorderOptions o;
    o.tolerance_mm = j.settings.tolerance_mm;
    o.as_written = as_written;
    o.tool_of = tool_of(j);
    // Without a report nothing needs the cusp or the pairing: the figures only.
    o.cusp = !dir.empty();
    if (!dir.empty()) {
      std::error_code ec;
      fs::create_directories(dir, ec);
      if (ec) throw Error(ErrorKind::io, dir + ": error: cannot create the report folder: " + ec.message());
      points = std::make_unique<writer::AtomicFile>((fs::path(dir) / "points.csv").string(), "");
      flank = std::make_unique<writer::AtomicFile>((fs::path(dir) / "flank_profile.csv").string(), "");
      o.points_csv = &points->stream();
      o.flank_csv = &flank->stream();
      o.page = o.percentiles = true;
      o.spill_dir = dir;
    }
    rec = std::make_unique<report::Recorder>(std::move(o));
  }

  // points.csv and flank_profile.csv into place; summary.json and report.html.
  void finish(const Job& j, const report::RunFigures& f, const report::Json& summary,
              std::vector<std::vector<std::string>> facts, const char* what, const std::string& command,
              const std::string& reference) {
    points->commit();
    if (f.flank_rows) flank->commit();
    const fs::path d(dir);
    writer::write_file_atomically((d / "summary.json").string(), "",
                                  [&](std::ostream& o) { o << report::document(summary); });
    const report::Page page = rec->page();
    report::HtmlInput h;
    h.title = fs::path(j.prog.source().name()).filename().string() + ": deflex " + what;
    h.provenance = provenance(j, command, reference);
    h.summary = summary;
    h.page = &page;
    std::vector<std::uint32_t> lines;
    for (const auto& row : page.worst["rows"]) lines.push_back(row["line"].get<std::uint32_t>());
    for (const auto& [l, text] : lines_of_file(j, lines)) h.line_text[l] = std::string(text.line_text(l));
    h.tolerance_mm = j.settings.tolerance_mm;
    h.facts = std::move(facts);
    writer::write_file_atomically((d / "report.html").string(), "", [&](std::ostream& o) { o << report::report_html(h); });
  }

  std::string dir;
  std::unique_ptr<writer::AtomicFile> points, flank;
  std::unique_ptr<report::Recorder> rec;
};

// What compensate says of a run on stderr: lowered feeds, plausibility,
// capped offsets, linearised and non-uniform arcs, convergence, the counts,
// the predicted error before and after, the machining time.
void print_run(const Job& j, const compensate::Result& r, const compensate::WriteStats& ws,
               const compensate::Plausibility& pl, const report::ErrorStats& before, const report::ErrorStats& after,
               const process::MachiningTime& t0, const process::MachiningTime& t1, Io& io) {
  const double tol = j.settings.tolerance_mm;
  if (!r.feed_lowered_lines.empty()) {
    std::string lines;
    for (std::size_t i = 0; i < r.feed_lowered_lines.size() && i < 12; ++i)
      lines += (i ? ", " : "") + std::to_string(r.feed_lowered_lines[i]);
    if (r.feed_lowered_lines.size() > 12) lines += ", ...";
    io.info() << j.prog.source().name() << ": note: feed lowered on " << plural(r.feed_lowered_lines.size(), "block")
           << " to keep the peak force under " << j.settings.feed_limit_N << " N ("
           << (r.feed_lowered_lines.size() == 1 ? "line " : "lines ") << lines << ")\n";
  }
  print_plausibility(j, pl, io);
  if (!r.capped_lines.empty() && !pl.find("offset_cap")) {
    std::string lines;
    for (std::size_t i = 0; i < r.capped_lines.size() && i < 12; ++i) lines += (i ? ", " : "") + std::to_string(r.capped_lines[i]);
    if (r.capped_lines.size() > 12) lines += ", ...";
    io.err << j.prog.source().name() << ": warning: the offset was capped at max_offset_mm = " << j.settings.max_offset_mm
           << " mm on " << plural(r.capped_lines.size(), "point") << " ("
           << (r.capped_lines.size() == 1 ? "line " : "lines ") << lines << ")\n";
  }
  if (r.linearised_arcs)
    io.info() << j.prog.source().name() << ": note: " << plural(r.linearised_arcs, "arc")
           << (r.linearised_arcs == 1 ? " whose compensation varies along it was" : " whose compensation varies along them were")
           << " linearised (G1 chords within "
           << j.settings.chord_tol_mm << " mm of the arc; the arc block keeps the last piece)\n";
  for (std::uint32_t l : r.nonuniform_arcs)
    io.err << j.prog.source().name() << ":" << l
           << ":1: warning: the compensation varies along this arc by more than the tolerance; it is kept as a translated arc\n";
  if (!r.converged)
    io.err << j.prog.source().name() << ": warning: the mirror iteration did not converge in " << plural(r.iterations, "update")
           << " at " << plural(r.unconverged_points, "point") << " (largest change left " << r.last_change_mm
           << " mm); the best iterate is written\n";
  io.info() << j.prog.source().name() << ": " << plural(r.compensated_points, "point") << " compensated, "
            << plural(ws.numbers_changed, "number") << " changed, " << plural(ws.words_inserted, "axis word") << " added, "
            << plural(ws.blocks_inserted, "block") << " inserted to split moves; mirror: "
            << plural(r.evaluations, "engagement evaluation") << ", at most " << plural(r.iterations, "update")
            << " per point" << (r.converged ? "" : " (not converged)") << "\n";
  summary_line(io, "predicted error, as written:", before, tol);
  summary_line(io, "predicted error, compensated:", after, tol);
  time_line(io, t0, t1);
}

// The cutting moves deflex leaves as written, once per reason with a count
// and the first line (a note); and the points they leave outside the
// tolerance (a warning at the first such line): "N points compensated" is
// never silently smaller than the points outside the tolerance.
// The moves of a reason deflex leaves as written, and whether that may change.
std::string moves_of(interp::Fixed why) {
  switch (why) {
    case interp::Fixed::cutter_comp:
      return "cutter compensation start-up moves (G41/G42 entries), and moves under it in G91 or with G90.1 arcs";
    case interp::Fixed::incremental: return "incremental (G91) arcs with absolute centres (G90.1), not compensated";
    case interp::Fixed::subprogram: return "moves in subprograms that run more than once";
    case interp::Fixed::canned_cycle: return "canned-cycle moves (drilling is not a surface)";
    case interp::Fixed::machine_frame: return "moves in machine coordinates (G53/G28/G30)";
    case interp::Fixed::block_delete: return "block-delete '/' moves (run or not at the operator's switch)";
    case interp::Fixed::no_normal:
      return "points whose surface normal the program does not determine (a ball end without --part: the first "
             "or last pass without two passes beside it within 8 mm, a single pass, points off a smooth surface; "
             "give the part model with --part)";
    case interp::Fixed::held:
      return "moves ending where a block deflex cannot re-target starts (a canned cycle, G28/G30/G53, a subprogram "
             "that runs more than once, a change of work offset, an arc that stays)";
    case interp::Fixed::gouge:
      return "moves the gouge check finds cutting into the part (--part): the program gouges there, and compensating "
             "would move the gouge";
    default: return std::string("moves: ") + interp::to_string(why);
  }
}

// The subprogram of the first point left alone in one, its calls and the
// largest error left: the same blocks run at each call, so deflex cannot
// give each pass its own compensation in place.
std::string subprogram_calls(const Job& j, const report::RunFigures::LeftAlone& l) {
  const interp::CallStructure& c = *j.calls;
  const std::uint32_t o_line = l.first_line < c.sub_of.size() ? c.sub_of[l.first_line] : 0;
  std::string calls;
  auto it = c.calls.find(o_line);
  if (it != c.calls.end())
    for (std::uint32_t line : it->second) calls += (calls.empty() ? "" : ", ") + std::to_string(line);
  char buf[96];
  std::snprintf(buf, sizeof buf, "; the largest error left %.4f mm", l.largest_mm);
  return (o_line ? " (the first here, in " + c.name_of(o_line, j.prog) + ", called at line" +
                       (it != c.calls.end() && it->second.size() > 1 ? "s " : " ") + calls + ")"
                 : std::string(" (the first here)")) +
         buf + "; --expand-subprograms writes each call inline and compensates each pass";
}

void print_left_alone(const Job& j, const report::RunFigures& f, Io& io) {
  for (const auto& [why, l] : j.left_moves)
    io.info() << j.prog.source().name() << ": note: " << l.blocks << (l.blocks == 1 ? " executed block stays" : " executed blocks stay")
              << " as written: " << moves_of(why) << "; the first at line " << l.first_line << "\n";
  if (f.left_alone.empty()) return;
  std::vector<std::uint32_t> lines;
  for (const auto& [why, l] : f.left_alone) lines.push_back(l.first_line);
  const auto text = lines_of_file(j, lines);
  Diagnostics diags(&io.err, 0);
  for (const auto& [why, l] : f.left_alone) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s outside +-%.4f mm %s left as programmed on ", plural(l.points, "point").c_str(),
                  j.settings.tolerance_mm, l.points == 1 ? "is" : "are");
    std::string more = " (the first here)";
    if (why == interp::Fixed::subprogram && j.calls) more = subprogram_calls(j, l);
    diags.report(Severity::warning, text.at(l.first_line), l.first_line, 1, buf + moves_of(why) + more + " [left_alone]");
  }
}

report::Json left_alone_json(const report::RunFigures& f) {
  report::Json a = report::Json::array();
  for (const auto& [why, l] : f.left_alone)
    a.push_back({{"reason", interp::to_string(why)}, {"points", l.points}, {"first_line", l.first_line},
                 {"largest_error_mm", l.largest_mm}});
  return a;
}

// What the pipeline in pieces needs of a job read in pieces.
compensate::PipelineInput pipeline_input(Job& j, const Args& a, Io& io) {
  compensate::PipelineInput in;
  in.path = a.file;
  in.lines_per_read = j.pieces->max_lines();
  in.motions_per_piece = j.pieces->max_lines();
  in.interp = j.setup.interp();
  in.fix = [&a, &j](interp::Motion& m) {
    fill_cut_defaults(a, m);
    leave_gouge(m, j.gouge_lines);
  };
  in.physics = &j.physics;
  in.settings = &j.settings;
  in.progress = progress_for(io);
  in.total_motions = j.motion_count;
  in.limits = j.setup.machine->axis_limits;
  return in;
}

// What a compensation ends with, read whole or in pieces.
struct Outcome {
  compensate::Result r;
  compensate::WriteStats ws;
  process::MachiningTime t0, t1;  // as written, compensated
};

// compensate on a program read in pieces (prepare() decided): the same
// messages and output as on the whole program, memory bounded by a piece.
Outcome compensate_in_pieces(Job& j, const Args& a, Io& io, const compensate::PointSinks& sinks,
                             compensate::PlausibilityScan& scan) {
  compensate::PipelineInput in = pipeline_input(j, a, io);
  in.sinks = sinks;
  in.on_piece = [&scan](const compensate::Result& r) { scan.capped(r.capped_lines); };
  // Nothing reads the initial stock after this: the mirror pass may cut it.
  j.physics.consumable_stock = j.stock.get();
  compensate::PipelineResult res;
  // The output appears whole or not at all: through a temporary file.
  auto fill = [&](std::ostream& o) { res = compensate::compensate_in_pieces(in, o); };
  if (a.output.empty() || a.output == "-") writer::write_through_temporary(io.out, fill);
  else writer::write_file_atomically(a.output, a.file, fill);
  j.physics.stock = j.physics.consumable_stock = nullptr;
  end_progress(in.progress);
  return {std::move(res.totals), res.written, j.time_as_written, res.time};
}

// compensate on the whole program (stdin, subprograms, --gain 0 --feed-limit).
Outcome compensate_whole(Job& j, const Args& a, Io& io, const compensate::PointSinks& sinks,
                         compensate::PlausibilityScan& scan) {
  auto progress = progress_for(io);
  const std::vector<bool> split_ok = compensate::splittable(j.prog, j.motions);
  // Nothing reads the initial stock after this: the mirror pass may cut it.
  j.physics.consumable_stock = j.stock.get();
  Outcome o;
  o.r = compensate::compensate(j.motions, j.physics, j.settings, progress, &split_ok, &sinks);
  compensate::Result& r = o.r;
  j.physics.stock = j.physics.consumable_stock = nullptr;
  end_progress(progress);
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
  if (a.output.empty() || a.output == "-") io.out << text;
  else writer::write_file_atomically(a.output, a.file, [&](std::ostream& out) { out << text; });
  return o;
}

}  // namespace

int cmd_compensate(const std::vector<std::string>& args, Io& io) {
  Args a;
  po::options_description desc("options");
  describe(desc, a, true);
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
  apply_job(a, files);
  if (a.help) {
    print_help(io.out,
               "deflex compensate IN [-o OUT] [--machine M] [--tool-file F] [--tool ID] [--material M | --kt K --kr K "
               "--ka K [--kte K --kre K --kae K]] [--stock box:X0,Y0,Z0,X1,Y1,Z1 | --stock FILE] [--tolerance MM] "
               "[--gain G] [--report DIR]",
               kCompensateHelp, desc);
    return 0;
  }
  if (files.empty()) throw Error(ErrorKind::settings, "compensate: a program IN (or - for stdin) is required");
  a.file = files[0];
  // Every check of the command line before any computation.
  if (!a.output.empty() && a.output != "-") writer::check_output_path(a.output, a.file);
  if (!a.report.empty()) writer::check_output_folder(a.report);
  // A long program is read, compensated and written in pieces.
  Job j = prepare(a, io, true, nullptr, true);
  Recording rec(a, j, true);
  // The figures, the plausibility scan and the report take the points as the
  // simulations produce them; nothing keeps them (a million points are 270 MB).
  compensate::PlausibilityScan scan(j.physics.tools, j.settings, !j.stock_from.empty());
  compensate::PointSinks sinks;
  sinks.nominal = [&](const compensate::Point& p) {
    scan.add(p);
    rec.rec->as_written(p);
  };
  sinks.final = [&](const compensate::Point& p, const V3& off, std::size_t original) { rec.rec->point(p, off, original); };
  const Outcome o = j.pieces ? compensate_in_pieces(j, a, io, sinks, scan) : compensate_whole(j, a, io, sinks, scan);
  const compensate::Result& r = o.r;
  const report::RunFigures f = rec.rec->finish();
  const compensate::Plausibility pl = scan.finish(true);
  print_left_alone(j, f, io);
  print_run(j, r, o.ws, pl, f.error_as_written, f.error, o.t0, o.t1, io);
  const Used u = used(j);
  io.info() << "  " << u.text << "\n";
  if (a.report.empty()) return 0;
  const double tol = j.settings.tolerance_mm;
  report::Json js{{"file", j.prog.source().name()}, {"surface_error_mm", report::to_json(f.error)},
                  {"surface_error_as_written_mm", report::to_json(f.error_as_written)}, {"cl_points", f.error.points},
                  {"tolerance_mm", report::fixed(tol, 6)}, {"iterations", r.iterations},
                  {"evaluations", r.evaluations}, {"converged", r.converged},
                  {"compensated_points", r.compensated_points}, {"inserted_blocks", o.ws.blocks_inserted},
                  {"capped_points", r.capped_lines.size()}, {"feed_lowered_blocks", r.feed_lowered_lines.size()}};
  js["cusp_height_mm"] = report::cusp_json(f.cusp);
  js["machining_time"] = {{"as_written", report::to_json(o.t0)}, {"compensated", report::to_json(o.t1)}};
  js["warnings"] = warnings_json(pl);
  js["left_alone"] = left_alone_json(f);
  js["used"] = u.json;
  std::vector<std::vector<std::string>> facts = {
      {"points compensated", std::to_string(r.compensated_points) + " of " + std::to_string(f.error.points), "compensated_points"},
      {"points at the offset cap", std::to_string(r.capped_lines.size()), "capped_points"},
      {"blocks inserted to split moves", std::to_string(o.ws.blocks_inserted), "inserted_blocks"},
      {"blocks with a lowered feed", std::to_string(r.feed_lowered_lines.size()), "feed_lowered_blocks"},
      {"machining time as written / compensated", report::clock(o.t0.program.total_s) + " / " + report::clock(o.t1.program.total_s),
       "machining_time"}};
  rec.finish(j, f, js, std::move(facts), "compensate", command_of("compensate", args), "");
  return 0;
}

int cmd_simulate(const std::vector<std::string>& args, Io& io) {
  Args a;
  po::options_description desc("options");
  describe(desc, a, false);
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
  apply_job(a, files);
  if (a.help) {
    print_help(io.out,
               "deflex simulate IN [--reference ORIGINAL] [--report DIR] (options as deflex compensate)",
               "Predicts the surface error of a program without changing it: where the deflected\n"
               "tool lands against the programmed path, or with --reference, against the path of\n"
               "another program with the same blocks (the design intent): that is how a\n"
               "compensated program is judged. A summary goes to stdout; --report DIR writes\n"
               "report.html, points.csv and summary.json.\n",
               desc);
    return 0;
  }
  if (files.empty()) throw Error(ErrorKind::settings, "simulate: a program IN (or - for stdin) is required");
  a.file = files[0];
  if (!a.report.empty()) writer::check_output_folder(a.report);
  // Without --reference a long program is read in pieces.
  Job j = prepare(a, io, false, nullptr, a.reference.empty());
  // With a reference, the offset of each motion is how far this program's
  // end point lies from the reference's: the design intent is the reference.
  std::vector<V3> intent;
  if (!a.reference.empty()) {
    gcode::Program ref(gcode::read_source(a.reference, &io.in));
    Diagnostics diags(&io.err, j.setup.max_errors);
    std::vector<interp::Motion> rm;
    Collect c;
    c.out = &rm;
    interp::Options ro = j.setup.interp();
    ro.repeated_lines = nullptr;  // another program's lines
    interp::interpret(ref, ro, diags, c);
    if (diags.errors()) throw Error(ErrorKind::input, a.reference + ": error: the reference program has errors");
    // Paired by the program structure (compensate/pairing.hpp): a motion the
    // compensation left alone has an intent offset of exactly zero; a block
    // deflex inserted is meant to lie on the move or arc it splits. F words
    // are left out of the skeletons: --feed-limit changes them.
    const compensate::LinePairing lines =
        compensate::pair_lines(compensate::line_facts(ref, rm, true), compensate::line_facts(j.prog, j.motions, true),
                               compensate::pairing_options(j.setup.machine->max_offset_mm));
    intent = compensate::intent_offsets(lines, rm, j.motions, a.file);
  }
  auto progress = progress_for(io);
  // The design path: this program's motions less the intent offsets (the
  // surface normals follow it), run with those offsets.
  // (No reference: the program itself, not a copy.)
  std::vector<interp::Motion> moved;
  if (!intent.empty()) moved = j.motions;
  for (std::size_t i = 0; i < intent.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      moved[i].start_mm[c] -= i ? intent[i - 1][c] : 0.0;
      moved[i].end_mm[c] -= intent[i][c];
      moved[i].center_mm[c] -= intent[i][c];
    }
  const std::vector<interp::Motion>& design = intent.empty() ? j.motions : moved;
  // Nothing reads the initial stock after the simulation: it may cut it.
  j.physics.consumable_stock = j.stock.get();
  // The points go to the recorder as they are produced; nothing keeps them.
  Recording rec(a, j, false);
  compensate::PlausibilityScan scan(j.physics.tools, j.settings, !j.stock_from.empty());
  const compensate::PointSink sink = [&](const compensate::Point& p) {
    scan.add(p);
    rec.rec->point(p, report::offset_at(p, intent), p.motion);
  };
  if (j.pieces) {
    compensate::PipelineInput in = pipeline_input(j, a, io);
    in.progress = progress;  // the one end_progress() closes
    in.sinks.nominal = sink;
    compensate::simulate_in_pieces(in);
  } else {
    compensate::simulate(design, intent, j.physics, j.settings, sink, progress);
  }
  j.physics.stock = j.physics.consumable_stock = nullptr;
  end_progress(progress);
  const report::RunFigures f = rec.rec->finish();
  const compensate::Plausibility pl = scan.finish(false);
  print_plausibility(j, pl, io);
  const report::ErrorStats& st = f.error;
  const double tol = j.settings.tolerance_mm;
  char buf[300];
  std::snprintf(buf, sizeof buf,
                "%s: %s%s: surface error max %.4f mm, rms %.4f mm, %.1f%% outside +-%.4f mm "
                "(undercut up to %.4f, overcut up to %.4f mm)\n",
                j.prog.source().name().c_str(), plural(st.points, "CL point").c_str(), a.reference.empty() ? "" : " against the reference",
                st.max_abs, st.rms, 100.0 * st.share_out, tol, st.max_under, -st.max_over);
  io.out << buf;
  const process::MachiningTime tm =
      j.pieces ? j.time_as_written : process::machining_time(j.motions, j.setup.machine->axis_limits);
  time_line(io, tm, tm);
  const Used u = used(j);
  io.info() << "  " << u.text << "\n";
  if (a.report.empty()) return 0;
  report::Json js{{"file", j.prog.source().name()}, {"surface_error_mm", report::to_json(st)},
                  {"cl_points", st.points}, {"tolerance_mm", report::fixed(tol, 6)},
                  {"reference_file", a.reference.empty() ? report::Json() : report::Json(a.reference)}};
  js["cusp_height_mm"] = report::cusp_json(f.cusp);
  js["machining_time"] = report::to_json(tm);
  js["warnings"] = warnings_json(pl);
  js["used"] = u.json;
  std::vector<std::vector<std::string>> facts = {
      {"CL points in material", std::to_string(st.points), "cl_points"},
      {"machining time", report::clock(tm.program.total_s), "machining_time"}};
  rec.finish(j, f, js, std::move(facts), "simulate", command_of("simulate", args), a.reference);
  return 0;
}

}  // namespace deflex::cli
