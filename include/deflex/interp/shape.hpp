// What a machinist must be told about the shape of a file before trusting it:
// an empty program, CR-only line ends (the whole file reads as one line), no
// program end (a file cut off in transfer), cutting with the spindle stopped.
// Warnings, each once, at the line concerned.
#pragma once
#include "deflex/diag/diagnostics.hpp"
#include "deflex/gcode/program.hpp"
#include "deflex/interp/motion.hpp"

namespace deflex::interp {

// The file as text: empty, CR-only line ends, no M2/M30 (M99 for a file that
// is one subprogram). Reads the blocks, not the motions.
void check_program_shape(const gcode::Program& prog, Diagnostics& diags);

// Per motion: a cutting motion with no spindle speed (no S word, or S0)
// warns once, at its line.
class SpindleCheck {
 public:
  SpindleCheck(const SourceText& src, Diagnostics& d) : src_(src), d_(d) {}
  void motion(const Motion& m);

 private:
  const SourceText& src_;
  Diagnostics& d_;
  bool told_ = false;
};

}  // namespace deflex::interp
