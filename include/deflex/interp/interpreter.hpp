// Fanuc/ISO modal interpreter: blocks in, motions out (see motion.hpp).
//
// Positions are kept in mm whatever G20/G21 says; numbers are converted with the
// dialect's decimal-point rule. Anything whose effect deflex cannot know exactly
// (macro B, G68, G51, G52, G92, G10, G65/G66, polar coordinates, rotary axes,
// G87/G88 ...) is refused with an error, and interpretation stops there: every
// position after it would be a guess. Lexical errors elsewhere are still reported.
#pragma once
#include <functional>
#include <map>
#include <string>
#include <memory>
#include <optional>
#include <cstdint>
#include <vector>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/gcode/program.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/profile/profile.hpp"

namespace deflex::interp {

struct Options {
  profile::Dialect dialect;
  const profile::MachineProfile* machine = nullptr;  // offsets, reference points
  bool block_delete_switch = false;  // true: `/` blocks are skipped
  // Most blocks executed, and most motions generated, repeats included: a few
  // nested subprogram calls can otherwise ask for 9999^8 of them.
  std::uint64_t max_blocks = 10'000'000;
  // G41/G42: the radius (wear included, mm) of D register n, or none (the
  // caller reads the machine profile's tool_offsets, else the tool library's
  // T<n>: cli::Setup). Empty: every D but D0 is an error.
  std::function<std::optional<double>(int d)> cutter_radius_mm;
  // Per line number of the whole file, whether the line runs more than once
  // (a subprogram called twice or repeated: CallStructure::repeated). A move
  // inside a subprogram on a line that runs once is compensable; null: none
  // inside a subprogram is.
  const std::vector<std::uint8_t>* repeated_lines = nullptr;
  // Called with each line as the interpreter steps onto it, in execution order.
  std::function<void(std::uint32_t line)> on_line;
};

struct Stats {
  std::uint64_t lines = 0;
  std::uint64_t blocks = 0;          // lines with words that were executed
  std::uint64_t motions = 0;
  std::uint64_t compensable = 0;
  std::uint64_t cutter_comp_motions = 0;
  std::uint32_t first_cutter_comp_line = 0;
  bool stopped = false;              // interpretation stopped at an error
  std::uint32_t stopped_line = 0;
  bool ended = false;                // reached M2/M30
};

// Runs the whole program; returns statistics. Errors and warnings go to diags.
Stats interpret(const gcode::Program& prog, const Options& opt, Diagnostics& diags, MotionSink& sink);

// How a whole program runs its subprograms (M98/M99), from one run of it.
struct CallStructure {
  std::vector<std::uint8_t> repeated;  // per line (index = line number): 1 if it runs more than once
  std::vector<std::uint32_t> sub_of;   // per line: the O line of the subprogram it runs in (0: the main program)
  std::map<std::uint32_t, std::vector<std::uint32_t>> calls;  // O line -> the lines of the M98 blocks calling it
  std::string name_of(std::uint32_t o_line, const gcode::Program& prog) const;  // "O2000"
};
// Messages of the run go to `diags` (it may be quiet).
CallStructure call_structure(const gcode::Program& whole, const Options& opt, Diagnostics& diags);

namespace detail {
class Run;
}

// The same over a program read in pieces (gcode::ProgramReader), fed in
// order: the motions and diagnostics are those of interpret() on the whole
// file. A piece cannot call a subprogram in another piece: a file that calls
// subprograms is fed whole. `opt` must outlive the interpreter.
class Interpreter {
 public:
  Interpreter(const Options& opt, Diagnostics& diags, MotionSink& sink);
  ~Interpreter();
  Interpreter(const Interpreter&) = delete;
  Interpreter& operator=(const Interpreter&) = delete;
  // The piece must stay alive until the next feed() or finish(). `last`: no
  // piece follows (the end-of-file checks then come before the messages of
  // the lines never executed, as from interpret()).
  void feed(const gcode::Program& piece, bool last = false);
  Stats finish();  // after the last piece
  // True once nothing more will run: M2/M30, the tape end, or an error stopped it.
  bool over() const;

 private:
  std::unique_ptr<detail::Run> run_;
};

}  // namespace deflex::interp
