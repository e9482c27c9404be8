// The checks of job::open() (checks.hpp).
#include "checks.hpp"

#include "deflex/job/check.hpp"

#include <algorithm>

#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>
#include <tuple>

#include "deflex/compensate/gouge.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/engage/path.hpp"
#include "deflex/interp/decimal.hpp"
#include "deflex/interp/shape.hpp"
#include "deflex/interp/travel.hpp"
#include "deflex/report/html.hpp"
#include "deflex/report/summary.hpp"
#include "deflex/stability/frf.hpp"
#include "deflex/writer/expand.hpp"
#include "internal.hpp"

namespace deflex::job::detail {

compensate::Settings settings_of(const Settings& a, const profile::Config& cfg, const profile::MachineProfile& mp) {
  compensate::Settings st;
  st.tolerance_mm = a.tolerance_mm ? *a.tolerance_mm : config_number(cfg, "tolerance_mm", 0.01);
  st.gain = a.gain ? *a.gain : config_number(cfg, "gain", 1.0);
  st.max_offset_mm = mp.max_offset_mm;
  st.cl_spacing_mm = a.cl_spacing_mm;
  st.max_iterations = a.max_iterations;
  st.threads = a.threads;
  st.tool_override = !a.tool.empty() ? a.tool : config_string(cfg, "tool");
  st.feed_limit_N = a.feed_limit_N;
  st.flank_profiles = !a.report_dir.empty();  // flank_profile.csv of the program as written
  if (a.feed_limit_N < 0) throw Error(ErrorKind::settings, "{feed_limit_N} must be > 0 N");
  if (!(st.tolerance_mm > 0)) throw Error(ErrorKind::settings, "{tolerance_mm} must be > 0 mm");
  if (!(st.gain >= 0 && st.gain <= 2)) throw Error(ErrorKind::settings, "{gain} must be between 0 and 2");
  if (!(a.cl_spacing_mm > 0)) throw Error(ErrorKind::settings, "{cl_spacing_mm} must be > 0 mm");
  if (a.max_iterations < 1 || a.max_iterations > 50) throw Error(ErrorKind::settings, "{max_iterations} must be 1..50");
  if (a.threads < 0 || a.threads > 1024) throw Error(ErrorKind::settings, "{threads} must be 0 (all cores) .. 1024");
  if (!(a.cell_mm >= 0.005 && a.cell_mm <= 5)) throw Error(ErrorKind::settings, "{cell_mm} must be between 0.005 and 5");
  if (a.spindle_rpm && !(*a.spindle_rpm > 0 && *a.spindle_rpm <= 1e6)) throw Error(ErrorKind::settings, "{spindle_rpm} must be > 0 rpm");
  if (a.feed_mm_per_min && !(*a.feed_mm_per_min > 0 && *a.feed_mm_per_min <= 1e6))
    throw Error(ErrorKind::settings, "{feed_mm_per_min} must be > 0 mm/min");
  return st;
}

namespace {

// What the simulation needs of every cutting motion, before it runs: a tool
// in the library, a spindle speed and a feed (--spindle, --feed supply what
// the program lacks). Errors at the line of the first motion lacking each,
// kept until report() (the line's text with them: a program read in pieces
// no longer holds it then).
class CuttingCheck {
 public:
  CuttingCheck(const Settings& a, const compensate::Settings& st, const stiffness::ToolLibrary& lib,
               Run::CutExtent& extent)
      // The sweep alone (check --stock) needs neither a spindle speed nor a feed.
      : a_(a), st_(st), lib_(lib), extent_(extent), no_s_(st.geometry_only), no_f_(st.geometry_only) {
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
      error(src, m.line, "cutting with no tool selected (T.. M6): give {tool}");
      fatal_ = Error(ErrorKind::settings, src.name() + ": error: no tool; nothing done");
      return;
    }
    const std::string id = compensate::tool_id(m, st_);
    if (!lib_.tools.count(id)) {
      error(src, m.line, "tool " + id + " is not in the tool library " + lib_.file + " (give {tool_file}, or {tool})");
      fatal_ = Error(ErrorKind::config, src.name() + ": error: a tool of the program is missing from the library; nothing done");
      return;
    }
    if (!no_s_ && m.spindle_rpm <= 0) {
      no_s_ = true;
      error(src, m.line, "cutting with no spindle speed (S0 or no S word): give {spindle_rpm} RPM");
    }
    if (!no_f_ && m.feed_mm_per_min <= 0) {
      no_f_ = true;
      error(src, m.line, "cutting with no feed (F0 or no F word): give {feed_mm_per_min} MM_PER_MIN");
    }
    const stiffness::Tool& t = lib_.tools.at(id);
    // A tool's measured FRF is read now, so that a broken one is a located
    // error before the simulation, not in the middle of it.
    if (!t.frf_file.empty() && frf_read_.insert(id).second) (void)stability::load_frf_csv(t.frf_file);
    extent_.add(m, 0.5 * t.diameter_mm);
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
  const Settings& a_;
  const compensate::Settings& st_;
  const stiffness::ToolLibrary& lib_;
  Run::CutExtent& extent_;
  bool no_s_ = false, no_f_ = false;
  std::optional<Error> fatal_;
  std::vector<std::tuple<SourceText, std::uint32_t, std::string>> found_;
  std::set<std::string> frf_read_;  // the tools whose frf_file was read
};

// --stock auto[:MARGIN]: the box round the cutting moves' tips and their
// tools' radius, MARGIN mm beyond them in X, Y and below, its top at the
// highest cutting tip: a blank, which a finishing program seldom starts
// from (the note says so). The box spec it stands for.
}  // namespace

std::string auto_stock(const std::string& spec, const Run& j, Io& io) {
  double margin_mm = 1.0;
  if (spec != "auto") {
    const std::string m = spec.starts_with("auto:") ? spec.substr(5) : "";
    char* end = nullptr;
    margin_mm = std::strtod(m.c_str(), &end);
    if (m.empty() || *end || !(margin_mm >= 0 && margin_mm <= 1000))
      throw Error(ErrorKind::settings, "{stock} " + spec + ": give auto or auto:MARGIN, MARGIN in mm (0 to 1000)");
  }
  const Run::CutExtent& e = j.cut_extent;
  if (!e.any) throw Error(ErrorKind::settings, "{stock} auto: the program has no cutting move to put a stock round");
  const double side = e.radius_mm + margin_mm;
  char box[200];
  std::snprintf(box, sizeof box, "box:%.3f,%.3f,%.3f,%.3f,%.3f,%.3f", e.lo_mm.x() - side, e.lo_mm.y() - side,
                e.lo_mm.z() - margin_mm, e.hi_mm.x() + side, e.hi_mm.y() + side, e.hi_mm.z());
  io.info() << j.prog.source().name() << io.named(": note: {stock} ") << spec << " is the blank " << box
            << " (round the cutting moves and the tool, " << margin_mm
            << io.named(" mm beyond them, its top at the highest cutting point): the stock a finishing program starts "
                        "from is usually less ({stock_from} the earlier programs, or deflex rough)\n");
  return box;
}

// Settings that pass the range checks but leave the run meaningless, said
// before anything is read further (an error under --strict).
void warn_meaningless(const compensate::Settings& st, bool strict, Io& io) {
  std::vector<std::string> why;
  char buf[400];
  if (st.tolerance_mm >= st.max_offset_mm) {
    std::snprintf(buf, sizeof buf,
                  "the tolerance %g mm ({tolerance_mm}, or tolerance_mm in the config) is not below the offset cap max_offset_mm = %g mm: only points whose predicted "
                  "error exceeds %g mm are moved, and by %g mm at most; finishing tolerances are a few um (0.01 mm)",
                  st.tolerance_mm, st.max_offset_mm, st.tolerance_mm, st.max_offset_mm);
    why.push_back(buf);
  }
  if (st.gain > 1) {
    // Smaoui 2011 §4: at the mirror's fixed point the tool lands (1 - gain) e
    // off the surface; gain 1 lands it on the surface.
    std::snprintf(buf, sizeof buf,
                  "{gain} %g over-corrects: at the mirror's fixed point the surface error becomes %g times the "
                  "deflection along the normal (gain 2 mirrors it to the other side of the surface); 1 lands the "
                  "tool on the surface",
                  st.gain, 1 - st.gain);
    why.push_back(buf);
  }
  for (const std::string& w : why) io.err << "deflex: " << (strict ? "error: " : "warning: ") << io.named(w) << "\n";
  if (strict && !why.empty()) throw Error(ErrorKind::settings, "deflex: error: settings that make the run meaningless ({strict})");
}

// A stock no cutting move reaches (a box typed in inch for a metric
// program, another part's blank) makes the whole run meaningless: every
// point in air, "0 points outside", the output equal to the input. Said
// before anything is simulated, with both extents; an error under --strict.
void check_stock_reached(const Run& j, Diagnostics& diags) {
  const Settings& a = j.given;
  const Run::CutExtent& e = j.cut_extent;
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
                "check {stock}%s (in mm, in the program's work frame)",
                e.lo_mm.x(), e.hi_mm.x(), e.lo_mm.y(), e.hi_mm.y(), e.lo_mm.z(), e.hi_mm.z(), r, g.x0_mm,
                g.x0_mm + g.nx * g.cell_mm, g.y0_mm, g.y0_mm + g.ny * g.cell_mm, top_text,
                a.stock_from.empty() ? "" : " and {stock_from}");
  diags.report(j.setup.strict ? Severity::error : Severity::warning, j.prog.source().name(), buf);
  if (j.setup.strict)
    throw Error(ErrorKind::input, j.prog.source().name() + ": error: the stock is out of reach ({strict}); nothing done");
}

// The checks of prepare() on a program read in pieces, pass by pass so their
// messages come in the order they come on the whole program: the text
// (shape, decimal points), the interpretation, then per motion the travel and
// what cutting needs. The last passes also find what the compensation needs
// of the whole program: the count of motions and the time as written.
void check_in_pieces(Run& j, Diagnostics& diags, const compensate::Progress& progress) {
  const Settings& a = j.given;
  gcode::ProgramPasses& src = *j.pieces;
  // Three passes over the file: the fraction by the bytes they have read.
  std::error_code ec;
  const double pass_bytes = std::max<double>(1, static_cast<double>(std::filesystem::file_size(src.path(), ec)));
  double read_bytes = 0;
  auto read = [&](const gcode::Program& p) {
    read_bytes += static_cast<double>(p.source().bytes().size());
    if (progress) progress("checking", std::min(1.0, read_bytes / (3 * pass_bytes)));
  };
  report::Sha256 sha;
  check_text(src, j.setup, diags, [&](const gcode::Program& p) {
    sha.add(p.source().bytes());
    read(p);
  });
  j.sha256 = sha.hex();
  const interp::Options opt = j.setup.interp();
  struct Count : interp::MotionSink {
    std::size_t n = 0;
    void motion(const interp::Motion&) override { ++n; }
  } count;
  {
    interp::Interpreter it(opt, diags, count);
    src.each([&](const gcode::Program& p, bool last) {
      it.feed(p, last);
      read(p);
    });
    it.finish();
  }
  j.motion_count = count.n;
  const compensate::Settings& st = j.settings;
  process::MachiningClock clock(j.setup.machine->axis_limits);
  CuttingCheck cut(a, st, j.physics.tools, j.cut_extent);
  std::vector<interp::Motion> piece;
  interp::MotionList c(piece);
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
    read(p);
  });
  it.finish();
  if (!diags.errors()) cut.report(diags);
  if (diags.errors()) return;
  j.time_as_written = clock.finish();
}

// --verbose: the files and settings of a run, before it starts.
void print_setup(const Run& j, Io& io) {
  const Settings& a = j.given;
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

namespace {

// The moves the gouge check finds cutting into the part stay as written (the
// error there is the program's, not the tool's): their lines, kept sorted.
void add_gouge_lines(Run& j, const compensate::PartGaps& g) {
  if (g.overcut.lines.empty()) return;
  std::vector<std::uint32_t>& v = j.gouge_lines;
  v.insert(v.end(), g.overcut.lines.begin(), g.overcut.lines.end());
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// A whole program's subprograms: --expand-subprograms writes each call
// inline (the job then runs on that program); which lines run more than once
// (a move on a line that runs once is compensable inside a subprogram), and
// the calls, for the warning on what stays.
}  // namespace

void subprograms(Run& j, Io& io) {
  const Settings& a = j.given;
  if (a.expand_subprograms) {
    Diagnostics diags = io.diagnostics(j.setup.max_errors);
    std::string text = writer::expand_subprograms(j.prog, j.setup.interp(), diags);
    if (diags.errors())
      throw Error(ErrorKind::input, j.prog.source().name() + ": error: not written: the subprograms cannot be written inline")
          .with_errors_of(diags);
    if (text != j.prog.bytes())
      j.prog = gcode::Program(SourceText(j.prog.source().name() + " (subprograms expanded)", std::move(text)));
  }
  if (!gcode::may_need_whole_file(j.prog.bytes())) return;  // no M98 (nor G41/G42): no call to know of
  Diagnostics quiet(nullptr, 0);  // the check pass reports
  auto calls = std::make_shared<const interp::CallStructure>(interp::call_structure(j.prog, j.setup.interp(), quiet));
  j.setup.repeated_lines = std::shared_ptr<const std::vector<std::uint8_t>>(calls, &calls->repeated);
  j.calls = std::move(calls);
}


void check_whole(Run& j, Diagnostics& diags) {
  interp::check_program_shape(j.prog, diags);
  interp::check_decimal_points(j.prog, j.setup.dialect, diags, j.setup.strict);
  interp::MotionList c(j.motions);
  // About one motion per line: reserved once, the list is not copied while it
  // grows (at 10M motions a doubling would hold 2 GB for a moment).
  j.motions.reserve(j.prog.line_count());
  interp::interpret(j.prog, j.setup.interp(), diags, c);
  // The machine's travel before any simulation: a move far outside it is a
  // crash on the machine and unbounded work here.
  for (const interp::Motion& m : j.motions) interp::check_travel(m, j.setup.machine->travel, j.prog.source(), diags);
  if (diags.errors()) return;
  CuttingCheck cut(j.given, j.settings, j.physics.tools, j.cut_extent);
  for (interp::Motion& m : j.motions) cut.check(m, j.prog.source());
  cut.report(diags);
}

namespace {

// The gouge check of a program read in pieces: a pass of its own over them
// (the part model is read after the checks).
compensate::PartGaps gouges_in_pieces(Run& j, const std::function<compensate::PartGaps(const std::vector<interp::Motion>&)>& gaps_of) {
  compensate::PartGaps g;
  each_piece(j, [&](std::vector<interp::Motion>& piece) {
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
  });
  return g;
}

}  // namespace

void each_piece(Run& j, const std::function<void(std::vector<interp::Motion>&)>& fn) {
  std::vector<interp::Motion> piece;
  interp::MotionList c(piece);
  Diagnostics quiet(nullptr, 0);
  const interp::Options opt = j.setup.interp();
  interp::Interpreter it(opt, quiet, c);
  j.pieces->each([&](const gcode::Program& p, bool last) {
    it.feed(p, last);
    for (interp::Motion& m : piece) fill_cut_defaults(j.given, m);
    fn(piece);
    piece.clear();
  });
}

void check_gouges(Run& j, Diagnostics& diags) {
  // The gouge check runs before the simulation: it needs no stock and no
  // forces. Not on a program judged against a reference: a compensated
  // program stands off the part on purpose (the reference is the design).
  if (!j.physics.part || !j.given.reference.empty()) return;
  const compensate::Settings& st = j.settings;
  const double gap = part_gap_mm(j.given.part, j.setup.config);
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
    return;
  }
  const compensate::PartGaps g = gouges_in_pieces(j, gaps_of);
  const auto text = lines_of_file(j, {g.overcut.worst_line, g.standoff.worst_line});
  report_part_gaps(g, [&text](std::uint32_t l) { return text.at(l); }, gap, diags);
}

}  // namespace deflex::job::detail
