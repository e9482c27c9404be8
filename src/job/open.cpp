// job::open() (run.hpp): the program read and checked, the physics built.
#include "deflex/diag/plural.hpp"
#include "deflex/job/run.hpp"

#include <algorithm>
#include <memory>

#include "checks.hpp"
#include "internal.hpp"
#include "workpiece_run.hpp"
#include "deflex/engage/engagement.hpp"
#include "deflex/engage/sweep_program.hpp"
#include "deflex/force/tool.hpp"
#include "deflex/interp/arc.hpp"
#include "deflex/job/earlier.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::job {

stock::ToolProfile profile_of(const stiffness::Tool& t) { return engage::tool_profile(force::cutter_of(t)); }

void fill_cut_defaults(const Settings& s, interp::Motion& m) {
  if (m.kind == interp::MotionKind::rapid) return;
  if (m.spindle_rpm <= 0 && s.spindle_rpm) m.spindle_rpm = *s.spindle_rpm;
  if (m.feed_mm_per_min <= 0 && s.feed_mm_per_min) m.feed_mm_per_min = *s.feed_mm_per_min;
}

void leave_gouge(interp::Motion& m, const std::vector<std::uint32_t>& gouge_lines) {
  if (m.compensable() && m.kind != interp::MotionKind::rapid &&
      std::binary_search(gouge_lines.begin(), gouge_lines.end(), m.line))
    m.fixed = interp::Fixed::gouge;
}

void Run::count_left(const interp::Motion& m) {
  if (m.kind == interp::MotionKind::rapid || m.fixed == interp::Fixed::no || m.fixed == interp::Fixed::rapid) return;
  LeftMoves& l = left_moves[m.fixed];
  if (l.blocks && l.last_line == m.line) return;
  if (!l.blocks++) l.first_line = m.line;
  l.last_line = m.line;
}

void Run::CutExtent::add(const interp::Motion& m, double r_mm) {
  // An arc bulges past its ends by at most its radius about its centre.
  const bool arc = interp::is_arc(m);
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

std::function<const stiffness::Tool*(int)> tool_of(const Run& j) {
  return [&j](int t) -> const stiffness::Tool* {
    const auto it = j.physics.tools.tools.find(compensate::tool_id(t, j.settings));
    return it == j.physics.tools.tools.end() ? nullptr : &it->second;
  };
}

std::map<std::uint32_t, SourceText> lines_of_file(const Run& j, const std::vector<std::uint32_t>& lines) {
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

// The program, in pieces where it can be: from a file (not the input
// stream), for a purpose that takes pieces, and long enough to need them.
void read_program(Run& j, Io& io) {
  const Settings& s = j.given;
  const bool in_pieces = j.purpose == Purpose::compensate || j.purpose == Purpose::check ||
                         (j.purpose == Purpose::simulate && s.reference.empty());
  std::unique_ptr<gcode::ProgramPasses> pieces;
  if (in_pieces && s.program != "-") pieces = std::make_unique<gcode::ProgramPasses>(s.program, &io.in, piece_lines());
  if (!pieces) {
    j.prog = gcode::Program(gcode::read_source(s.program, &io.in));
  } else if (pieces->whole()) {
    j.prog = std::move(*pieces->take_whole());
  } else {
    j.prog = gcode::Program(SourceText(pieces->name(), ""));
    j.pieces = std::move(pieces);
  }
  if (j.pieces && j.settings.feed_limit_N > 0 && j.settings.gain == 0.0) {
    // Gain 0 with a feed limit simulates the program twice over (as written,
    // then at the lowered feeds): read whole.
    j.prog = gcode::Program(gcode::read_source(s.program, &io.in));
    j.pieces.reset();
  }
}

// The tools, the machine's stiffness and the material's coefficients.
void resolve_physics(Run& j) {
  const Settings& s = j.given;
  const profile::Config& cfg = j.setup.config;
  j.physics.tools = stiffness::load_tool_library(tool_library_path(s.tool_file, cfg));
  j.physics.machine = stiffness::parse_machine_stiffness(j.setup.machine->root, j.setup.machine->file);
  j.physics.tool_only = s.tool_only;
  j.physics.spindle = j.setup.machine->spindle;
  if (j.purpose == Purpose::check) return;  // the sweep alone: no forces
  MaterialSettings mat = s.material;
  // A material by name (given, or the config's): its library. Coefficients
  // given alone need none (and a material file beside them is an error).
  if (!mat.material.empty() || !mat.kt) mat.material_file = material_library_path(mat.material_file, cfg);
  j.physics.k = coefficients_of(mat, config_string(cfg, "material"), &j.material);
  // The machine's fitted force scale (profile/profile.hpp MachineProfile::force_scale).
  const double f = j.setup.machine->force_scale;
  if (f != 1.0) {
    j.physics.k = force::scaled(j.physics.k, f);
    j.material += " x " + fixed_decimals(f, 3) + " (force_scale of machine " + j.setup.machine->name + ")";
  }
}

// The stock (shared, or built from its spec and the earlier operations) and
// the part model, after every check of the program.
void build_stock_and_part(Run& j, Io& io, const Run* shared, const std::vector<EarlierRun>& earlier) {
  const Settings& s = j.given;
  const std::string part = !s.part.part.empty() ? s.part.part : config_path(j.setup.config, "part");
  if (!part.empty() && j.purpose != Purpose::check) {
    j.part_spec = part;
    if (!shared) j.part = std::make_unique<part::PartModel>(part::PartModel::load(part));
    j.physics.part = shared ? shared->physics.part : j.part.get();
  }
  if (shared) {
    j.physics.stock = shared->physics.stock;
    return;
  }
  stock::SolidOptions so;
  so.cell_mm = s.cell_mm;
  if (j.stock_spec.starts_with("auto")) j.stock_spec = detail::auto_stock(j.stock_spec, j, io);
  j.stock = std::make_unique<stock::ZMap>(stock::make_stock(j.stock_spec, so));
  j.physics.stock = j.stock.get();
  sweep_earlier_all(earlier, *j.stock, j.physics.tools, j.settings.cl_spacing_mm);
}

}  // namespace

Run open(const Settings& s, Purpose purpose, Io& io, Observer* observer, const Run* shared) {
  // A job file names its program beside the settings (apply_job_file): one
  // left there would otherwise read as a file of no name.
  if (s.program.empty()) throw Error(ErrorKind::settings, "no program given: {program} is a file, or - for the input stream");
  const compensate::Progress progress = detail::progress_of(observer);
  auto stage = [&progress](const char* name, double fraction) {
    if (progress) progress(name, fraction);
  };
  // The output's checks before anything is read: a run never ends writing nothing after an hour.
  if (purpose == Purpose::compensate && !s.output.empty() && s.output != "-") writer::check_output_path(s.output, s.program);
  if (purpose != Purpose::compare && !s.report_dir.empty()) writer::check_output_folder(s.report_dir);
  Run j;
  j.given = s;
  j.purpose = purpose;
  j.setup = resolve_with_machine(s.read);
  j.setup.tool_file = s.tool_file;
  j.settings = detail::settings_of(s, j.setup.config, *j.setup.machine);
  j.settings.rounding_mm = writer::rounding_mm(false, j.setup.dialect);
  j.settings.rounding_inch_mm = writer::rounding_mm(true, j.setup.dialect);
  j.settings.geometry_only = purpose == Purpose::check;
  read_program(j, io);
  if (purpose == Purpose::compensate) detail::warn_meaningless(j.settings, j.setup.strict, io);
  if (!j.pieces) detail::subprograms(j, io);
  j.stock_spec = stock_spec(s.stock, j.setup.config);
  resolve_physics(j);
  // The workpiece's part, material and fixtures checked before the program.
  const std::optional<detail::WorkpiecePlan> plan = shared ? std::nullopt : detail::plan_workpiece(j);
  Diagnostics diags = io.diagnostics(j.setup.max_errors);
  stage("checking", 0);
  if (j.pieces) detail::check_in_pieces(j, diags, progress);
  else detail::check_whole(j, diags);
  stage("checking", 1);
  if (diags.errors())
    throw Error(ErrorKind::input, j.prog.source().name() + ": error: the program has errors; " +
                                 (purpose == Purpose::compensate ? "nothing compensated, nothing written" : "not simulated"))
        .with_errors_of(diags);
  if (!s.measured.empty()) j.measured = detail::read_observations(s);
  // The earlier operations read and checked before any stock is built.
  std::vector<EarlierRun> earlier;
  if (!shared) earlier = read_earlier_all(s.stock_from, j.setup, j.physics.tools, io);
  stage("stock", 0);
  build_stock_and_part(j, io, shared, earlier);
  stage("stock", 1);
  detail::check_stock_reached(j, diags);
  if (j.physics.part) stage("gouge check", 0);
  detail::check_gouges(j, diags);
  for (const interp::Motion& m : j.motions) j.count_left(m);  // in pieces: the check pass counted them
  // The workpiece's FEM last: every check that can fail has run.
  j.workpiece = shared ? shared->workpiece : plan ? detail::build_workpiece(j, *plan, io, progress) : nullptr;
  j.physics.workpiece = j.workpiece.get();
  if (io.verbose) detail::print_setup(j, io);
  return j;
}

}  // namespace deflex::job
