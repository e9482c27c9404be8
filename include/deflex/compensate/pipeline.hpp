// compensate over a program read in pieces, end to end: read, interpret,
// simulate the program as written beside the mirror pass, write, read back
// and check, piece after piece, so that memory is the Z-maps, the design
// normals and one piece, whatever the program's length. The output is the
// one compensate() and apply_offsets() give on the whole program, byte for
// byte (tests/cli/test_pieces.cpp).
#pragma once
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>

#include "deflex/compensate/apply.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/compensate/normals.hpp"
#include "deflex/process/machining_time.hpp"

namespace deflex::compensate {

struct PipelineInput {
  std::string path;                         // the program's file (read again: the checks read it first)
  std::uint32_t lines_per_read = 0;         // gcode::ProgramReader's
  std::size_t motions_per_piece = 0;        // a piece ends after at least this many motions
  interp::Options interp;
  std::function<void(interp::Motion&)> fix; // what the checks did to each motion (--spindle, --feed)
  const Physics* physics = nullptr;
  const Settings* settings = nullptr;
  PointSinks sinks;
  Progress progress;
  std::size_t total_motions = 0;            // for progress
  profile::AxisLimits limits;               // the machining time of the output
  std::function<void(const Result& piece)> on_piece;  // after each piece (its capped lines ...)
};

struct PipelineResult {
  Result totals;                   // Compensation::finish()
  WriteStats written;
  process::MachiningTime time;     // of the program as written out
  std::size_t pieces = 0;
};

// Writes the compensated program to `out` as it goes (the caller makes the
// output atomic); throws as safety_check() does when a piece is not what
// deflex meant.
PipelineResult compensate_in_pieces(const PipelineInput& in, std::ostream& out);

// simulate() over a program read in pieces: the points to in.sinks.nominal,
// as simulate() gives them on the whole program. Returns the motions run.
std::size_t simulate_in_pieces(const PipelineInput& in);

}  // namespace deflex::compensate
