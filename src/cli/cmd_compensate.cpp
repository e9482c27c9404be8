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
#include "deflex/compensate/apply.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/compensate/pairing.hpp"
#include "deflex/compensate/plausibility.hpp"
#include "deflex/compensate/plot.hpp"
#include "deflex/engage/path.hpp"
#include "deflex/interp/decimal.hpp"
#include "deflex/interp/shape.hpp"
#include "deflex/interp/travel.hpp"
#include "deflex/report/json.hpp"
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
      ("report", po::value(&a.report), "write points.csv (one row per CL point), flank_profile.csv (flank cuts) and summary.json into this folder")
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
  Job j{std::move(s), gcode::Program(gcode::read_source(a.file, &io.in)), {}, {}, {}, {}, {}};
  const profile::Config& cfg = j.setup.config;
  compensate::Settings& st = j.settings;
  st = settings_of(a, cfg, *j.setup.machine);
  std::string stock = !a.stock.empty() ? a.stock : config_path(cfg, "stock");
  if (stock.empty()) throw Error(Exit::usage, "no stock: give --stock box:X0,Y0,Z0,X1,Y1,Z1 or a solid file (or stock: in config.yaml)");
  j.physics.tools = stiffness::load_tool_library(tool_library_path(a.tool_file, cfg));
  j.physics.machine = stiffness::parse_machine_stiffness(j.setup.machine->root, j.setup.machine->file);
  j.physics.tool_only = a.tool_only;
  MaterialOptions mat = a.mat;
  if (mat.material_file.empty() && mat.material.empty() && !mat.kt) mat.material_file = config_path(cfg, "material_file");
  else if (mat.material_file.empty() && !mat.material.empty()) mat.material_file = config_path(cfg, "material_file");
  j.physics.k = coefficients_of(mat, config_string(cfg, "material"));
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

// Offset commanded at a CL sample: between the offsets of the motion's start
// (the motion before) and its end, by the sample's position along it.
V3 offset_at(const compensate::Point& p, const std::vector<V3>& offsets) {
  if (offsets.empty()) return V3::Zero();
  const V3 end = offsets[p.motion], start = p.motion ? offsets[p.motion - 1] : V3(V3::Zero());
  const double u = p.count ? static_cast<double>(p.index) / p.count : 1.0;
  return start + u * (end - start);
}

struct Stats {
  double max_abs = 0, rms = 0, share_out = 0, max_under = 0, max_over = 0;
  std::size_t points = 0, cutting = 0;
};
Stats stats_of(const std::vector<double>& e, double tol) {
  Stats s;
  double sq = 0;
  std::size_t out = 0;
  for (double v : e) {
    s.max_abs = std::max(s.max_abs, std::fabs(v));
    s.max_under = std::max(s.max_under, v);
    s.max_over = std::min(s.max_over, v);
    sq += v * v;
    out += std::fabs(v) > tol;
  }
  s.points = e.size();
  s.rms = e.empty() ? 0 : std::sqrt(sq / static_cast<double>(e.size()));
  s.share_out = e.empty() ? 0 : static_cast<double>(out) / static_cast<double>(e.size());
  return s;
}

report::Json stats_json(const Stats& s) {
  using report::fixed;
  return {{"max", fixed(s.max_abs, 6)}, {"rms", fixed(s.rms, 6)}, {"out_of_tolerance_share", fixed(s.share_out, 6)},
          {"max_undercut", fixed(s.max_under, 6)}, {"max_overcut", fixed(s.max_over, 6)}};
}

// Per CL point: the surface error relative to the path the programmer meant.
// `landing` = commanded tip + deflection; `intent` = the reference point.
std::vector<double> errors_against(const std::vector<compensate::Point>& pts, const std::vector<V3>& intent_offsets) {
  std::vector<double> e;
  e.reserve(pts.size());
  for (const auto& p : pts) {
    if (p.air || p.plunge) continue;
    // Landing point minus the intended point, along n: the offset deflex
    // applied plus the error at the commanded point (compensate::landing_error).
    e.push_back(compensate::landing_error(p, offset_at(p, intent_offsets)));
  }
  return e;
}

std::vector<compensate::PlotPoint> plot_points(const std::vector<compensate::Point>& pts, const std::vector<V3>& offsets) {
  std::vector<compensate::PlotPoint> v;
  for (const auto& p : pts)
    if (!p.air && !p.plunge)
      v.push_back({p.tip_mm.x(), p.tip_mm.y(), compensate::landing_error(p, offset_at(p, offsets))});
  return v;
}

// Top-view maps of the surface error, on one colour scale.
void write_maps(const std::string& dir, double tol,
                const std::vector<std::pair<std::string, std::vector<compensate::PlotPoint>>>& maps) {
  double scale = 2 * tol;
  for (const auto& m : maps)
    for (const auto& p : m.second) scale = std::max(scale, std::fabs(p.error_mm));
  // A named pair, not a structured binding: clang 14 cannot capture bindings in a lambda.
  for (const auto& map : maps)
    writer::write_file_atomically((fs::path(dir) / (map.first + ".svg")).string(), "", [&](std::ostream& o) {
      o << compensate::error_map_svg(map.second, tol, scale, map.first + " (top view, work frame)");
    });
}

// points.csv: surface_error_mm and flank_min/max_mm are against the design
// (the offset included). flank_profile.csv: e(z) of each flank point of
// `as_written` (simulated with Settings::flank_profiles), written when there is one.
void write_report(const std::string& dir, const std::vector<compensate::Point>& pts, const std::vector<V3>& offsets,
                  const std::string& summary_json, const std::vector<compensate::Point>& as_written) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error(Exit::io, dir + ": error: cannot create the report folder: " + ec.message());
  writer::write_file_atomically((fs::path(dir) / "points.csv").string(), "", [&](std::ostream& o) {
    o << "line,x_mm,y_mm,z_mm,ap_mm,ae_mm,Fx_N,Fy_N,Fz_N,dx_mm,dy_mm,dz_mm,surface_error_mm,offset_mm,nx,ny,nz,"
         "normal_source,part_gap_mm,flank_min_mm,flank_max_mm,flank_z_min_mm,flank_z_max_mm\n";
    char buf[480];
    for (const auto& p : pts) {
      if (p.air) continue;
      const V3 off = offset_at(p, offsets);
      const double err = compensate::landing_error(p, off);
      std::snprintf(buf, sizeof buf, "%u,%.4f,%.4f,%.4f,%.4f,%.4f,%.2f,%.2f,%.2f,%.6f,%.6f,%.6f,%.6f,%.6f", p.line,
                    p.tip_mm.x(), p.tip_mm.y(), p.tip_mm.z(), p.ap_mm, p.ae_mm, p.force_N.x(), p.force_N.y(),
                    p.force_N.z(), p.delta_mm.x(), p.delta_mm.y(), p.delta_mm.z(), err, off.dot(p.normal));
      o << buf;
      std::snprintf(buf, sizeof buf, ",%.6f,%.6f,%.6f,%s,", p.normal.x(), p.normal.y(), p.normal.z(),
                    compensate::to_string(p.normal_source));
      o << buf;
      if (p.normal_source == compensate::NormalSource::part) {
        std::snprintf(buf, sizeof buf, "%.6f", p.part_gap_mm);
        o << buf;
      }
      if (p.flank) {
        const double o_n = off.dot(p.normal);
        std::snprintf(buf, sizeof buf, ",%.6f,%.6f,%.4f,%.4f\n", o_n + p.flank_min_mm, o_n + p.flank_max_mm,
                      p.flank_z_min_mm, p.flank_z_max_mm);
        o << buf;
      } else {
        o << ",,,,\n";
      }
    }
  });
  bool any_flank = false;
  for (const auto& p : as_written) any_flank = any_flank || (!p.air && p.flank && !p.flank_profile.empty());
  if (any_flank)
    writer::write_file_atomically((fs::path(dir) / "flank_profile.csv").string(), "", [&](std::ostream& o) {
      o << "line,x_mm,y_mm,z_tip_mm,z_mm,error_mm\n";
      char buf[200];
      for (const auto& p : as_written) {
        if (p.air || !p.flank) continue;
        for (const auto& q : p.flank_profile) {
          std::snprintf(buf, sizeof buf, "%u,%.4f,%.4f,%.4f,%.4f,%.6f\n", p.line, p.tip_mm.x(), p.tip_mm.y(),
                        p.tip_mm.z(), q.z_mm, q.error_mm);
          o << buf;
        }
      }
    });
  writer::write_file_atomically((fs::path(dir) / "summary.json").string(), "",
                                [&](std::ostream& o) { o << summary_json; });
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
    "--report DIR writes points.csv, summary.json and top-view maps of the error\n"
    "(error_as_written.svg, error_compensated.svg; one colour scale).\n"
    "--feed-limit N also lowers F (by the ratio of N to the predicted peak force) on\n"
    "cutting blocks whose peak force would exceed N, restoring the programmed F after.\n"
    "The surface normal comes from the tool and the programmed path: the wall for a\n"
    "flat or bull-nose flank, else the normal to the travel in its vertical plane.\n";

void summary_line(Io& io, const char* what, const Stats& s, double tol) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "  %-28s max %.4f mm, rms %.4f mm, %.1f%% of %zu points outside +-%.4f mm\n", what,
                s.max_abs, s.rms, 100.0 * s.share_out, s.points, tol);
  io.err << buf;
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
  Stats before = stats_of(errors_against(r.nominal, {}), tol);
  Stats after = stats_of(errors_against(r.final, r.offsets), tol);
  io.err << j.prog.source().name() << ": " << r.compensated_points << " points compensated, " << ws.numbers_changed
         << " numbers changed, " << ws.words_inserted << " axis words added, " << ws.blocks_inserted
         << " blocks inserted to split moves; mirror: " << r.evaluations << " engagement evaluations, at most "
         << r.iterations << " updates per point" << (r.converged ? "" : " (not converged)") << "\n";
  summary_line(io, "predicted error, as written:", before, tol);
  summary_line(io, "predicted error, compensated:", after, tol);
  if (!a.report.empty()) {
    const report::Json js{{"file", j.prog.source().name()}, {"surface_error_mm", stats_json(after)},
                          {"surface_error_as_written_mm", stats_json(before)}, {"cl_points", after.points},
                          {"tolerance_mm", report::fixed(tol, 6)}, {"iterations", r.iterations},
                          {"evaluations", r.evaluations}, {"converged", r.converged},
                          {"compensated_points", r.compensated_points}, {"inserted_blocks", ws.blocks_inserted},
                          {"capped_points", r.capped_lines.size()}, {"warnings", warnings_json(pl)}};
    write_report(a.report, r.final, r.offsets, report::document(js), r.nominal);
    write_maps(a.report, tol, {{"error_as_written", plot_points(r.nominal, {})},
                               {"error_compensated", plot_points(r.final, r.offsets)}});
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
               "points.csv and summary.json.\n",
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
  Stats st = stats_of(errors_against(pts, intent), tol);
  char buf[300];
  std::snprintf(buf, sizeof buf,
                "%s: %zu CL points%s: surface error max %.4f mm, rms %.4f mm, %.1f%% outside +-%.4f mm "
                "(undercut up to %.4f, overcut up to %.4f mm)\n",
                j.prog.source().name().c_str(), st.points, a.reference.empty() ? "" : " against the reference",
                st.max_abs, st.rms, 100.0 * st.share_out, tol, st.max_under, -st.max_over);
  io.out << buf;
  if (!a.report.empty()) {
    const report::Json js{{"file", j.prog.source().name()}, {"surface_error_mm", stats_json(st)},
                          {"cl_points", st.points}, {"tolerance_mm", report::fixed(tol, 6)},
                          {"reference_file", a.reference.empty() ? report::Json() : report::Json(a.reference)},
                          {"warnings", warnings_json(pl)}};
    write_report(a.report, pts, intent, report::document(js), pts);
    write_maps(a.report, tol, {{"surface_error", plot_points(pts, intent)}});
  }
  return 0;
}

}  // namespace deflex::cli
