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

namespace {

// The increment in millimetres a pointless word counts under the dialect.
double increment_mm(const profile::Dialect& d, bool inch) { return inch ? d.lii_inch * 25.4 : d.lii_mm; }

void report_mixed(const gcode::Program& prog, const profile::Dialect& d, Diagnostics& diags, bool strict,
                  const DecimalFinding& f, char letter, double value, double lii_mm) {
  // Both readings of the first word: increments of the dialect's least input
  // increment (Fanuc's rule) or the number as written (calculator style).
  char buf[420];
  std::snprintf(buf, sizeof buf,
                "%c%g has no decimal point while %zu other axis words have one: dialect %s reads it as %g "
                "(least input increments of %g), a control that reads numbers as written (LinuxCNC) as %g; "
                "%zu such words on %zu lines. Check the dialect (--dialect linuxcnc) or write the points",
                letter, value, f.with_point, d.name.c_str(), value * lii_mm, lii_mm, value, f.without_point,
                f.lines);
  diags.report(strict ? Severity::error : Severity::warning, prog.source(), f.first_line, f.first_col, buf);
}

}  // namespace

DecimalFinding check_decimal_points(const gcode::Program& prog, const profile::Dialect& d, Diagnostics& diags,
                                    bool strict) {
  DecimalFinding f;
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  bool inch = false;
  struct Word {
    char letter = 0;
    double value = 0, lii_mm = 0;
    std::uint32_t line = 0, col = 0;
  } first, largest, tiny;  // first pointless word, the largest one, the first sub-micrometre one
  for (std::uint32_t l = 1; l <= prog.line_count(); ++l) {
    prog.lex(l, b, quiet);
    if (b.kind != gcode::LineKind::block || b.macro) continue;
    for (const gcode::Word& w : b.words)
      if (w.letter == 'G' && (w.value == 20 || w.value == 21)) inch = w.value == 20;
    bool counted = false;
    for (const gcode::Word& w : b.words) {
      if (!axis_letter(w.letter)) continue;
      if (w.has_point) {
        ++f.with_point;
        continue;
      }
      if (w.value == 0) continue;
      const Word here{w.letter, w.value, increment_mm(d, inch), l, w.begin - b.begin + 1};
      if (!f.without_point) first = here;
      if (std::abs(here.value * here.lii_mm) > std::abs(largest.value * largest.lii_mm)) largest = here;
      if (!tiny.letter && std::abs(here.value * here.lii_mm) < 1e-3) tiny = here;
      ++f.without_point;
      if (!counted) ++f.lines, counted = true;
    }
  }
  f.first_line = first.line;
  f.first_col = first.col;
  // Under calculator-style input (LinuxCNC) a number reads as written with or
  // without its point: no finding.
  if (!f.without_point || d.decimal_rule != profile::DecimalRule::least_input_increment) return f;
  const Severity sev = strict ? Severity::error : Severity::warning;
  char buf[480];
  if (f.with_point) {
    report_mixed(prog, d, diags, strict, f, first.letter, first.value, first.lii_mm);
  } else if (std::abs(largest.value * largest.lii_mm) < kTinyProgramMm) {
    // A consistent increment program (X76000 for 76 mm) is ordinary; one whose
    // largest word still reads under a millimetre was written for a control
    // that reads numbers as written.
    std::snprintf(buf, sizeof buf,
                  "no axis word has a decimal point and the largest, %c%g, reads as %g mm under dialect %s "
                  "(least input increments of %g mm): the whole program moves within %g mm, hops of "
                  "micrometres. A control that reads numbers as written (LinuxCNC) reads it as %g. Check the "
                  "dialect (--dialect linuxcnc) or write the points",
                  largest.letter, largest.value, largest.value * largest.lii_mm, d.name.c_str(), largest.lii_mm,
                  std::abs(largest.value * largest.lii_mm), largest.value);
    diags.report(sev, prog.source(), largest.line, largest.col, buf);
  }
  if (tiny.letter) {
    std::snprintf(buf, sizeof buf,
                  "%c%g has no decimal point and reads as %g mm under dialect %s (least input increments of "
                  "%g mm): a sub-micrometre hop no control resolves. A control that reads numbers as written "
                  "reads it as %g",
                  tiny.letter, tiny.value, tiny.value * tiny.lii_mm, d.name.c_str(), tiny.lii_mm, tiny.value);
    diags.report(sev, prog.source(), tiny.line, tiny.col, buf);
  }
  return f;
}

}  // namespace deflex::interp
