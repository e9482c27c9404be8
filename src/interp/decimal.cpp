#include "deflex/interp/decimal.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace deflex::interp {
namespace {

bool axis_letter(char c) {
  return c == 'X' || c == 'Y' || c == 'Z' || c == 'I' || c == 'J' || c == 'K' || c == 'R';
}

}  // namespace

DecimalFinding check_decimal_points(const gcode::Program& prog, const profile::Dialect& d, Diagnostics& diags,
                                    bool strict) {
  DecimalFinding f;
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  double first_value = 0;
  char first_letter = 0;
  for (std::uint32_t l = 1; l <= prog.line_count(); ++l) {
    prog.lex(l, b, quiet);
    if (b.kind != gcode::LineKind::block || b.macro) continue;
    bool counted = false;
    for (const gcode::Word& w : b.words) {
      if (!axis_letter(w.letter)) continue;
      if (w.has_point) {
        ++f.with_point;
      } else if (w.value != 0) {
        if (!f.without_point) {
          f.first_line = l;
          f.first_col = w.begin - b.begin + 1;
          first_value = w.value;
          first_letter = w.letter;
        }
        ++f.without_point;
        if (!counted) ++f.lines, counted = true;
      }
    }
  }
  // Under calculator-style input (LinuxCNC) a number reads as written with or
  // without its point, and a mixed program is ordinary: no finding.
  if (!f.with_point || !f.without_point || d.decimal_rule != profile::DecimalRule::least_input_increment) return f;
  // Both readings of the first word: increments of the dialect's least input
  // increment (Fanuc's rule) or the number as written (calculator style).
  char buf[420];
  const double increments = first_value * d.lii_mm;
  std::snprintf(buf, sizeof buf,
                "%c%g has no decimal point while %zu other axis words have one: dialect %s reads it as %g "
                "(least input increments of %g), a control that reads numbers as written (LinuxCNC) as %g; "
                "%zu such words on %zu lines. Check the dialect (--dialect linuxcnc) or write the points",
                first_letter, first_value, f.with_point, d.name.c_str(), increments, d.lii_mm, first_value,
                f.without_point, f.lines);
  diags.report(strict ? Severity::error : Severity::warning, prog.source(), f.first_line, f.first_col, buf);
  return f;
}

}  // namespace deflex::interp
