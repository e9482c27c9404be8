// job::path() and job::rewrite() (program.hpp).
#include "deflex/job/program.hpp"

#include <future>

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

// What both forms of path() do before they interpret: the settings, the
// program and the text's own checks (true: they found no error).
struct PathRun {
  Setup s;
  gcode::ProgramPasses prog;
  Diagnostics diags;
  PathResult r;
  PathRun(const PathSettings& ps, Io& io)
      : s(resolve(ps.read)), prog(load(ps.program, io)), diags(io.diagnostics(s.max_errors)) {
    s.tool_file = ps.tool_file;
    r.name = prog.name();
  }
  // The text's own checks come first, as `check` reports them; an error
  // there (under strict, a number without its decimal point) hands nothing on.
  bool text_ok() {
    check_text(prog, s, diags);
    return !diags.errors();
  }
  PathResult& counted() {
    r.errors = diags.errors();
    r.warnings = diags.warnings();
    return r;
  }
};

}  // namespace

PathResult path(const PathSettings& ps, interp::MotionSink& sink, Io& io) {
  PathRun run(ps, io);
  if (!run.text_ok()) return run.counted();
  // Two passes: the first reports every diagnostic and hands nothing on, so a
  // program with an error (past max_blocks included) hands over no path at
  // all rather than megabytes of it cut off at the error; the second, quiet,
  // hands on.
  NullSink none;
  const interp::Options opt = run.s.interp();  // the interpreter keeps a reference
  run.r.stats = interpret_all(run.prog, opt, run.diags, none);
  if (run.r.stats.stopped || run.diags.errors()) return run.counted();
  Diagnostics quiet(nullptr, 0);
  interpret_all(run.prog, opt, quiet, sink);
  run.r.handed = true;
  return run.counted();
}

PathResult path(const PathSettings& ps, HoldingSink& sink, Io& io) {
  PathRun run(ps, io);
  const interp::Options opt = run.s.interp();  // the interpreter keeps a reference
  if (ps.threads == 1) {
    if (!run.text_ok()) {
      sink.finish(false);
      return run.counted();
    }
    run.r.stats = interpret_all(run.prog, opt, run.diags, sink);
    run.r.handed = !run.r.stats.stopped && !run.diags.errors();
    sink.finish(run.r.handed);
    return run.counted();
  }
  // The text checks on a thread of their own, beside the interpretation (they
  // lex every line too). Their messages come first, as in one thread: the
  // interpretation's are held until the checks are done, and dropped with the
  // interpretation when the checks found an error.
  TextChecks text(run.s);
  std::future<void> reading = std::async(std::launch::async, [&] { text.read(run.prog); });
  int text_errors = -1;  // -1: the checks' messages not reported yet
  auto text_first = [&] {  // true: the checks found no error
    if (text_errors < 0) {
      reading.get();
      text.finish(run.diags);
      text_errors = run.diags.errors();
    }
    return text_errors == 0;
  };
  Diagnostics interp_diags = io.diagnostics(run.s.max_errors);
  interp_diags.hold(ps.held_messages, [&] { text_first() ? interp_diags.release() : interp_diags.drop_held(); });
  const interp::Stats stats = interpret_all(run.prog, opt, interp_diags, sink);
  if (!text_first()) {
    sink.finish(false);
    return run.counted();
  }
  interp_diags.release();
  run.r.stats = stats;
  run.r.handed = !stats.stopped && !interp_diags.errors();
  sink.finish(run.r.handed);
  PathResult& r = run.counted();
  r.errors += interp_diags.errors();
  r.warnings += interp_diags.warnings();
  return r;
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
