#include "deflex/interp/shape.hpp"

#include <string>

namespace deflex::interp {

void check_program_shape(const gcode::Program& prog, Diagnostics& diags) {
  ShapeCheck c;
  c.add(prog);
  c.finish(diags);
}

void ShapeCheck::add(const gcode::Program& piece) {
  begin(piece);
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  for (std::uint32_t l = piece.first_line(); l <= piece.last_line() && wants_lines(); ++l) {
    piece.lex(l, b, quiet);
    line(b);
  }
  end(piece);
}

void ShapeCheck::begin(const gcode::Program& piece) {
  const std::string& bytes = piece.source().bytes();
  if (!pieces_) {
    pieces_ = true;
    name_ = piece.source().name();
    // A piece ends at a LF: with none in the first piece it is the whole file.
    cr_only_ = bytes.find('\r') != std::string::npos && bytes.find('\n') == std::string::npos &&
               bytes.find('\r') + 1 < bytes.size();
    // The excerpt of a line over 240 bytes is its first 240 and "..." (Diagnostics::report).
    first_line_head_ = std::string(piece.source().line_text(1).substr(0, 241));
  }
  if (!text_) text_ = bytes.find_first_not_of(" \t\r\n%") != std::string::npos;
  piece_last_ = 0;
}

void ShapeCheck::line(const gcode::Block& b) {
  if (b.kind != gcode::LineKind::block) return;
  piece_last_ = b.line;
  for (const gcode::Word& w : b.words)
    if (w.letter == 'M' && (w.code10() == 20 || w.code10() == 300 || w.code10() == 990)) ended_ = true;
}

void ShapeCheck::end(const gcode::Program& piece) {
  if (piece_last_ && !ended_) {
    last_block_ = piece_last_;
    last_block_text_ = std::string(piece.source().line_text(piece_last_));
  }
}

void ShapeCheck::finish(Diagnostics& diags) {
  if (!text_) {
    diags.report(Severity::warning, name_, "the program is empty: nothing to do");
    return;
  }
  if (cr_only_)
    diags.report(Severity::warning, SourceText(name_, first_line_head_), 1, 1,
                 "the line ends are CR only (classic Mac): the whole file reads as one line; convert it, e.g. "
                 "tr '\\r' '\\n'");
  if (last_block_ && !ended_)
    diags.report(Severity::warning, SourceText(name_, last_block_text_, last_block_), last_block_, 1,
                 "no program end (M2, M30) after this last block: the file may be cut off; check it is complete");
}

void SpindleCheck::motion(const Motion& m) {
  if (told_ || m.kind == MotionKind::rapid || m.spindle_rpm > 0) return;
  told_ = true;
  d_.report(Severity::warning, *src_, m.line, 1, "cutting with the spindle at 0 rpm (no S word, or S0)");
}

}  // namespace deflex::interp
