#include "deflex/interp/shape.hpp"

#include <string>

namespace deflex::interp {

void check_program_shape(const gcode::Program& prog, Diagnostics& diags) {
  const std::string& bytes = prog.source().bytes();
  const std::string& name = prog.source().name();
  if (bytes.find_first_not_of(" \t\r\n%") == std::string::npos) {
    diags.report(Severity::warning, name, "the program is empty: nothing to do");
    return;
  }
  if (bytes.find('\r') != std::string::npos && bytes.find('\n') == std::string::npos && bytes.find('\r') + 1 < bytes.size())
    diags.report(Severity::warning, prog.source(), 1, 1,
                 "the line ends are CR only (classic Mac): the whole file reads as one line; convert it, e.g. "
                 "tr '\\r' '\\n'");
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  std::uint32_t last = 0;
  for (std::uint32_t l = 1; l <= prog.line_count(); ++l) {
    prog.lex(l, b, quiet);
    if (b.kind != gcode::LineKind::block) continue;
    last = l;
    for (const gcode::Word& w : b.words)
      if (w.letter == 'M' && (w.code10() == 20 || w.code10() == 300 || w.code10() == 990)) return;
  }
  if (last)
    diags.report(Severity::warning, prog.source(), last, 1,
                 "no program end (M2, M30) after this last block: the file may be cut off; check it is complete");
}

void SpindleCheck::motion(const Motion& m) {
  if (told_ || m.kind == MotionKind::rapid || m.spindle_rpm > 0) return;
  told_ = true;
  d_.report(Severity::warning, src_, m.line, 1, "cutting with the spindle at 0 rpm (no S word, or S0)");
}

}  // namespace deflex::interp
