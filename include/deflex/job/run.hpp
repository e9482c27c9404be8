// A job opened: the program read and checked, and everything the physics
// needs (machine, tools, material, stock, part model) built from the
// settings. job::open() runs every check that can fail before the stock and
// the part model are built; simulate() and compensate() (job/job.hpp) run it.
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "deflex/compensate/compensate.hpp"
#include "deflex/fit/observe.hpp"
#include "deflex/gcode/reader.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/job/io.hpp"
#include "deflex/job/settings.hpp"
#include "deflex/job/setup.hpp"
#include "deflex/job/workpiece.hpp"
#include "deflex/part/part.hpp"
#include "deflex/process/machining_time.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::job {

// What the run is opened for: the checks and how the program is read differ.
enum class Purpose {
  compensate,  // read in pieces where it can be (memory does not grow with the program)
  simulate,    // in pieces unless judged against a reference
  compare,     // read whole, beside others on a shared stock
  fit,         // read whole: simulated once per basis machine (fit/basis.hpp)
  check,       // check --stock: in pieces like simulate; the sweep and the assembly check
               // alone (compensate::Settings::geometry_only): no material, no part model
};

struct Run {
  Settings given;          // as given, for what comes after open()
  Purpose purpose = Purpose::simulate;
  Setup setup;
  std::string material, stock_spec, part_spec;  // as resolved, for the report's provenance
  gcode::Program prog{SourceText("", "")};
  std::vector<interp::Motion> motions;
  compensate::Physics physics;
  compensate::Settings settings;  // the simulation's and the mirror's, resolved and checked
  std::unique_ptr<stock::ZMap> stock;
  std::unique_ptr<part::PartModel> part;
  // Settings::workholding: the workpiece's compliance in the cut, built last
  // in open() (physics.workpiece points to it); null: a rigid workpiece.
  std::shared_ptr<const WorkpieceInCut> workpiece;
  // Settings::measured read (before anything is built): the points the
  // prediction is held against.
  std::vector<fit::Observation> measured;
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
  // The lines the gouge check finds cutting into the part, sorted.
  std::vector<std::uint32_t> gouge_lines;
  void count_left(const interp::Motion& m);
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

class Observer;  // job.hpp

// Reads the program and everything the physics needs; throws on any error.
// Every check that can fail runs before the stock and part are built.
// `observer` (may be null) sees the stages ("checking", "stock", "gouge
// check") with their fractions and may cancel at each step (Cancelled).
// `shared` (may be null): a run whose stock and part model this one uses
// instead of building its own (compare: every program on the same stock).
// Chooses itself whether the program is read whole or in pieces: in pieces
// where it is long, comes from a file and calls no subprogram.
Run open(const Settings& s, Purpose purpose, Io& io, Observer* observer = nullptr, const Run* shared = nullptr);

// What --spindle and --feed (Settings::spindle_rpm, feed_mm_per_min) give a
// cutting motion whose program lacks them.
void fill_cut_defaults(const Settings& s, interp::Motion& m);
// A cutting move on one of the sorted gouge lines stays as written (Fixed::gouge).
void leave_gouge(interp::Motion& m, const std::vector<std::uint32_t>& gouge_lines);
// The Z-map's view of a library tool: its lower surface.
stock::ToolProfile profile_of(const stiffness::Tool& t);
// Lines of the program's file, each as a one-line SourceText (the excerpts of
// findings, also when the program was read in pieces: one pass over the file).
std::map<std::uint32_t, SourceText> lines_of_file(const Run& r, const std::vector<std::uint32_t>& lines);
// The tool of a T number in the run's library (Settings::tool overriding), null where none.
std::function<const stiffness::Tool*(int)> tool_of(const Run& r);

}  // namespace deflex::job
