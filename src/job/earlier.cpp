// The earlier operations (earlier.hpp).
#include "deflex/job/earlier.hpp"

#include "deflex/engage/path.hpp"
#include "deflex/engage/sweep_program.hpp"
#include "deflex/interp/interpreter.hpp"
#include "deflex/interp/travel.hpp"
#include "deflex/job/run.hpp"
#include "internal.hpp"

namespace deflex::job {

std::vector<EarlierRun> read_earlier_all(const std::vector<EarlierOp>& ops, const Setup& setup,
                                         const stiffness::ToolLibrary& run_tools, Io& io) {
  std::vector<EarlierRun> runs;
  for (const EarlierOp& op : ops) {
    EarlierRun r;
    if (op.tool_file.empty()) {
      r.motions = read_earlier(op.program, setup, run_tools, io);
    } else {
      r.own_tools = stiffness::load_tool_library(op.tool_file);
      // Its G41/G42 radii come from its own library too.
      Setup own = setup;
      own.tool_file = op.tool_file;
      r.motions = read_earlier(op.program, own, *r.own_tools, io);
    }
    runs.push_back(std::move(r));
  }
  return runs;
}

void sweep_earlier_all(const std::vector<EarlierRun>& runs, stock::ZMap& z, const stiffness::ToolLibrary& run_tools,
                       double cl_spacing_mm) {
  for (const EarlierRun& r : runs) sweep_earlier(r.motions, z, r.tools(run_tools), cl_spacing_mm);
}

std::string earlier_text(const EarlierOp& op) {
  return op.tool_file.empty() ? op.program : op.program + " (tools: " + op.tool_file + ")";
}

std::vector<interp::Motion> read_earlier(const std::string& file, const Setup& setup, const stiffness::ToolLibrary& lib,
                                         Io& io, const std::string& tool_override) {
  if (file == "-") throw Error(ErrorKind::settings, "{stock_from} takes files (standard input is the program's)");
  const gcode::Program prog(gcode::read_source(file, &io.in));
  Diagnostics diags = io.diagnostics(setup.max_errors);
  std::vector<interp::Motion> motions;
  interp::MotionList c(motions);
  interp::interpret(prog, setup.interp(), diags, c);
  for (const interp::Motion& m : motions) interp::check_travel(m, setup.machine->travel, prog.source(), diags);
  for (const interp::Motion& m : motions) {
    if (diags.errors()) break;
    if (m.kind == interp::MotionKind::rapid) continue;
    const bool no_tool = m.tool == 0 && tool_override.empty();
    const std::string id = !tool_override.empty() ? tool_override : "T" + std::to_string(m.tool);
    if (no_tool || !lib.tools.count(id)) {
      diags.report(Severity::error, prog.source(), m.line, 1,
                   (no_tool ? std::string("cutting with no tool selected (T.. M6)")
                            : "tool " + id + " is not in the tool library " + lib.file) +
                       ": an earlier operation sweeps the stock with its own tools");
      throw Error(ErrorKind::config, prog.source().name() + ": error: a tool of an earlier operation is missing; nothing done");
    }
  }
  if (diags.errors())
    throw Error(ErrorKind::input, prog.source().name() + ": error: the earlier operation has errors; nothing done")
        .with_errors_of(diags);
  return motions;
}

// Sweeps an earlier operation's motions into the job's stock with their own tools.
void sweep_earlier(const std::vector<interp::Motion>& motions, stock::ZMap& z, const stiffness::ToolLibrary& lib,
                   double cl_spacing_mm, const std::string& tool_override) {
  engage::PathOptions po;
  po.cl_spacing_mm = cl_spacing_mm;
  // Before the first tool change the tool is the one of the first cutting motion.
  int first = 0;
  for (const interp::Motion& m : motions)
    if (m.tool) { first = m.tool; break; }
  // A program with no tool at all has only rapids (read_earlier checked the
  // cutting moves): nothing is known to sweep.
  if (!first && tool_override.empty()) return;
  // The profile looked up once per tool change, not per motion (a program of
  // a million moves changes tools a few times).
  int last = -1;
  stock::ToolProfile profile;
  engage::sweep_motions(z, motions, [&](const interp::Motion& m) {
    const int t = m.tool ? m.tool : first;
    if (t != last) {
      profile = profile_of(lib.tools.at(!tool_override.empty() ? tool_override : "T" + std::to_string(t)));
      last = t;
    }
    return profile;
  }, po);
}

}  // namespace deflex::job
