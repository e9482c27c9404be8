// Subprograms written inline (compensate --expand-subprograms): each pass of
// a subprogram gets blocks of its own, so each can get its own compensation.
#pragma once
#include <string>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/gcode/program.hpp"
#include "deflex/interp/interpreter.hpp"

namespace deflex::writer {

// The program as it runs, with each subprogram call written inline: the M98
// block becomes a comment naming the call (in the dialect's style), the
// subprogram's blocks follow as many times as it runs (nested calls too), its
// M99 goes. The lines after the main program's end (the subprograms'
// definitions, the closing '%') stay as they are; lines the program never
// runs before its end (none in a program laid out as controls expect) are
// left out. Errors go to `diags` and the text is then empty: the run's own,
// and an M98 or M99 block with other words than N, P, L (they could not
// stand inline). A program without calls comes back byte for byte.
std::string expand_subprograms(const gcode::Program& whole, const interp::Options& opt, Diagnostics& diags);

}  // namespace deflex::writer
