// job::check() (check.hpp): a program's diagnostics, travel and gouges.
#include "deflex/job/check.hpp"

#include <memory>
#include <optional>
#include <sstream>

#include "deflex/compensate/compensate.hpp"
#include "deflex/compensate/gouge.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/interp/decimal.hpp"
#include "deflex/interp/shape.hpp"
#include "deflex/interp/travel.hpp"
#include "deflex/job/run.hpp"
#include "deflex/part/part.hpp"
#include "deflex/stiffness/tool.hpp"
#include "internal.hpp"

namespace deflex::job {
namespace {

// The travel check as a sink of the interpreter, keeping the motions when asked.
class TravelCheck : public interp::MotionSink {
 public:
  TravelCheck(const profile::Travel& t, const std::string& name, Diagnostics& d)
      : t_(t), d_(d), spindle_(none_, d), none_(name, "") {}
  std::vector<interp::Motion>* keep = nullptr;  // collects the motions (the gouge check's)
  void motion(const interp::Motion& m) override {
    if (keep) keep->push_back(m);
    ++count_;
    interp::check_travel(m, t_, *src_, d_);
    spindle_.motion(m);
    if (m.comp && !cutter_comp_.first_line())
      cutter_comp_ = SourceText(none_.name(), std::string(src_->line_text(m.line)), m.line);
  }
  // The line of the first motion under G41/G42 (its piece may be gone).
  const SourceText& cutter_comp_line() const { return cutter_comp_; }
  void set_source(const SourceText& piece) {  // the piece being read
    src_ = &piece;
    spindle_.set_source(piece);
  }
  std::uint64_t count_ = 0;

 private:
  const profile::Travel& t_;
  const SourceText* src_ = &none_;
  Diagnostics& d_;
  interp::SpindleCheck spindle_;
  SourceText none_;
  SourceText cutter_comp_{"", "", 0};
};

// Which lines of a whole program run more than once, so that the count of
// compensable motions is compensate's (a subprogram run once is).
void find_repeated_lines(const gcode::ProgramPasses& prog, Setup& s) {
  const gcode::Program* whole = prog.whole_program();
  if (!whole || !gcode::may_need_whole_file(whole->bytes())) return;
  Diagnostics quiet(nullptr, 0);
  auto calls = std::make_shared<const interp::CallStructure>(interp::call_structure(*whole, s.interp(), quiet));
  s.repeated_lines = std::shared_ptr<const std::vector<std::uint8_t>>(calls, &calls->repeated);
}

// The gouge check of a whole program's motions against the part model.
void check_gouges(const CheckSettings& cs, const Setup& s, const std::string& part_file, const gcode::Program& whole,
                  const std::vector<interp::Motion>& motions, Diagnostics& diags) {
  const double gap = part_gap_mm(cs.part, s.config);
  const part::PartModel pm = part::PartModel::load(part_file);
  const stiffness::ToolLibrary lib = stiffness::load_tool_library(tool_library_path(cs.tool_file, s.config));
  compensate::Settings st;  // the tool choice and part reach of compensate
  st.tool_override = !cs.tool.empty() ? cs.tool : config_string(s.config, "tool");
  const compensate::PartGaps g = compensate::part_gaps(
      motions, pm, lib, [&st](const interp::Motion& m) { return compensate::tool_id(m, st); }, {}, gap,
      st.part_reach_mm);
  report_part_gaps(g, whole.source(), gap, diags);
}

// The holder and shank check: the program opened as a simulation would open
// it (the stock, the earlier programs swept into it, the tools and the
// machine's holder) and swept through the stock alone. Its own diagnostics
// were reported by the check's pass; the run's are kept quiet unless it fails.
void check_collisions(const CheckSettings& cs, Io& io, Diagnostics& diags) {
  if (cs.program == "-")
    throw Error(ErrorKind::settings, "{stock} in check takes a program file: the input stream is read once");
  Settings s;
  s.program = cs.program;
  s.read = cs.read;
  s.tool_file = cs.tool_file;
  s.tool = cs.tool;
  s.stock = cs.stock;
  s.stock_from = cs.stock_from;
  s.cell_mm = cs.cell_mm;
  s.cl_spacing_mm = cs.cl_spacing_mm;
  s.threads = cs.threads;
  std::ostringstream held;
  Io quiet{io.in, held, held};
  quiet.quiet = true;
  quiet.names = io.names;
  std::optional<Run> j;
  try {
    j.emplace(open(s, Purpose::check, quiet));
  } catch (const Error&) {
    io.err << held.str();
    throw;
  }
  detail::report_collisions(*j, detail::sweep_collisions(*j, {}), diags);
}

}  // namespace

void TextChecks::read(gcode::ProgramPasses& src, const std::function<void(const gcode::Program&)>& also) {
  // Each line lexed once for both checks.
  gcode::Block b;
  src.each([&](const gcode::Program& p, bool) {
    Diagnostics quiet(nullptr, 0);
    shape_.begin(p);
    for (std::uint32_t l = p.first_line(); l <= p.last_line(); ++l) {
      const bool ok = p.lex(l, b, quiet);
      if (shape_.wants_lines()) shape_.line(b);
      dec_.line(p, b, ok);
    }
    shape_.end(p);
    if (also) also(p);
  });
}

void TextChecks::finish(Diagnostics& diags) {
  shape_.finish(diags);
  dec_.finish(diags, s_.strict);
}

void check_text(gcode::ProgramPasses& src, const Setup& s, Diagnostics& diags,
                const std::function<void(const gcode::Program&)>& also) {
  TextChecks t(s);
  t.read(src, also);
  t.finish(diags);
}

double part_gap_mm(const PartSettings& p, const profile::Config& cfg) {
  const double gap = p.gap_mm ? *p.gap_mm : config_number(cfg, "part_gap_mm", 0.02);
  if (!(gap > 0)) throw Error(ErrorKind::settings, "{part_gap_mm} must be > 0 mm");
  return gap;
}

CheckResult check(const CheckSettings& cs, Io& io) {
  Setup s = resolve(cs.read);
  s.tool_file = cs.tool_file;
  const std::string part_file = !cs.part.part.empty() ? cs.part.part : config_path(s.config, "part");
  // The gouge check keeps the motions and names lines of the whole file: it reads it whole.
  gcode::ProgramPasses prog(cs.program, &io.in, part_file.empty() ? piece_lines() : 0);
  find_repeated_lines(prog, s);
  Diagnostics diags = io.diagnostics(s.max_errors);
  diags.set_keep(cs.keep_diagnostics);
  profile::Travel none;
  TravelCheck tc(s.machine ? s.machine->travel : none, prog.name(), diags);
  std::vector<interp::Motion> motions;
  tc.keep = part_file.empty() ? nullptr : &motions;
  check_text(prog, s, diags);
  const interp::Options opt = s.interp();  // the interpreter keeps a reference
  interp::Interpreter it(opt, diags, tc);
  prog.each([&](const gcode::Program& p, bool last) {
    tc.set_source(p.source());
    it.feed(p, last);
  });
  CheckResult r;
  r.stats = it.finish();
  if (!part_file.empty() && !r.stats.stopped) check_gouges(cs, s, part_file, *prog.whole_program(), motions, diags);
  if (!cs.stock.empty() && !r.stats.stopped && !diags.errors()) check_collisions(cs, io, diags);
  if (r.stats.cutter_comp_motions)
    diags.report(Severity::note, tc.cutter_comp_line(), r.stats.first_cutter_comp_line, 1,
                 plural(r.stats.cutter_comp_motions, "motion") + (r.stats.cutter_comp_motions == 1 ? " runs" : " run") +
                     " under G41/G42 cutter compensation (first here): deflex simulates the tool "
                     "centre's path and compensates the programmed contour (not the start-up moves)");
  r.name = prog.name();
  r.dialect = s.dialect.name;
  r.machine = s.machine ? s.machine->name : "";
  r.errors = diags.errors();
  r.warnings = diags.warnings();
  r.diagnostics = diags.all();
  return r;
}

}  // namespace deflex::job
