// The job of compensate, simulate and compare (job.hpp).
#include "job.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <tuple>

#include "deflex/compensate/gouge.hpp"
#include "deflex/engage/engagement.hpp"
#include "deflex/engage/path.hpp"
#include "deflex/force/tool.hpp"
#include "deflex/engage/sweep_program.hpp"
#include "deflex/interp/decimal.hpp"
#include "deflex/interp/shape.hpp"
#include "deflex/interp/travel.hpp"
#include "deflex/profile/yaml.hpp"
#include "deflex/writer/writer.hpp"
#include "deflex/report/html.hpp"
#include "deflex/report/summary.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/version.hpp"
#include "deflex/writer/expand.hpp"
#include "deflex/diag/plural.hpp"

namespace deflex::cli {
namespace fs = std::filesystem;

void describe(po::options_description& d, Args& a, bool compensating) {
  auto opt = [](std::optional<double>& dst) { return po::value<double>()->notifier([&dst](double v) { dst = v; }); };
  d.add_options()("help,h", po::bool_switch(&a.help), "show this help");
  if (compensating)
    d.add_options()("output,o", po::value(&a.output), "write the compensated program here (atomically); default stdout")
        ("feed-limit", po::value(&a.feed_limit_N), "also lower F where the peak cutting force would exceed this, N")
        ("expand-subprograms", po::bool_switch(&a.expand_subprograms),
         "write each subprogram call (M98) inline, with a comment naming it, so each pass gets its own compensation "
         "(messages then name lines of the expanded program); without it a subprogram that runs more than once stays as written");
  else d.add_options()("reference", po::value(&a.reference), "judge against this program's path (the design intent), e.g. the original of a compensated program");
  d.add_options()
      ("tool-file", po::value(&a.tool_file), "tool library (default: config tool_file, else the installed samples/tools.yaml)")
      ("tool", po::value(&a.tool), "use this tool for every cut (default: the program's T words, as T<n>)")
      ("spindle", opt(a.spindle_rpm), "spindle speed, rpm, for cutting moves the program gives no S (or S0)")
      ("feed", opt(a.feed_mm_per_min), "feed, mm/min, for cutting moves the program gives no F")
      ("stock", po::value(&a.stock), "box:X0,Y0,Z0,X1,Y1,Z1 (mm, work frame), an STL/STEP/IGES solid, a .zmap (deflex stock), or auto[:MARGIN] "
                                     "(a blank box round the cutting moves and the tool, MARGIN mm beyond them, default 1; "
                                     "its top at the highest cutting point) (default: config stock)")
      ("job", po::value(&a.job), "a job file (YAML): program, machine, tool_file, material, stock, stock_from, part, tolerance ... for one part; the command line overrides it");
  add_stock_from_options(d, a.stock_from);
  d.add_options()
      ("tolerance", opt(a.tolerance), "surface tolerance, mm: points predicted inside +-tolerance stay as programmed (default 0.01)")
      ("gain", opt(a.gain), "mirror gain: 1 reflects the whole deflection, 0 changes nothing (default 1)")
      ("report", po::value(&a.report), "write report.html, points.csv (one row per CL point), flank_profile.csv (flank cuts) and summary.json into this folder")
      ("cell-mm", po::value(&a.cell_mm)->default_value(0.05, "0.05"), "Z-map cell size, mm (finishing: 0.05; 0.1 is ~4x faster)")
      ("cl-spacing", po::value(&a.cl_spacing_mm)->default_value(0.5), "largest distance between CL points along a move, mm")
      ("max-iterations", po::value(&a.max_iterations)->default_value(8), "mirror updates per point at most (secant steps toward the fixed point)")
      ("threads", po::value(&a.threads)->default_value(0), "worker threads (0: all cores)")
      ("tool-only", po::bool_switch(&a.tool_only), "leave holder, spindle and machine out of the compliance");
  add_part_options(d, a.part);
  add_material_options(d, a.mat);
  add_read_options(d, a.read);
}



namespace {

// A number as a person writes it: 0.01, 80, 2.5.
std::string report_number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

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
// the program lacks). Errors at the line of the first motion lacking each,
// kept until report() (the line's text with them: a program read in pieces
// no longer holds it then).
class CuttingCheck {
 public:
  CuttingCheck(const Args& a, const compensate::Settings& st, const stiffness::ToolLibrary& lib,
               Job::CutExtent& extent)
      : a_(a), st_(st), lib_(lib), extent_(extent) {
    // A tool named on the command line that the library lacks is a usage error
    // (exit 2, with the library's tools).
    if (!st.tool_override.empty()) (void)stiffness::find_tool(lib, st.tool_override);
  }
  void check(interp::Motion& m, const SourceText& src) {
    if (m.kind == interp::MotionKind::rapid) return;
    fill_cut_defaults(a_, m);
    if (fatal_) return;
    // A T word of the program the library lacks is the library's (exit 3).
    if (m.tool == 0 && st_.tool_override.empty()) {
      error(src, m.line, "cutting with no tool selected (T.. M6): give --tool");
      fatal_ = Error(Exit::usage, src.name() + ": error: no tool; nothing done");
      return;
    }
    const std::string id = compensate::tool_id(m, st_);
    if (!lib_.tools.count(id)) {
      error(src, m.line, "tool " + id + " is not in the tool library " + lib_.file + " (give --tool-file, or --tool)");
      fatal_ = Error(Exit::config, src.name() + ": error: a tool of the program is missing from the library; nothing done");
      return;
    }
    if (!no_s_ && m.spindle_rpm <= 0) {
      no_s_ = true;
      error(src, m.line, "cutting with no spindle speed (S0 or no S word): give --spindle RPM");
    }
    if (!no_f_ && m.feed_mm_per_min <= 0) {
      no_f_ = true;
      error(src, m.line, "cutting with no feed (F0 or no F word): give --feed MM_PER_MIN");
    }
    extent_.add(m, 0.5 * lib_.tools.at(id).diameter_mm);
  }
  // The errors in the order found; throws where one ends the run.
  void report(Diagnostics& diags) const {
    for (const auto& [src, line, msg] : found_) diags.report(Severity::error, src, line, 1, msg);
    if (fatal_) throw *fatal_;
  }

 private:
  void error(const SourceText& src, std::uint32_t line, std::string msg) {
    found_.push_back({SourceText(src.name(), std::string(src.line_text(line)), line), line, std::move(msg)});
  }
  const Args& a_;
  const compensate::Settings& st_;
  const stiffness::ToolLibrary& lib_;
  Job::CutExtent& extent_;
  bool no_s_ = false, no_f_ = false;
  std::optional<Error> fatal_;
  std::vector<std::tuple<SourceText, std::uint32_t, std::string>> found_;
};

// --stock auto[:MARGIN]: the box round the cutting moves' tips and their
// tools' radius, MARGIN mm beyond them in X, Y and below, its top at the
// highest cutting tip: a blank, which a finishing program seldom starts
// from (the note says so). The box spec it stands for.
std::string auto_stock(const std::string& spec, const Job& j, Io& io) {
  double margin_mm = 1.0;
  if (spec != "auto") {
    const std::string m = spec.starts_with("auto:") ? spec.substr(5) : "";
    char* end = nullptr;
    margin_mm = std::strtod(m.c_str(), &end);
    if (m.empty() || *end || !(margin_mm >= 0 && margin_mm <= 1000))
      throw Error(Exit::usage, "--stock " + spec + ": give auto or auto:MARGIN, MARGIN in mm (0 to 1000)");
  }
  const Job::CutExtent& e = j.cut_extent;
  if (!e.any) throw Error(Exit::usage, "--stock auto: the program has no cutting move to put a stock round");
  const double side = e.radius_mm + margin_mm;
  char box[200];
  std::snprintf(box, sizeof box, "box:%.3f,%.3f,%.3f,%.3f,%.3f,%.3f", e.lo_mm.x() - side, e.lo_mm.y() - side,
                e.lo_mm.z() - margin_mm, e.hi_mm.x() + side, e.hi_mm.y() + side, e.hi_mm.z());
  io.info() << j.prog.source().name() << ": note: --stock " << spec << " is the blank " << box
            << " (round the cutting moves and the tool, " << margin_mm
            << " mm beyond them, its top at the highest cutting point): the stock a finishing program starts from "
               "is usually less (--stock-from the earlier programs, or deflex rough)\n";
  return box;
}

// Settings that pass the range checks but leave the run meaningless, said
// before anything is read further (an error under --strict).
void warn_meaningless(const compensate::Settings& st, bool strict, Io& io) {
  std::vector<std::string> why;
  char buf[400];
  if (st.tolerance_mm >= st.max_offset_mm) {
    std::snprintf(buf, sizeof buf,
                  "the tolerance %g mm (--tolerance, or tolerance_mm in the config) is not below the offset cap max_offset_mm = %g mm: only points whose predicted "
                  "error exceeds %g mm are moved, and by %g mm at most; finishing tolerances are a few um (0.01 mm)",
                  st.tolerance_mm, st.max_offset_mm, st.tolerance_mm, st.max_offset_mm);
    why.push_back(buf);
  }
  if (st.gain > 1) {
    // Smaoui 2011 §4: at the mirror's fixed point the tool lands (1 - gain) e
    // off the surface; gain 1 lands it on the surface.
    std::snprintf(buf, sizeof buf,
                  "--gain %g over-corrects: at the mirror's fixed point the surface error becomes %g times the "
                  "deflection along the normal (gain 2 mirrors it to the other side of the surface); 1 lands the "
                  "tool on the surface",
                  st.gain, 1 - st.gain);
    why.push_back(buf);
  }
  for (const std::string& w : why) io.err << "deflex: " << (strict ? "error: " : "warning: ") << w << "\n";
  if (strict && !why.empty()) throw Error(Exit::usage, "deflex: error: settings that make the run meaningless (--strict)");
}

// A stock no cutting move reaches (a box typed in inch for a metric
// program, another part's blank) makes the whole run meaningless: every
// point in air, "0 points outside", the output equal to the input. Said
// before anything is simulated, with both extents; an error under --strict.
void check_stock_reached(const Job& j, const Args& a, Diagnostics& diags) {
  const Job::CutExtent& e = j.cut_extent;
  if (!e.any || !j.stock) return;
  const double r = e.radius_mm;
  const float top = j.stock->max_height_in(e.lo_mm.x() - r, e.lo_mm.y() - r, e.hi_mm.x() + r, e.hi_mm.y() + r);
  if (top != stock::no_material && top > e.lo_mm.z()) return;
  const stock::GridSpec& g = j.stock->grid();
  char top_text[64] = "out of their reach", buf[512];
  if (top != stock::no_material) std::snprintf(top_text, sizeof top_text, "at Z %.3f mm", top);
  std::snprintf(buf, sizeof buf,
                "no cutting move reaches the stock: the cutting moves' tips span X %.3f..%.3f Y %.3f..%.3f "
                "Z %.3f..%.3f mm (tools up to R %.3f mm), the stock X %.3f..%.3f Y %.3f..%.3f mm with its top %s; "
                "check --stock%s (in mm, in the program's work frame)",
                e.lo_mm.x(), e.hi_mm.x(), e.lo_mm.y(), e.hi_mm.y(), e.lo_mm.z(), e.hi_mm.z(), r, g.x0_mm,
                g.x0_mm + g.nx * g.cell_mm, g.y0_mm, g.y0_mm + g.ny * g.cell_mm, top_text,
                a.stock_from.empty() ? "" : " and --stock-from");
  diags.report(j.setup.strict ? Severity::error : Severity::warning, j.prog.source().name(), buf);
  if (j.setup.strict)
    throw Error(Exit::input, j.prog.source().name() + ": error: the stock is out of reach (--strict); nothing done");
}

}  // namespace

stock::ToolProfile profile_of(const stiffness::Tool& t) { return engage::tool_profile(force::cutter_of(t)); }

void apply_job(Args& a, std::vector<std::string>& files) {
  if (a.job.empty()) return;
  const std::string file = a.job;
  const YAML::Node root = yaml::load_text(yaml::read_file(file), file);
  const yaml::Map m(root, "job", file,
                    {"program", "machine", "dialect", "tool_file", "tool", "material", "material_file", "stock",
                     "stock_from", "part", "tolerance_mm", "gain", "output", "report"});
  const fs::path dir = fs::path(file).parent_path();
  // A path of the job is relative to the job's folder (the file sits beside
  // the program); a box, a built-in name or an absolute path is taken as is.
  auto path = [&](const std::string& p) { return p.empty() || fs::path(p).is_absolute() ? p : (dir / p).string(); };
  auto text = [&](const char* key, std::string& dst, bool is_path) {
    if (dst.empty() && m.has(key)) dst = is_path ? path(m.text(key)) : m.text(key);
  };
  if (files.empty() && m.has("program")) files.push_back(path(m.text("program")));
  const std::string machine = m.has("machine") ? m.text("machine") : "";
  if (a.read.machine.empty() && !machine.empty())
    a.read.machine = machine.find('/') != std::string::npos || machine.ends_with(".yaml") ? path(machine) : machine;
  text("dialect", a.read.dialect, false);
  text("tool_file", a.tool_file, true);
  text("tool", a.tool, false);
  text("material", a.mat.material, false);
  text("material_file", a.mat.material_file, true);
  if (a.stock.empty() && m.has("stock")) {
    const std::string st = m.text("stock");
    a.stock = st.rfind("box:", 0) == 0 ? st : path(st);
  }
  if (a.stock_from.empty() && m.has("stock_from")) a.stock_from = earlier_of_job(m, path);
  text("part", a.part.part, true);
  if (!a.tolerance && m.has("tolerance_mm")) a.tolerance = m.number("tolerance_mm", yaml::Range::positive());
  if (!a.gain && m.has("gain")) a.gain = m.number("gain", yaml::Range::between(0, 2));
  text("output", a.output, true);
  text("report", a.report, true);
  std::vector<std::string> inputs = files;
  for (const EarlierOp& e : a.stock_from) inputs.insert(inputs.end(), {e.program, e.tool_file});
  inputs.insert(inputs.end(), {a.stock, a.part.part, a.tool_file, a.mat.material_file});
  refuse_output_onto_input(inputs);  // the files the job names
}

Setup resolve_with_machine(const ReadOptions& r) {
  Setup s = resolve(r);
  if (!s.machine) throw Error(Exit::usage, "a machine profile is needed (--machine, or machine: in config.yaml)");
  return s;
}

std::string stock_spec(const std::string& given, const profile::Config& cfg) {
  const std::string s = !given.empty() ? given : config_path(cfg, "stock");
  if (s.empty()) throw Error(Exit::usage, "no stock: give --stock box:X0,Y0,Z0,X1,Y1,Z1 or a solid file (or stock: in config.yaml)");
  return s;
}

void fill_cut_defaults(const Args& a, interp::Motion& m) {
  if (m.kind == interp::MotionKind::rapid) return;
  if (m.spindle_rpm <= 0 && a.spindle_rpm) m.spindle_rpm = *a.spindle_rpm;
  if (m.feed_mm_per_min <= 0 && a.feed_mm_per_min) m.feed_mm_per_min = *a.feed_mm_per_min;
}

namespace {

// The checks of prepare() on a program read in pieces, pass by pass so their
// messages come in the order they come on the whole program: the text
// (shape, decimal points), the interpretation, then per motion the travel and
// what cutting needs. The last passes also find what the compensation needs
// of the whole program: the count of motions and the time as written.
void check_in_pieces(Job& j, const Args& a, Diagnostics& diags) {
  gcode::ProgramPasses& src = *j.pieces;
  interp::ShapeCheck shape;
  interp::DecimalCheck dec(j.setup.dialect);
  report::Sha256 sha;
  src.each([&](const gcode::Program& p, bool) {
    shape.add(p);
    dec.add(p);
    sha.add(p.source().bytes());
  });
  j.sha256 = sha.hex();
  shape.finish(diags);
  dec.finish(diags, j.setup.strict);
  const interp::Options opt = j.setup.interp();
  struct Count : interp::MotionSink {
    std::size_t n = 0;
    void motion(const interp::Motion&) override { ++n; }
  } count;
  {
    interp::Interpreter it(opt, diags, count);
    src.each([&](const gcode::Program& p, bool last) { it.feed(p, last); });
    it.finish();
  }
  j.motion_count = count.n;
  const compensate::Settings& st = j.settings;
  process::MachiningClock clock(j.setup.machine->axis_limits);
  CuttingCheck cut(a, st, j.physics.tools, j.cut_extent);
  Collect c;
  std::vector<interp::Motion> piece;
  c.out = &piece;
  Diagnostics quiet(nullptr, 0);
  interp::Interpreter it(opt, quiet, c);
  src.each([&](const gcode::Program& p, bool last) {
    it.feed(p, last);
    for (interp::Motion& m : piece) {
      interp::check_travel(m, j.setup.machine->travel, p.source(), diags);
      cut.check(m, p.source());
      clock.add(m);
      if (m.kind != interp::MotionKind::rapid) j.cutting_tools.insert(compensate::tool_id(m, st));
      j.count_left(m);
    }
    piece.clear();
  });
  it.finish();
  if (!diags.errors()) cut.report(diags);
  if (diags.errors()) return;
  j.time_as_written = clock.finish();
}

}  // namespace

std::function<const stiffness::Tool*(int)> tool_of(const Job& j) {
  return [&j](int t) -> const stiffness::Tool* {
    const auto it = j.physics.tools.tools.find(compensate::tool_id(t, j.settings));
    return it == j.physics.tools.tools.end() ? nullptr : &it->second;
  };
}

std::map<std::uint32_t, SourceText> lines_of_file(const Job& j, const std::vector<std::uint32_t>& lines) {
  std::map<std::uint32_t, SourceText> out;
  auto keep = [&](const SourceText& src, std::uint32_t l) {
    out.emplace(l, SourceText(src.name(), std::string(src.line_text(l)), l));
  };
  if (!j.pieces) {
    for (std::uint32_t l : lines) keep(j.prog.source(), l);
    return out;
  }
  // One pass over the file for all of them.
  j.pieces->each([&](const gcode::Program& p, bool) {
    for (std::uint32_t l : lines)
      if (l >= p.first_line() && l <= p.last_line()) keep(p.source(), l);
  });
  for (std::uint32_t l : lines) out.emplace(l, SourceText(j.pieces->name(), "", l));  // past the end: no text
  return out;
}

namespace {

// --verbose: the files and settings of a run, before it starts.
void print_setup(const Job& j, const Args& a, Io& io) {
  const profile::MachineProfile& m = *j.setup.machine;
  char cell[64];
  std::snprintf(cell, sizeof cell, "%g mm", a.cell_mm);
  io.err << "deflex: config " << (j.setup.config.file.empty() ? "none (built-in defaults)" : j.setup.config.file)
         << "; machine " << m.name << " (" << m.file << "), dialect " << j.setup.dialect.name << "\n"
         << "deflex: tool library " << j.physics.tools.file << "; material " << j.material << "\n"
         << "deflex: stock " << j.stock_spec << ", Z-map cell " << cell << "; part model "
         << (j.part_spec.empty() ? "none" : j.part_spec) << "\n"
         << "deflex: tolerance " << j.settings.tolerance_mm << " mm, gain " << j.settings.gain << "; "
         << (j.pieces ? plural(j.motion_count, "motion") + ", read in pieces of " + plural(j.pieces->max_lines(), "line")
                      : plural(j.motions.size(), "motion") + ", read whole")
         << "\n";
}

// The moves the gouge check finds cutting into the part stay as written (the
// error there is the program's, not the tool's): their lines, kept sorted.
void add_gouge_lines(Job& j, const compensate::PartGaps& g) {
  if (g.overcut.lines.empty()) return;
  std::vector<std::uint32_t>& v = j.gouge_lines;
  v.insert(v.end(), g.overcut.lines.begin(), g.overcut.lines.end());
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

}  // namespace

// A whole program's subprograms: --expand-subprograms writes each call
// inline (the job then runs on that program); which lines run more than once
// (a move on a line that runs once is compensable inside a subprogram), and
// the calls, for the warning on what stays.
void subprograms(Job& j, const Args& a, Io& io) {
  if (a.expand_subprograms) {
    Diagnostics diags(&io.err, j.setup.max_errors);
    std::string text = writer::expand_subprograms(j.prog, j.setup.interp(), diags);
    if (diags.errors())
      throw Error(Exit::input, j.prog.source().name() + ": error: not written: the subprograms cannot be written inline");
    if (text != j.prog.bytes())
      j.prog = gcode::Program(SourceText(j.prog.source().name() + " (subprograms expanded)", std::move(text)));
  }
  if (!gcode::may_need_whole_file(j.prog.bytes())) return;  // no M98 (nor G41/G42): no call to know of
  Diagnostics quiet(nullptr, 0);  // the check pass reports
  auto calls = std::make_shared<const interp::CallStructure>(interp::call_structure(j.prog, j.setup.interp(), quiet));
  j.setup.repeated_lines = std::shared_ptr<const std::vector<std::uint8_t>>(calls, &calls->repeated);
  j.calls = std::move(calls);
}

void Job::CutExtent::add(const interp::Motion& m, double r_mm) {
  // An arc bulges past its ends by at most its radius about its centre.
  const bool arc = m.kind == interp::MotionKind::arc_cw || m.kind == interp::MotionKind::arc_ccw;
  const compensate::V3 a(m.start_mm[0], m.start_mm[1], m.start_mm[2]), b(m.end_mm[0], m.end_mm[1], m.end_mm[2]);
  compensate::V3 lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  if (arc) {
    const compensate::V3 c(m.center_mm[0], m.center_mm[1], m.center_mm[2]);
    const double rho = (a - c).norm();
    lo = lo.cwiseMin(c - compensate::V3::Constant(rho));
    hi = hi.cwiseMax(c + compensate::V3::Constant(rho));
  }
  lo_mm = any ? lo_mm.cwiseMin(lo) : lo;
  hi_mm = any ? hi_mm.cwiseMax(hi) : hi;
  radius_mm = std::max(radius_mm, r_mm);
  any = true;
}

Job prepare(Args& a, Io& io, bool compensating, const Job* shared, bool in_pieces) {
  Setup s = resolve_with_machine(a.read);
  s.tool_file = a.tool_file;
  const std::string part = !a.part.part.empty() ? a.part.part : config_path(s.config, "part");
  std::unique_ptr<gcode::ProgramPasses> pieces;
  if (in_pieces && a.file != "-")
    pieces = std::make_unique<gcode::ProgramPasses>(a.file, &io.in, piece_lines());
  std::unique_ptr<gcode::Program> whole;
  if (!pieces) whole = std::make_unique<gcode::Program>(gcode::read_source(a.file, &io.in));
  else if (pieces->whole()) whole = pieces->take_whole();
  Job j{std::move(s), {}, {}, {}, {}, whole ? std::move(*whole) : gcode::Program(SourceText(pieces->name(), "")),
        {}, {}, {}, {}, {}};
  if (!whole) j.pieces = std::move(pieces);
  const profile::Config& cfg = j.setup.config;
  compensate::Settings& st = j.settings;
  st = settings_of(a, cfg, *j.setup.machine);
  st.rounding_mm = writer::rounding_mm(false, j.setup.dialect);
  st.rounding_inch_mm = writer::rounding_mm(true, j.setup.dialect);
  if (compensating) warn_meaningless(st, j.setup.strict, io);
  if (j.pieces && st.feed_limit_N > 0 && st.gain == 0.0) {
    // Gain 0 with a feed limit simulates the program twice over (as written,
    // then at the lowered feeds): read whole, as before.
    j.prog = gcode::Program(gcode::read_source(a.file, &io.in));
    j.pieces.reset();
  }
  if (!j.pieces) subprograms(j, a, io);
  const std::string stock = stock_spec(a.stock, cfg);
  j.stock_spec = stock;
  j.physics.tools = stiffness::load_tool_library(tool_library_path(a.tool_file, cfg));
  j.physics.machine = stiffness::parse_machine_stiffness(j.setup.machine->root, j.setup.machine->file);
  j.physics.tool_only = a.tool_only;
  MaterialOptions mat = a.mat;
  // A material by name (given, or the config's): its library. Coefficients
  // given alone need none (and a --material-file beside them is an error).
  if (!mat.material.empty() || !mat.kt) mat.material_file = material_library_path(mat.material_file, cfg);
  j.physics.k = coefficients_of(mat, config_string(cfg, "material"), &j.material);
  Diagnostics diags(&io.err, j.setup.max_errors);
  if (j.pieces) {
    check_in_pieces(j, a, diags);
  } else {
    interp::check_program_shape(j.prog, diags);
    interp::check_decimal_points(j.prog, j.setup.dialect, diags, j.setup.strict);
    Collect c;
    c.out = &j.motions;
    // About one motion per line: reserved once, the list is not copied while it
    // grows (at 10M motions a doubling would hold 2 GB for a moment).
    j.motions.reserve(j.prog.line_count());
    interp::interpret(j.prog, j.setup.interp(), diags, c);
    // The machine's travel before any simulation: a move far outside it is a
    // crash on the machine and unbounded work here.
    for (const interp::Motion& m : j.motions) interp::check_travel(m, j.setup.machine->travel, j.prog.source(), diags);
    if (!diags.errors()) {
      CuttingCheck cut(a, st, j.physics.tools, j.cut_extent);
      for (interp::Motion& m : j.motions) cut.check(m, j.prog.source());
      cut.report(diags);
    }
  }
  if (diags.errors())
    throw Error(Exit::input, j.prog.source().name() + ": error: the program has errors; " +
                                 (compensating ? "nothing compensated, nothing written" : "not simulated"));
  // The earlier operations read and checked before any stock is built.
  std::vector<EarlierRun> earlier;
  if (!shared) earlier = read_earlier_all(a.stock_from, j.setup, j.physics.tools, io);
  j.stock_from = a.stock_from;
  if (!part.empty()) {
    j.part_spec = part;
    if (!shared) j.part = std::make_unique<part::PartModel>(part::PartModel::load(part));
    j.physics.part = shared ? shared->physics.part : j.part.get();
  }
  if (shared) {
    j.physics.stock = shared->physics.stock;
  } else {
    stock::SolidOptions so;
    so.cell_mm = a.cell_mm;
    if (stock.starts_with("auto")) j.stock_spec = auto_stock(stock, j, io);
    j.stock = std::make_unique<stock::ZMap>(stock::make_stock(j.stock_spec, so));
    j.physics.stock = j.stock.get();
    sweep_earlier_all(earlier, *j.stock, j.physics.tools, st.cl_spacing_mm);
  }
  check_stock_reached(j, a, diags);
  if (j.physics.part && a.reference.empty()) {
    // The gouge check runs before the simulation: it needs no stock and no
    // forces. Not on a program judged against a reference: a compensated
    // program stands off the part on purpose (the reference is the design).
    const double gap = a.part.gap_mm ? *a.part.gap_mm : config_number(cfg, "part_gap_mm", 0.02);
    if (!(gap > 0)) throw Error(Exit::usage, "--part-gap must be > 0 mm");
    engage::PathOptions po;
    po.cl_spacing_mm = st.cl_spacing_mm;
    auto gaps_of = [&](const std::vector<interp::Motion>& ms) {
      return compensate::part_gaps(ms, *j.physics.part, j.physics.tools,
                                   [&st](const interp::Motion& m) { return compensate::tool_id(m, st); }, po, gap,
                                   st.part_reach_mm);
    };
    if (!j.pieces) {
      const compensate::PartGaps g = gaps_of(j.motions);
      report_part_gaps(g, j.prog.source(), gap, diags);
      add_gouge_lines(j, g);
      for (interp::Motion& m : j.motions) leave_gouge(m, j.gouge_lines);
    } else {
      // A pass of its own over the pieces (the part model is read after the checks).
      compensate::PartGaps g;
      std::vector<interp::Motion> piece;
      Collect c;
      c.out = &piece;
      Diagnostics quiet(nullptr, 0);
      const interp::Options opt = j.setup.interp();
      interp::Interpreter it(opt, quiet, c);
      j.pieces->each([&](const gcode::Program& p, bool last) {
        it.feed(p, last);
        for (interp::Motion& m : piece) fill_cut_defaults(a, m);
        const compensate::PartGaps pg = gaps_of(piece);
        compensate::merge(g, pg);
        // The check pass counted these moves as compensable: count them as left.
        const std::size_t before = j.gouge_lines.size();
        add_gouge_lines(j, pg);
        if (j.gouge_lines.size() != before)
          for (interp::Motion m : piece) {
            leave_gouge(m, j.gouge_lines);
            if (m.fixed == interp::Fixed::gouge) j.count_left(m);
          }
        piece.clear();
      });
      const auto text = lines_of_file(j, {g.overcut.worst_line, g.standoff.worst_line});
      report_part_gaps(g, [&text](std::uint32_t l) { return text.at(l); }, gap, diags);
    }
  }
  for (const interp::Motion& m : j.motions) j.count_left(m);  // in pieces: the check pass counted them
  if (io.verbose) print_setup(j, a, io);
  return j;
}

compensate::Progress progress_for(Io& io) {
  const bool shown = !io.quiet && (io.progress == ProgressWhen::always ||
                                   (io.progress == ProgressWhen::automatic && io.err_is_terminal));
  if (!shown && !io.verbose) return {};
  using Clock = std::chrono::steady_clock;
  struct State {
    std::string stage;
    Clock::time_point start;
    int decile = -1;
  };
  auto st = std::make_shared<State>();
  // On a terminal one line redrawn in place; elsewhere (a log) a line per 10%.
  const bool redraw = io.err_is_terminal;
  return [&io, st, shown, redraw](const std::string& stage, double f) {
    const Clock::time_point now = Clock::now();
    if (stage != st->stage) {
      if (shown && redraw) io.err << "\r\033[K";
      if (io.verbose && !st->stage.empty()) {
        char done[32];
        std::snprintf(done, sizeof done, "%.1f s", std::chrono::duration<double>(now - st->start).count());
        io.err << "deflex: " << st->stage << " done in " << done << "\n";
      }
      st->stage = stage;
      st->start = now;
      st->decile = -1;
    }
    if (!shown || stage.empty()) return;  // end_progress(): the last stage closed
    const double s = std::chrono::duration<double>(now - st->start).count();
    char buf[160];
    const int n = std::snprintf(buf, sizeof buf, "deflex: %s %3.0f%%, %s elapsed", stage.c_str(), 100.0 * f,
                                report::clock(s).c_str());
    std::string text(buf, static_cast<std::size_t>(std::max(0, n)));
    // The rest at the rate so far, once there is a rate to go by.
    if (f > 0.01 && f < 1 && s > 1) text += ", about " + report::clock(s * (1 - f) / f) + " left";
    if (redraw) {
      io.err << "\r\033[K" << text << std::flush;
    } else if (const int d = static_cast<int>(10 * f); d != st->decile) {
      st->decile = d;
      io.err << text << "\n";
    }
  };
}

void end_progress(const compensate::Progress& p) {
  if (p) p("", 1.0);
}

namespace {

// The tools the cutting moves use, by id.
std::set<std::string> cutting_tools(const Job& j) {
  std::set<std::string> tools = j.cutting_tools;  // in pieces; else:
  for (const interp::Motion& m : j.motions)
    if (m.kind != interp::MotionKind::rapid) tools.insert(compensate::tool_id(m, j.settings));
  return tools;
}

// "T1: flat D10 mm", "T2: bull nose D12 mm r1".
std::string tool_text(const std::string& id, const stiffness::Tool& t) {
  const bool bull = t.type == stock::EndShape::bull;
  return id + ": " + (t.type == stock::EndShape::ball ? "ball" : bull ? "bull nose" : "flat") + " D" +
         report_number(t.diameter_mm) + " mm" + (bull ? " r" + report_number(t.corner_radius_mm) : "");
}

// The material's name and library, without the source that Job::material
// adds after a ';' ("C35 (samples/materials.yaml; source: ...)").
std::string material_text(const Job& j) {
  const std::size_t cut = j.material.find(';');
  return cut == std::string::npos ? j.material : j.material.substr(0, cut) + ")";
}

}  // namespace

Used used(const Job& j) {
  Used u;
  const profile::MachineProfile& m = *j.setup.machine;
  u.json = {{"config", j.setup.config.file.empty() ? report::Json() : report::Json(j.setup.config.file)},
            {"machine", m.name}, {"machine_file", m.file}, {"dialect", j.setup.dialect.name},
            {"tool_file", j.physics.tools.file}, {"material", material_text(j)}};
  report::Json tools = report::Json::array();
  std::string t_text;
  for (const std::string& id : cutting_tools(j)) {
    const std::string t = tool_text(id, j.physics.tools.tools.at(id));
    tools.push_back(t);
    t_text += (t_text.empty() ? "" : ", ") + t;
  }
  u.json["tools"] = tools;
  u.text = "used: machine " + m.name + " (" + m.file + ", dialect " + j.setup.dialect.name + "); " +
           (t_text.empty() ? "no cutting tool" : t_text) + " (" + j.physics.tools.file + "); material " +
           material_text(j) + "; config " + (j.setup.config.file.empty() ? "none" : j.setup.config.file);
  return u;
}

std::vector<std::pair<std::string, std::string>> provenance(const Job& j, const std::string& command,
                                                            const std::string& reference) {
  std::vector<std::pair<std::string, std::string>> p;
  p.emplace_back("program", j.prog.source().name());
  p.emplace_back("program SHA-256", j.pieces ? j.sha256 : report::sha256_hex(j.prog.source().bytes()));
  if (!reference.empty()) p.emplace_back("judged against", reference);
  p.emplace_back("machine", j.setup.machine->name + " (" + j.setup.machine->file + "), dialect " + j.setup.dialect.name);
  for (const std::string& id : cutting_tools(j)) {
    const stiffness::Tool& t = j.physics.tools.tools.at(id);
    char buf[200];
    std::snprintf(buf, sizeof buf, "%s, %d flutes, helix %g deg, stick-out %g mm, flutes %g mm long",
                  tool_text(id, t).c_str(), t.flutes, t.helix_deg, t.stickout_mm, t.flute_length_mm);
    p.emplace_back("tool", buf);
  }
  p.emplace_back("tool library", j.physics.tools.file);
  p.emplace_back("material", j.material);
  p.emplace_back("stock", j.stock_spec);
  for (const EarlierOp& e : j.stock_from) p.emplace_back("stock from", earlier_text(e));
  p.emplace_back("part model", j.part_spec.empty() ? "none (normals fitted through the path, or from the travel)" : j.part_spec);
  p.emplace_back("tolerance", report_number(j.settings.tolerance_mm) + " mm");
  p.emplace_back("deflex", std::string(DEFLEX_VERSION " (git ") + revision() + ")");
  p.emplace_back("date", report::utc_now());
  p.emplace_back("command", command);
  return p;
}

void leave_gouge(interp::Motion& m, const std::vector<std::uint32_t>& gouge_lines) {
  if (m.compensable() && m.kind != interp::MotionKind::rapid &&
      std::binary_search(gouge_lines.begin(), gouge_lines.end(), m.line))
    m.fixed = interp::Fixed::gouge;
}

void print_plausibility(const Job& j, const compensate::Plausibility& pl, Io& io) {
  Diagnostics diags(&io.err, 0);
  std::vector<std::uint32_t> lines;
  for (const compensate::Finding& f : pl.findings) lines.push_back(f.line);
  const auto text = lines_of_file(j, lines);
  for (const compensate::Finding& f : pl.findings)
    diags.report(Severity::warning, text.at(f.line), f.line, 1, f.message + " [" + f.kind + "]");
}

report::Json warnings_json(const compensate::Plausibility& pl) {
  report::Json a = report::Json::array();
  for (const compensate::Finding& f : pl.findings)
    a.push_back({{"kind", f.kind}, {"count", f.count}, {"worst", report::fixed(f.worst, 4)},
                 {"limit", report::fixed(f.limit, 4)}, {"tool", f.tool}, {"line", f.line},
                 {"line_count", f.line_count}, {"lines", f.lines}, {"message", f.message}});
  return a;
}

void time_line(Io& io, const process::MachiningTime& before, const process::MachiningTime& after) {
  std::ostream& o = io.info();
  // One form for the line: h:mm:ss for all its times when one reaches an hour.
  const bool h = report::clock_has_hours(std::max(before.program.total_s, after.program.total_s));
  o << "  machining time:              " << report::clock(before.program.total_s, h) << " (cutting "
    << report::clock(before.program.cutting_s, h) << ", rapids " << report::clock(before.program.rapid_s, h) << ")";
  if (std::fabs(after.program.total_s - before.program.total_s) >= 0.5)
    o << ", compensated " << report::clock(after.program.total_s, h);
  o << (h ? " [h:mm:ss" : " [m:ss") << ", axis limits of the machine profile]\n";
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

}  // namespace deflex::cli
