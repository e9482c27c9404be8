// deflex compensate | simulate: the product. Read a program, simulate the cut
// on the stock, predict where the deflected tool lands, and (compensate) move
// the cutting points by the mirror method and write the program back.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>

#include "common.hpp"
#include "deflex/compensate/apply.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/compensate/pairing.hpp"
#include "deflex/compensate/plausibility.hpp"
#include "deflex/engage/path.hpp"
#include "deflex/interp/decimal.hpp"
#include "deflex/interp/shape.hpp"
#include "deflex/interp/travel.hpp"
#include "deflex/process/machining_time.hpp"
#include "deflex/report/html.hpp"
#include "deflex/report/json.hpp"
#include "deflex/report/points.hpp"
#include "deflex/report/stats.hpp"
#include "deflex/report/summary.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::cli {
namespace {
namespace fs = std::filesystem;
using compensate::V3;

struct Args {
  ReadOptions read;
  MaterialOptions mat;
  PartOptions part;
  std::string file, output, reference, tool_file, tool, stock, report;
  std::optional<double> tolerance, gain;
  double feed_limit_N = 0;
  std::optional<double> spindle_rpm, feed_mm_per_min;
  double cell_mm = 0.05, cl_spacing_mm = 0.5;
  int max_iterations = 8, threads = 0;
  bool tool_only = false, help = false;
};

void describe(po::options_description& d, Args& a, bool compensating) {
  auto opt = [](std::optional<double>& dst) { return po::value<double>()->notifier([&dst](double v) { dst = v; }); };
  d.add_options()("help,h", po::bool_switch(&a.help), "show this help");
  if (compensating)
    d.add_options()("output,o", po::value(&a.output), "write the compensated program here (atomically); default stdout")
        ("feed-limit", po::value(&a.feed_limit_N), "also lower F where the peak cutting force would exceed this, N");
  else d.add_options()("reference", po::value(&a.reference), "judge against this program's path (the design intent), e.g. the original of a compensated program");
  d.add_options()
      ("tool-file", po::value(&a.tool_file), "tool library (default: config tool_file, else samples/tools.yaml)")
      ("tool", po::value(&a.tool), "use this tool for every cut (default: the program's T words, as T<n>)")
      ("spindle", opt(a.spindle_rpm), "spindle speed, rpm, for cutting moves the program gives no S (or S0)")
      ("feed", opt(a.feed_mm_per_min), "feed, mm/min, for cutting moves the program gives no F")
      ("stock", po::value(&a.stock), "box:X0,Y0,Z0,X1,Y1,Z1 (mm, work frame) or an STL/STEP/IGES solid (default: config stock)")
      ("tolerance", opt(a.tolerance), "surface tolerance, mm: points predicted inside +-tolerance stay as programmed (default 0.01)")
      ("gain", opt(a.gain), "mirror gain: 1 reflects the whole deflection, 0 changes nothing (default 1)")
      ("report", po::value(&a.report), "write report.html, points.csv (one row per CL point), flank_profile.csv (flank cuts) and summary.json into this folder")
      ("cell-mm", po::value(&a.cell_mm)->default_value(0.05), "Z-map cell size, mm (finishing: 0.05; 0.1 is ~4x faster)")
      ("cl-spacing", po::value(&a.cl_spacing_mm)->default_value(0.5), "largest distance between CL points along a move, mm")
      ("max-iterations", po::value(&a.max_iterations)->default_value(8), "mirror updates per point at most (secant steps toward the fixed point)")
      ("threads", po::value(&a.threads)->default_value(0), "worker threads (0: all cores)")
      ("tool-only", po::bool_switch(&a.tool_only), "leave holder, spindle and machine out of the compliance");
  add_part_options(d, a.part);
  add_material_options(d, a.mat);
  add_read_options(d, a.read);
}

struct Job {
  Setup setup;
  std::string material, stock_spec, part_spec;  // as given, for the report's provenance
  gcode::Program prog;
  std::vector<interp::Motion> motions;
  compensate::Physics physics;
  compensate::Settings settings;
  std::unique_ptr<stock::ZMap> stock;
  std::unique_ptr<part::PartModel> part;
};

struct Collect : interp::MotionSink {
  std::vector<interp::Motion>* out;
  void motion(const interp::Motion& m) override { out->push_back(m); }
};

// The settings from the options and config.yaml, each checked (usage errors
// before anything is read or computed).
compensate::Settings settings_of(const Args& a, const profile::Config& cfg, const profile::MachineProfile& mp) {
  compensate::Settings st;
  st.tolerance_mm = a.tolerance ? *a.tolerance : config_number(cfg, "tolerance_mm", 0.01);
  st.gain = a.gain ? *a.gain : config_number(cfg, "gain", 1.0);
  st.max_offset_mm = mp.max_offset_mm;
  st.cl_spacing_mm = a.cl_spacing_mm;
  st.max_iterations = a.max_iterations;
  st.threads = a.threads;
  st.tool_override = !a.tool.empty() ? a.tool : config_string(cfg, "tool");
  st.feed_limit_N = a.feed_limit_N;
  st.flank_profiles = !a.report.empty();  // flank_profile.csv of the program as written
  if (a.feed_limit_N < 0) throw Error(Exit::usage, "--feed-limit must be > 0 N");
  if (!(st.tolerance_mm > 0)) throw Error(Exit::usage, "--tolerance must be > 0 mm");
  if (!(st.gain >= 0 && st.gain <= 2)) throw Error(Exit::usage, "--gain must be between 0 and 2");
  if (!(a.cl_spacing_mm > 0)) throw Error(Exit::usage, "--cl-spacing must be > 0 mm");
  if (a.max_iterations < 1 || a.max_iterations > 50) throw Error(Exit::usage, "--max-iterations must be 1..50");
  if (a.threads < 0 || a.threads > 1024) throw Error(Exit::usage, "--threads must be 0 (all cores) .. 1024");
  if (!(a.cell_mm >= 0.005 && a.cell_mm <= 5)) throw Error(Exit::usage, "--cell-mm must be between 0.005 and 5");
  if (a.spindle_rpm && !(*a.spindle_rpm > 0 && *a.spindle_rpm <= 1e6)) throw Error(Exit::usage, "--spindle must be > 0 rpm");
  if (a.feed_mm_per_min && !(*a.feed_mm_per_min > 0 && *a.feed_mm_per_min <= 1e6))
    throw Error(Exit::usage, "--feed must be > 0 mm/min");
  return st;
}

// What the simulation needs of every cutting motion, before it runs: a tool
// in the library, a spindle speed and a feed (--spindle, --feed supply what
// the program lacks). Errors at the line of the first motion lacking each.
void check_cutting(std::vector<interp::Motion>& motions, const Args& a, const compensate::Settings& st,
                   const stiffness::ToolLibrary& lib, const SourceText& src, Diagnostics& diags) {
  // A tool named on the command line that the library lacks is a usage error
  // (exit 2, with the library's tools); a T word of the program the library
  // lacks is the library's (exit 3).
  if (!st.tool_override.empty()) (void)stiffness::find_tool(lib, st.tool_override);
  bool no_s = false, no_f = false;
  for (interp::Motion& m : motions) {
    if (m.kind == interp::MotionKind::rapid) continue;
    if (m.spindle_rpm <= 0 && a.spindle_rpm) m.spindle_rpm = *a.spindle_rpm;
    if (m.feed_mm_per_min <= 0 && a.feed_mm_per_min) m.feed_mm_per_min = *a.feed_mm_per_min;
    const std::string id = compensate::tool_id(m, st);
    if (m.tool == 0 && st.tool_override.empty()) {
      diags.report(Severity::error, src, m.line, 1, "cutting with no tool selected (T.. M6): give --tool");
      throw Error(Exit::usage, src.name() + ": error: no tool; nothing done");
    }
    if (!lib.tools.count(id)) {
      diags.report(Severity::error, src, m.line, 1,
                   "tool " + id + " is not in the tool library " + lib.file + " (give --tool-file, or --tool)");
      throw Error(Exit::config, src.name() + ": error: a tool of the program is missing from the library; nothing done");
    }
    if (!no_s && m.spindle_rpm <= 0) {
      no_s = true;
      diags.report(Severity::error, src, m.line, 1, "cutting with no spindle speed (S0 or no S word): give --spindle RPM");
    }
    if (!no_f && m.feed_mm_per_min <= 0) {
      no_f = true;
      diags.report(Severity::error, src, m.line, 1, "cutting with no feed (F0 or no F word): give --feed MM_PER_MIN");
    }
  }
}

// Reads the program and everything the physics needs; throws on any error.
// Every check that can fail runs before the stock and part are built.
Job prepare(Args& a, Io& io, bool compensating) {
  Setup s = resolve(a.read);
  if (!s.machine) throw Error(Exit::usage, "a machine profile is needed (--machine, or machine: in config.yaml)");
  Job j{std::move(s), {}, {}, {}, gcode::Program(gcode::read_source(a.file, &io.in)), {}, {}, {}, {}, {}};
  const profile::Config& cfg = j.setup.config;
  compensate::Settings& st = j.settings;
  st = settings_of(a, cfg, *j.setup.machine);
  std::string stock = !a.stock.empty() ? a.stock : config_path(cfg, "stock");
  if (stock.empty()) throw Error(Exit::usage, "no stock: give --stock box:X0,Y0,Z0,X1,Y1,Z1 or a solid file (or stock: in config.yaml)");
  j.stock_spec = stock;
  j.physics.tools = stiffness::load_tool_library(tool_library_path(a.tool_file, cfg));
  j.physics.machine = stiffness::parse_machine_stiffness(j.setup.machine->root, j.setup.machine->file);
  j.physics.tool_only = a.tool_only;
  MaterialOptions mat = a.mat;
  if (mat.material_file.empty() && mat.material.empty() && !mat.kt) mat.material_file = config_path(cfg, "material_file");
  else if (mat.material_file.empty() && !mat.material.empty()) mat.material_file = config_path(cfg, "material_file");
  j.physics.k = coefficients_of(mat, config_string(cfg, "material"), &j.material);
  Diagnostics diags(&io.err, j.setup.max_errors);
  interp::check_program_shape(j.prog, diags);
  interp::check_decimal_points(j.prog, j.setup.dialect, diags, j.setup.strict);
  Collect c;
  c.out = &j.motions;
  interp::interpret(j.prog, j.setup.interp(), diags, c);
  // The machine's travel before any simulation: a move far outside it is a
  // crash on the machine and unbounded work here.
  for (const interp::Motion& m : j.motions) interp::check_travel(m, j.setup.machine->travel, j.prog.source(), diags);
  if (!diags.errors()) check_cutting(j.motions, a, st, j.physics.tools, j.prog.source(), diags);
  if (diags.errors())
    throw Error(Exit::input, j.prog.source().name() + ": error: the program has errors; " +
                                 (compensating ? "nothing compensated, nothing written" : "not simulated"));
  const std::string part = !a.part.part.empty() ? a.part.part : config_path(cfg, "part");
  if (!part.empty()) {
    j.part_spec = part;
    j.part = std::make_unique<part::PartModel>(part::PartModel::load(part));
    j.physics.part = j.part.get();
  }
  stock::SolidOptions so;
  so.cell_mm = a.cell_mm;
  j.stock = std::make_unique<stock::ZMap>(stock::make_stock(stock, so));
  j.physics.stock = j.stock.get();
  if (j.part && a.reference.empty()) {
    // The gouge check runs before the simulation: it needs no stock and no
    // forces. Not on a program judged against a reference: a compensated
    // program stands off the part on purpose (the reference is the design).
    const double gap = a.part.gap_mm ? *a.part.gap_mm : config_number(cfg, "part_gap_mm", 0.02);
    if (!(gap > 0)) throw Error(Exit::usage, "--part-gap must be > 0 mm");
    engage::PathOptions po;
    po.cl_spacing_mm = st.cl_spacing_mm;
    const compensate::PartGaps g = compensate::part_gaps(
        j.motions, *j.part, j.physics.tools, [&st](const interp::Motion& m) { return compensate::tool_id(m, st); }, po,
        gap, st.part_reach_mm);
    report_part_gaps(g, j.prog.source(), gap, diags);
  }
  return j;
}

compensate::Progress progress_for(Io& io) {
  if (!io.err_is_terminal) return {};
  return [&io](const std::string& stage, double f) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "\r\033[Kdeflex: %s %3.0f%%", stage.c_str(), 100.0 * f);
    io.err << buf << std::flush;
  };
}

// A number as a person writes it: 0.01, 80, 2.5.
std::string report_number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

// The run's provenance for report.html: what a reader needs to trust or redo it.
std::vector<std::pair<std::string, std::string>> provenance(const Job& j, const std::string& command,
                                                            const std::string& reference) {
  std::vector<std::pair<std::string, std::string>> p;
  p.emplace_back("program", j.prog.source().name());
  p.emplace_back("program SHA-256", report::sha256_hex(j.prog.source().bytes()));
  if (!reference.empty()) p.emplace_back("judged against", reference);
  p.emplace_back("machine", j.setup.machine->name + " (" + j.setup.machine->file + "), dialect " + j.setup.dialect.name);
  std::set<std::string> tools;
  for (const interp::Motion& m : j.motions)
    if (m.kind != interp::MotionKind::rapid) tools.insert(compensate::tool_id(m, j.settings));
  for (const std::string& id : tools) {
    const stiffness::Tool& t = j.physics.tools.tools.at(id);
    char buf[200];
    std::snprintf(buf, sizeof buf, "%s: %s D%g mm%s, %d flutes, helix %g deg, stick-out %g mm, flutes %g mm long",
                  id.c_str(), t.type == stiffness::ToolType::ball ? "ball" : t.type == stiffness::ToolType::bull ? "bull nose" : "flat",
                  t.diameter_mm, t.type == stiffness::ToolType::bull ? (" r" + report_number(t.corner_radius_mm)).c_str() : "",
                  t.flutes, t.helix_deg, t.stickout_mm, t.flute_length_mm);
    p.emplace_back("tool", buf);
  }
  p.emplace_back("tool library", j.physics.tools.file);
  p.emplace_back("material", j.material);
  p.emplace_back("stock", j.stock_spec);
  p.emplace_back("part model", j.part_spec.empty() ? "none (normals fitted through the path, or from the travel)" : j.part_spec);
  p.emplace_back("tolerance", report_number(j.settings.tolerance_mm) + " mm");
  p.emplace_back("deflex", std::string(DEFLEX_VERSION));
  p.emplace_back("date", report::utc_now());
  p.emplace_back("command", command);
  return p;
}

// Plausibility warnings (compensate/plausibility.hpp), compiler style at the
// line of the worst point, and their summary.json array.
compensate::Plausibility report_plausibility(const Job& j, const std::vector<compensate::Point>& pts, Io& io,
                                             const std::vector<std::uint32_t>* capped_lines = nullptr) {
  compensate::Plausibility pl = compensate::plausibility(j.motions, pts, j.physics.tools, j.settings, capped_lines);
  Diagnostics diags(&io.err, 0);
  for (const compensate::Finding& f : pl.findings)
    diags.report(Severity::warning, j.prog.source(), f.line, 1, f.message + " [" + f.kind + "]");
  return pl;
}

report::Json warnings_json(const compensate::Plausibility& pl) {
  report::Json a = report::Json::array();
  for (const compensate::Finding& f : pl.findings)
    a.push_back({{"kind", f.kind}, {"count", f.count}, {"worst", report::fixed(f.worst, 4)},
                 {"limit", report::fixed(f.limit, 4)}, {"tool", f.tool}, {"line", f.line},
                 {"line_count", f.line_count}, {"lines", f.lines}, {"message", f.message}});
  return a;
}

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
    "block); rapids, canned cycles, subprograms, G91 and G41/G42 moves, and points\n"
    "predicted inside +-tolerance stay as programmed. A long G1 whose error varies\n"
    "along it gets G1 blocks inserted before it; an arc whose compensation varies is\n"
    "linearised (G1 chords within 1 um, the arc block keeps the last piece) when its\n"
    "block has its own G2/G3 and I/J/K, else moved whole with a warning. Offsets are\n"
    "capped at the machine profile's max_offset_mm. The written program is read back\n"
    "and checked against the original before anything is written; with --gain 0 the\n"
    "output is the input.\n"
    "--report DIR writes report.html (open it in a browser: provenance, summary, the\n"
    "surface in 3D and top views coloured by the error as written and compensated,\n"
    "plots of force, deflection, engagement and cusp along the path, the worst lines),\n"
    "points.csv (one row per CL point), flank_profile.csv and summary.json.\n"
    "--feed-limit N also lowers F (by the ratio of N to the predicted peak force) on\n"
    "cutting blocks whose peak force would exceed N, restoring the programmed F after.\n"
    "The surface normal comes from the tool and the programmed path: the wall for a\n"
    "flat or bull-nose flank, else the normal to the travel in its vertical plane.\n";

void summary_line(Io& io, const char* what, const report::ErrorStats& s, double tol) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "  %-28s max %.4f mm, rms %.4f mm, %.1f%% of %zu points outside +-%.4f mm\n", what,
                s.max_abs, s.rms, 100.0 * s.share_out, s.points, tol);
  io.err << buf;
}

// Machining time from the machine's axis limits (process/machining_time.hpp).
void time_line(Io& io, const process::MachiningTime& before, const process::MachiningTime& after) {
  io.err << "  machining time:              " << report::clock(before.program.total_s) << " (cutting "
         << report::clock(before.program.cutting_s) << ", rapids " << report::clock(before.program.rapid_s) << ")";
  if (std::fabs(after.program.total_s - before.program.total_s) >= 0.5)
    io.err << ", compensated " << report::clock(after.program.total_s);
  io.err << " [m:ss, axis limits of the machine profile]\n";
}

std::string command_of(const char* cmd, const std::vector<std::string>& args) {
  std::string c = std::string("deflex ") + cmd;
  for (const std::string& w : args) {
    const bool plain = !w.empty() && w.find_first_not_of(
        "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.,:/=+@%") == std::string::npos;
    std::string q = "'";
    for (char ch : w) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    c += " " + (plain ? w : q + "'");
  }
  return c;
}

// The report folder: points.csv, flank_profile.csv (flank cuts), summary.json
// and report.html (whose top views replaced the SVG maps of earlier versions).
// `motions`: those the table's points index (a compensation's, with its inserted blocks).
void write_folder(const std::string& dir, const Job& j, const report::PointTable& t,
                  const std::vector<interp::Motion>& motions,
                  const std::vector<compensate::Point>& as_written, const report::Json& summary,
                  std::vector<std::vector<std::string>> facts, const char* what, const std::string& command,
                  const std::string& reference) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error(Exit::io, dir + ": error: cannot create the report folder: " + ec.message());
  const fs::path d(dir);
  report::write_points_csv((d / "points.csv").string(), t);
  report::write_flank_profile_csv((d / "flank_profile.csv").string(), as_written);
  writer::write_file_atomically((d / "summary.json").string(), "",
                                [&](std::ostream& o) { o << report::document(summary); });
  report::HtmlInput h;
  h.title = fs::path(j.prog.source().name()).filename().string() + ": deflex " + what;
  h.provenance = provenance(j, command, reference);
  h.summary = summary;
  h.table = &t;
  h.contact_mm = report::contact_points(t, motions, j.physics, j.settings);
  h.source = &j.prog.source();
  h.tolerance_mm = j.settings.tolerance_mm;
  h.facts = std::move(facts);
  const report::Json cusp = summary.value("cusp_height_mm", report::Json());
  if (!cusp.is_null() && cusp.value("points", 0) > 0)
    h.facts.push_back({"cusp height, max / mean (Miko Eq. 7)", report_number(1000 * cusp.value("max", 0.0)) + " / " +
                                                                   report_number(1000 * cusp.value("mean", 0.0)) + " µm",
                       "cusp_height_mm"});
  writer::write_file_atomically((d / "report.html").string(), "", [&](std::ostream& o) { o << report::report_html(h); });
}

}  // namespace

int cmd_compensate(const std::vector<std::string>& args, Io& io) {
  Args a;
  po::options_description desc("options");
  describe(desc, a, true);
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
  if (a.help) {
    print_help(io.out,
               "deflex compensate IN [-o OUT] [--machine M] [--tool-file F] [--tool ID] [--material M | --kt K --kr K "
               "--ka K [--kte K --kre K --kae K]] [--stock box:X0,Y0,Z0,X1,Y1,Z1 | --stock FILE] [--tolerance MM] "
               "[--gain G] [--report DIR]",
               kCompensateHelp, desc);
    return 0;
  }
  if (files.empty()) throw Error(Exit::usage, "compensate: a program IN (or - for stdin) is required");
  a.file = files[0];
  // Every check of the command line before any computation.
  if (!a.output.empty() && a.output != "-") writer::check_output_path(a.output, a.file);
  if (!a.report.empty()) writer::check_output_folder(a.report);
  Job j = prepare(a, io, true);
  auto progress = progress_for(io);
  const std::vector<bool> split_ok = compensate::splittable(j.prog, j.motions);
  compensate::Result r = compensate::compensate(j.motions, j.physics, j.settings, progress, &split_ok);
  if (progress) io.err << "\r\033[K";
  std::vector<bool> can = compensate::movable(r.motions);
  compensate::WriteStats ws;
  const std::vector<double>* feeds = j.settings.feed_limit_N > 0 ? &r.feeds_mm_per_min : nullptr;
  std::string text = compensate::apply_offsets(j.prog, j.setup.dialect, r.motions, r.offsets, &ws, &r.inserted, feeds);
  compensate::safety_check(j.prog, r.motions, text, j.setup.interp(), can, j.settings.max_offset_mm, &r.inserted, feeds);
  if (!r.feed_lowered_lines.empty()) {
    std::string lines;
    for (std::size_t i = 0; i < r.feed_lowered_lines.size() && i < 12; ++i)
      lines += (i ? ", " : "") + std::to_string(r.feed_lowered_lines[i]);
    if (r.feed_lowered_lines.size() > 12) lines += ", ...";
    io.err << j.prog.source().name() << ": note: feed lowered on " << r.feed_lowered_lines.size()
           << " blocks to keep the peak force under " << j.settings.feed_limit_N << " N (lines " << lines << ")\n";
  }
  const compensate::Plausibility pl = report_plausibility(j, r.nominal, io, &r.capped_lines);
  if (!r.capped_lines.empty() && !pl.find("offset_cap")) {
    std::string lines;
    for (std::size_t i = 0; i < r.capped_lines.size() && i < 12; ++i) lines += (i ? ", " : "") + std::to_string(r.capped_lines[i]);
    if (r.capped_lines.size() > 12) lines += ", ...";
    io.err << j.prog.source().name() << ": warning: the offset was capped at max_offset_mm = " << j.settings.max_offset_mm
           << " mm on " << r.capped_lines.size() << " points (lines " << lines << ")\n";
  }
  if (r.linearised_arcs)
    io.err << j.prog.source().name() << ": note: " << r.linearised_arcs
           << " arcs whose compensation varies along them were linearised (G1 chords within "
           << j.settings.chord_tol_mm << " mm of the arc; the arc block keeps the last piece)\n";
  for (std::uint32_t l : r.nonuniform_arcs)
    io.err << j.prog.source().name() << ":" << l
           << ":1: warning: the compensation varies along this arc by more than the tolerance; it is kept as a translated arc\n";
  if (!r.converged)
    io.err << j.prog.source().name() << ": warning: the mirror iteration did not converge in " << r.iterations
           << " updates at " << r.unconverged_points << " points (largest change left " << r.last_change_mm
           << " mm); the best iterate is written\n";
  const double tol = j.settings.tolerance_mm;
  const report::ErrorStats before = report::error_stats(report::landing_errors(r.nominal, {}), tol);
  const report::ErrorStats after = report::error_stats(report::landing_errors(r.final, r.offsets), tol);
  io.err << j.prog.source().name() << ": " << r.compensated_points << " points compensated, " << ws.numbers_changed
         << " numbers changed, " << ws.words_inserted << " axis words added, " << ws.blocks_inserted
         << " blocks inserted to split moves; mirror: " << r.evaluations << " engagement evaluations, at most "
         << r.iterations << " updates per point" << (r.converged ? "" : " (not converged)") << "\n";
  summary_line(io, "predicted error, as written:", before, tol);
  summary_line(io, "predicted error, compensated:", after, tol);
  const profile::AxisLimits& lim = j.setup.machine->axis_limits;
  const process::MachiningTime t0 = process::machining_time(j.motions, lim);
  const process::MachiningTime t1 = process::machining_time(r.motions, lim, r.feeds_mm_per_min);
  time_line(io, t0, t1);
  if (!a.report.empty()) {
    report::PointTable t = report::table_of_compensation(r, j.motions, j.physics, j.settings);
    report::Json js{{"file", j.prog.source().name()}, {"surface_error_mm", report::to_json(after)},
                    {"surface_error_as_written_mm", report::to_json(before)}, {"cl_points", after.points},
                    {"tolerance_mm", report::fixed(tol, 6)}, {"iterations", r.iterations},
                    {"evaluations", r.evaluations}, {"converged", r.converged},
                    {"compensated_points", r.compensated_points}, {"inserted_blocks", ws.blocks_inserted},
                    {"capped_points", r.capped_lines.size()}, {"feed_lowered_blocks", r.feed_lowered_lines.size()}};
    js["cusp_height_mm"] = report::cusp_json(t);
    js["machining_time"] = {{"as_written", report::to_json(t0)}, {"compensated", report::to_json(t1)}};
    js["warnings"] = warnings_json(pl);
    std::vector<std::vector<std::string>> facts = {
        {"points compensated", std::to_string(r.compensated_points) + " of " + std::to_string(after.points), "compensated_points"},
        {"points at the offset cap", std::to_string(r.capped_lines.size()), "capped_points"},
        {"blocks inserted to split moves", std::to_string(ws.blocks_inserted), "inserted_blocks"},
        {"blocks with a lowered feed", std::to_string(r.feed_lowered_lines.size()), "feed_lowered_blocks"},
        {"machining time as written / compensated", report::clock(t0.program.total_s) + " / " + report::clock(t1.program.total_s),
         "machining_time"}};
    write_folder(a.report, j, t, r.motions, r.nominal, js, std::move(facts), "compensate", command_of("compensate", args), "");
  }
  if (a.output.empty() || a.output == "-") io.out << text;
  else writer::write_file_atomically(a.output, a.file, [&](std::ostream& o) { o << text; });
  return 0;
}

int cmd_simulate(const std::vector<std::string>& args, Io& io) {
  Args a;
  po::options_description desc("options");
  describe(desc, a, false);
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
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
  if (files.empty()) throw Error(Exit::usage, "simulate: a program IN (or - for stdin) is required");
  a.file = files[0];
  if (!a.report.empty()) writer::check_output_folder(a.report);
  Job j = prepare(a, io, false);
  // With a reference, the offset of each motion is how far this program's
  // end point lies from the reference's: the design intent is the reference.
  std::vector<V3> intent;
  if (!a.reference.empty()) {
    gcode::Program ref(gcode::read_source(a.reference, &io.in));
    Diagnostics diags(&io.err, j.setup.max_errors);
    std::vector<interp::Motion> rm;
    Collect c;
    c.out = &rm;
    interp::interpret(ref, j.setup.interp(), diags, c);
    if (diags.errors()) throw Error(Exit::input, a.reference + ": error: the reference program has errors");
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
  std::vector<interp::Motion> design = j.motions;
  for (std::size_t i = 0; i < intent.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      design[i].start_mm[c] -= i ? intent[i - 1][c] : 0.0;
      design[i].end_mm[c] -= intent[i][c];
      design[i].center_mm[c] -= intent[i][c];
    }
  std::vector<compensate::Point> pts = compensate::simulate(design, intent, j.physics, j.settings, progress);
  if (progress) io.err << "\r\033[K";
  const compensate::Plausibility pl = report_plausibility(j, pts, io);
  const double tol = j.settings.tolerance_mm;
  const report::ErrorStats st = report::error_stats(report::landing_errors(pts, intent), tol);
  char buf[300];
  std::snprintf(buf, sizeof buf,
                "%s: %zu CL points%s: surface error max %.4f mm, rms %.4f mm, %.1f%% outside +-%.4f mm "
                "(undercut up to %.4f, overcut up to %.4f mm)\n",
                j.prog.source().name().c_str(), st.points, a.reference.empty() ? "" : " against the reference",
                st.max_abs, st.rms, 100.0 * st.share_out, tol, st.max_under, -st.max_over);
  io.out << buf;
  const process::MachiningTime tm = process::machining_time(j.motions, j.setup.machine->axis_limits);
  time_line(io, tm, tm);
  if (!a.report.empty()) {
    report::PointTable t = report::table_of_simulation(pts, intent, design, j.physics, j.settings);
    report::Json js{{"file", j.prog.source().name()}, {"surface_error_mm", report::to_json(st)},
                    {"cl_points", st.points}, {"tolerance_mm", report::fixed(tol, 6)},
                    {"reference_file", a.reference.empty() ? report::Json() : report::Json(a.reference)}};
    js["cusp_height_mm"] = report::cusp_json(t);
    js["machining_time"] = report::to_json(tm);
    js["warnings"] = warnings_json(pl);
    std::vector<std::vector<std::string>> facts = {
        {"CL points in material", std::to_string(st.points), "cl_points"},
        {"machining time", report::clock(tm.program.total_s), "machining_time"}};
    write_folder(a.report, j, t, design, pts, js, std::move(facts), "simulate", command_of("simulate", args), a.reference);
  }
  return 0;
}

}  // namespace deflex::cli
