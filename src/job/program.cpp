// job::path() and job::rewrite() (program.hpp).
#include "deflex/job/program.hpp"

#include "deflex/gcode/reader.hpp"
#include "deflex/job/check.hpp"
#include "deflex/job/setup.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::job {
namespace {

// Takes the motions and drops them: a pass for the diagnostics alone.
class NullSink : public interp::MotionSink {
 public:
  void motion(const interp::Motion&) override {}
};

// The file read in pieces (memory does not grow with its length) unless it
// is one piece anyway, may call subprograms or comes from the input stream.
gcode::ProgramPasses load(const std::string& file, Io& io) {
  return gcode::ProgramPasses(file, &io.in, piece_lines());
}

// One pass of the interpreter over the pieces.
interp::Stats interpret_all(gcode::ProgramPasses& src, const interp::Options& opt, Diagnostics& diags,
                            interp::MotionSink& sink) {
  interp::Interpreter it(opt, diags, sink);
  src.each([&](const gcode::Program& p, bool last) { it.feed(p, last); });
  return it.finish();
}

}  // namespace

PathResult path(const PathSettings& ps, interp::MotionSink& sink, Io& io) {
  Setup s = resolve(ps.read);
  s.tool_file = ps.tool_file;
  gcode::ProgramPasses prog = load(ps.program, io);
  Diagnostics diags = io.diagnostics(s.max_errors);
  PathResult r;
  r.name = prog.name();
  auto counted = [&]() -> PathResult& {
    r.errors = diags.errors();
    r.warnings = diags.warnings();
    return r;
  };
  check_text(prog, s, diags);
  // The text's own checks come first, as `check` reports them; an error
  // there (under strict, a number without its decimal point) hands nothing on.
  if (diags.errors()) return counted();
  // Two passes: the first reports every diagnostic and hands nothing on, so a
  // program with an error (past max_blocks included) hands over no path at
  // all rather than megabytes of it cut off at the error; the second, quiet,
  // hands on. Interpretation is cheap next to printing, so a printed path
  // costs well under 2x.
  NullSink none;
  const interp::Options opt = s.interp();  // the interpreter keeps a reference
  r.stats = interpret_all(prog, opt, diags, none);
  if (r.stats.stopped || diags.errors()) return counted();
  Diagnostics quiet(nullptr, 0);
  interpret_all(prog, opt, quiet, sink);
  r.handed = true;
  return counted();
}

void rewrite(const RewriteSettings& rs, Io& io, const std::function<void()>& writing) {
  Setup s = resolve(rs.read);
  const bool to_out = rs.output.empty() || rs.output == "-";
  if (!to_out) writer::check_output_path(rs.output, rs.program);
  gcode::ProgramPasses prog = load(rs.program, io);
  Diagnostics diags = io.diagnostics(s.max_errors);
  NullSink none;
  const interp::Options opt = s.interp();
  interpret_all(prog, opt, diags, none);
  if (diags.errors()) throw Error(ErrorKind::input, prog.name() + ": error: not written: the program has errors");
  auto write = [&](std::ostream& o) {
    prog.each([&](const gcode::Program& p, bool) { writer::Rewriter(p, s.dialect).write(o); });
  };
  if (!to_out) return writer::write_file_atomically(rs.output, rs.program, write);
  if (writing) writing();
  write(io.out);
}

}  // namespace deflex::job
