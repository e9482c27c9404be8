// The earlier operations (earlier.hpp).
#include "earlier.hpp"

#include "deflex/engage/path.hpp"
#include "deflex/engage/sweep_program.hpp"
#include "deflex/interp/interpreter.hpp"
#include "deflex/interp/travel.hpp"
#include "job.hpp"

namespace deflex::cli {
namespace {

// --stock-from and --stock-from-tools keep their order: Boost stores each
// option's values apart, which loses which library follows which program, but
// its store() parses the occurrences in command-line order, each through this
// semantic's xparse, so each is appended to the list as it is parsed.
class EarlierOption : public po::typed_value<std::vector<std::string>> {
 public:
  EarlierOption(std::vector<EarlierOp>& ops, bool tools)
      : po::typed_value<std::vector<std::string>>(nullptr), ops_(ops), tools_(tools) {}
  void xparse(boost::any& store, const std::vector<std::string>& tokens) const override {
    po::typed_value<std::vector<std::string>>::xparse(store, tokens);
    for (const std::string& t : tokens) {
      if (!tools_) {
        ops_.push_back({t, ""});
      } else if (ops_.empty() || !ops_.back().tool_file.empty()) {
        throw po::error("--stock-from-tools " + t + " follows no --stock-from, or one that has its library already: " +
                        "it names the tool library of the --stock-from just before it");
      } else {
        ops_.back().tool_file = t;
      }
    }
  }

 private:
  std::vector<EarlierOp>& ops_;
  bool tools_;
};

}  // namespace

void add_stock_from_options(po::options_description& d, std::vector<EarlierOp>& ops) {
  d.add_options()
      ("stock-from", (new EarlierOption(ops, false))->composing()->value_name("FILE"),
       "an earlier program (roughing, semi-finishing) swept into the stock first with its own tools, geometry only; "
       "repeat for several, in order")
      ("stock-from-tools", (new EarlierOption(ops, true))->composing()->value_name("LIB"),
       "the tool library of the --stock-from just before it (YAML, Fusion 360 JSON or LinuxCNC .tbl), where that "
       "program's T numbers name another library than --tool-file's");
}

std::vector<EarlierOp> earlier_of_job(const yaml::Map& job, const std::function<std::string(const std::string&)>& path) {
  const YAML::Node list = job.get("stock_from");
  if (!list.IsSequence())
    job.fail("stock_from", "stock_from is a list of programs, in the order they ran: a path, or {program: P, "
                           "tool_file: T} for a program whose tools are in a library of its own");
  std::vector<EarlierOp> ops;
  for (const YAML::Node& n : list) {
    if (!n.IsMap()) {
      ops.push_back({path(yaml::text(n, "stock_from", job.file())), ""});
      continue;
    }
    const yaml::Map e(n, "stock_from entry", job.file(), {"program", "tool_file"});
    ops.push_back({path(e.text("program")), e.has("tool_file") ? path(e.text("tool_file")) : ""});
  }
  return ops;
}

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
  if (file == "-") throw Error(ErrorKind::settings, "--stock-from takes files (standard input is the program's)");
  const gcode::Program prog(gcode::read_source(file, &io.in));
  Diagnostics diags(&io.err, setup.max_errors);
  std::vector<interp::Motion> motions;
  Collect c;
  c.out = &motions;
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
    throw Error(ErrorKind::input, prog.source().name() + ": error: the earlier operation has errors; nothing done");
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

}  // namespace deflex::cli
