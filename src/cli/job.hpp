// What compensate, simulate and compare share: their options, the job a run
// reads (program, machine, tools, material, stock, part), the checks before
// any computation, and the pieces of their output.
#pragma once
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "common.hpp"
#include "earlier.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/compensate/plausibility.hpp"
#include "deflex/gcode/reader.hpp"
#include "deflex/part/part.hpp"
#include "deflex/process/machining_time.hpp"
#include "deflex/report/json.hpp"
#include "deflex/stock/tool.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::cli {

struct Args {
  ReadOptions read;
  MaterialOptions mat;
  PartOptions part;
  std::string file, output, reference, tool_file, tool, stock, report;
  std::vector<EarlierOp> stock_from;  // earlier operations swept into the stock, in order
  std::string job;                      // a job file: what the command line leaves out
  std::optional<double> tolerance, gain;
  double feed_limit_N = 0;
  std::optional<double> spindle_rpm, feed_mm_per_min;
  double cell_mm = 0.05, cl_spacing_mm = 0.5;
  int max_iterations = 8, threads = 0;
  bool tool_only = false, help = false;
  bool expand_subprograms = false;  // compensate --expand-subprograms
};

struct Job {
  Setup setup;
  std::string material, stock_spec, part_spec;  // as given, for the report's provenance
  std::vector<EarlierOp> stock_from;             // the earlier operations swept into the stock
  gcode::Program prog;
  std::vector<interp::Motion> motions;
  compensate::Physics physics;
  compensate::Settings settings;
  std::unique_ptr<stock::ZMap> stock;
  std::unique_ptr<part::PartModel> part;
  // A program read in pieces (memory does not grow with it): `prog` holds no
  // text and `motions` stay empty; the checks' pass built what needs the whole
  // program. Null: read whole.
  std::unique_ptr<gcode::ProgramPasses> pieces;
  // A whole program's subprogram calls (null in pieces: such a file is read whole).
  std::shared_ptr<const interp::CallStructure> calls;
  process::MachiningTime time_as_written;
  std::size_t motion_count = 0;
  // The cutting moves deflex leaves as written, per reason: blocks and the first line.
  struct LeftMoves {
    std::size_t blocks = 0;
    std::uint32_t first_line = 0, last_line = 0;
  };
  std::map<interp::Fixed, LeftMoves> left_moves;
  // The lines the gouge check finds cutting into the part (--part), sorted.
  std::vector<std::uint32_t> gouge_lines;
  void count_left(const interp::Motion& m) {
    if (m.kind == interp::MotionKind::rapid || m.fixed == interp::Fixed::no || m.fixed == interp::Fixed::rapid) return;
    LeftMoves& l = left_moves[m.fixed];
    if (l.blocks && l.last_line == m.line) return;
    if (!l.blocks++) l.first_line = m.line;
    l.last_line = m.line;
  }
  // For the provenance, in pieces: the program's SHA-256 and its cutting tools.
  std::string sha256;
  std::set<std::string> cutting_tools;
  // The box the cutting moves' tips span (work frame, mm) and the largest
  // radius of their tools: whether they can reach the stock at all.
  struct CutExtent {
    bool any = false;
    compensate::V3 lo_mm = compensate::V3::Zero(), hi_mm = compensate::V3::Zero();
    double radius_mm = 0;
    void add(const interp::Motion& m, double radius_mm);
  } cut_extent;
};

struct Collect : interp::MotionSink {
  std::vector<interp::Motion>* out;
  void motion(const interp::Motion& m) override { out->push_back(m); }
};

// What --spindle and --feed give a cutting motion whose program lacks them.
void fill_cut_defaults(const Args& a, interp::Motion& m);
// The options of compensate (compensating) or simulate/compare.
void describe(po::options_description& d, Args& a, bool compensating);
// The setup of a run that needs a machine (travel, dialect): throws Error(usage) without one.
Setup resolve_with_machine(const ReadOptions& r);
// The stock a run starts from: `given` (--stock), else config.yaml's; throws Error(usage) when neither.
std::string stock_spec(const std::string& given, const profile::Config& cfg);
// The Z-map's view of a library tool: its lower surface.
stock::ToolProfile profile_of(const stiffness::Tool& t);

// Fills what the command line left out from the job file `a.job` (if any);
// `files` gets the job's program when the command line names none. Paths in
// the job are relative to its folder. Throws Error(config) at line:col.
void apply_job(Args& a, std::vector<std::string>& files);
// Reads the program and everything the physics needs; throws on any error.
// Every check that can fail runs before the stock and part are built.
// `shared` (may be null): a job whose stock and part model this one uses
// instead of building its own (compare: every program on the same stock).
// `in_pieces`: the caller can take the program in pieces (compensate without
// --report); it is then read so where it is long, comes from a file and calls
// no subprogram (and not --gain 0 with --feed-limit).
Job prepare(Args& a, Io& io, bool compensating, const Job* shared = nullptr, bool in_pieces = false);
// Lines of the program's file, each as a one-line SourceText (the excerpts of
// findings, also when the program was read in pieces: one pass over the file).
std::map<std::uint32_t, SourceText> lines_of_file(const Job& j, const std::vector<std::uint32_t>& lines);
// The tool of a T number in the job's library (--tool overriding), null where none.
std::function<const stiffness::Tool*(int)> tool_of(const Job& j);
// The progress line (--progress: on a terminal by default) with the stage,
// percentage, elapsed time and what is left at the rate so far; with
// --verbose each stage's time when it ends. Null when nothing is shown.
compensate::Progress progress_for(Io& io);
// After the last stage: the line cleared, the last stage's time (--verbose).
void end_progress(const compensate::Progress& p);
// What a run used (machine, dialect, tools, material, config), found where
// the defaults led: one line for the summary, the same for summary.json.
struct Used {
  std::string text;  // "used: machine mill3 (...); T1: flat D10 mm (samples/tools.yaml); material ...; config ..."
  report::Json json;
};
Used used(const Job& j);

// The run's provenance for report.html: what a reader needs to trust or redo it.
std::vector<std::pair<std::string, std::string>> provenance(const Job& j, const std::string& command,
                                                            const std::string& reference);
// Plausibility warnings (compensate::PlausibilityScan), compiler style at the
// line of the worst point, and their summary.json array.
void print_plausibility(const Job& j, const compensate::Plausibility& pl, Io& io);
// A cutting move on one of the sorted gouge lines stays as written (Fixed::gouge).
void leave_gouge(interp::Motion& m, const std::vector<std::uint32_t>& gouge_lines);
report::Json warnings_json(const compensate::Plausibility& pl);
// Machining time from the machine's axis limits, one line on stderr.
void time_line(Io& io, const process::MachiningTime& before, const process::MachiningTime& after);
// The command line as a shell would take it back (for the provenance).
std::string command_of(const char* cmd, const std::vector<std::string>& args);

}  // namespace deflex::cli
