// Fanuc/ISO modal interpreter: blocks in, motions out (see motion.hpp).
//
// Positions are kept in mm whatever G20/G21 says; numbers are converted with the
// dialect's decimal-point rule. Anything whose effect deflex cannot know exactly
// (macro B, G68, G51, G52, G92, G10, G65/G66, polar coordinates, rotary axes,
// G87/G88 ...) is refused with an error, and interpretation stops there: every
// position after it would be a guess. Lexical errors elsewhere are still reported.
#pragma once
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

}  // namespace deflex::interp
