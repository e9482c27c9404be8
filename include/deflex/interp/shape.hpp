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

// The same over a program read in pieces (gcode/reader.hpp): add() each piece
// in order, then finish() reports what check_program_shape would.
class ShapeCheck {
 public:
  void add(const gcode::Program& piece);
  // add() with the lines lexed by the caller (who lexes them once for more
  // than one check): begin(piece), line() for its lines in order while
  // wants_lines(), end(piece).
  void begin(const gcode::Program& piece);
  bool wants_lines() const { return !ended_; }
  void line(const gcode::Block& b);
  void end(const gcode::Program& piece);
  void finish(Diagnostics& diags);

 private:
  std::string name_;
  bool pieces_ = false, text_ = false, ended_ = false;
  bool cr_only_ = false;          // no LF at all (one piece) and a CR before the last byte
  std::string first_line_head_;   // the start of line 1 (the CR-only warning's excerpt)
  std::uint32_t piece_last_ = 0;  // the last block line of the piece being read
  std::uint32_t last_block_ = 0;  // the last block line so far, and its text
  std::string last_block_text_;
};

// Per motion: a cutting motion with no spindle speed (no S word, or S0)
// warns once, at its line.
class SpindleCheck {
 public:
  SpindleCheck(const SourceText& src, Diagnostics& d) : src_(&src), d_(d) {}
  void motion(const Motion& m);
  void set_source(const SourceText& piece) { src_ = &piece; }  // the piece being read

 private:
  const SourceText* src_;
  Diagnostics& d_;
  bool told_ = false;
};

}  // namespace deflex::interp
