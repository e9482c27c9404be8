#include "deflex/interp/decimal.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "deflex/diag/plural.hpp"

namespace deflex::interp {
namespace {

bool axis_letter(char c) {
  return c == 'X' || c == 'Y' || c == 'Z' || c == 'I' || c == 'J' || c == 'K' || c == 'R';
}

}  // namespace

namespace {

// The increment in millimetres a pointless word counts under the dialect.
double increment_mm(const profile::Dialect& d, bool inch) { return inch ? d.lii_inch * 25.4 : d.lii_mm; }

void report_mixed(const SourceText& src, const profile::Dialect& d, Diagnostics& diags, bool strict,
                  const DecimalFinding& f, char letter, double value, double lii_mm) {
  // Both readings of the first word: increments of the dialect's least input
  // increment (Fanuc's rule) or the number as written (calculator style).
  char buf[420];
  std::snprintf(buf, sizeof buf,
                "%c%g has no decimal point while %s %s one: dialect %s reads it as %g "
                "(least input increments of %g), a control that reads numbers as written (LinuxCNC) as %g; "
                "%s on %s. Check the dialect ({dialect} linuxcnc) or write the points",
                letter, value, plural(f.with_point, "other axis word").c_str(), f.with_point == 1 ? "has" : "have",
                d.name.c_str(), value * lii_mm, lii_mm, value, plural(f.without_point, "such word").c_str(),
                plural(f.lines, "line").c_str());
  diags.report(strict ? Severity::error : Severity::warning, src, f.first_line, f.first_col, buf);
}

}  // namespace

DecimalFinding check_decimal_points(const gcode::Program& prog, const profile::Dialect& d, Diagnostics& diags,
                                    bool strict) {
  DecimalCheck c(d);
  c.add(prog);
  return c.finish(diags, strict);
}

void DecimalCheck::add(const gcode::Program& piece) {
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  for (std::uint32_t l = piece.first_line(); l <= piece.last_line(); ++l) {
    const bool ok = piece.lex(l, b, quiet);
    line(piece, b, ok);
  }
}

void DecimalCheck::line(const gcode::Program& piece, const gcode::Block& b, bool ok) {
  // A line that does not read is the lexer's to report (X11O.: a letter
  // where a digit was expected, not a missing decimal point).
  if (!ok || b.kind != gcode::LineKind::block || b.macro) return;
  for (const gcode::Word& w : b.words)
    if (w.letter == 'G' && (w.value == 20 || w.value == 21)) inch_ = w.value == 20;
  bool counted = false;
  const std::uint32_t l = b.line;
  for (const gcode::Word& w : b.words) {
    if (!axis_letter(w.letter)) continue;
    if (w.has_point) {
      ++f_.with_point;
      continue;
    }
    if (w.value == 0) continue;
    // The line's text goes with the word: the piece is gone when it is reported.
    auto here = [&] {
      name_ = piece.source().name();
      return Word{w.letter, w.value, increment_mm(d_, inch_), l, w.begin - b.begin + 1,
                  std::string(piece.source().line_text(l))};
    };
    if (!f_.without_point) first_ = here();
    if (std::abs(w.value * increment_mm(d_, inch_)) > std::abs(largest_.value * largest_.lii_mm)) largest_ = here();
    if (!tiny_.letter && std::abs(w.value * increment_mm(d_, inch_)) < 1e-3) tiny_ = here();
    ++f_.without_point;
    if (!counted) ++f_.lines, counted = true;
  }
}

DecimalFinding DecimalCheck::finish(Diagnostics& diags, bool strict) {
  const profile::Dialect& d = d_;
  DecimalFinding f = f_;
  const Word& first = first_;
  const Word& largest = largest_;
  const Word& tiny = tiny_;
  f.first_line = first.line;
  f.first_col = first.col;
  // Under calculator-style input (LinuxCNC) a number reads as written with or
  // without its point: no finding.
  if (!f.without_point || d.decimal_rule != profile::DecimalRule::least_input_increment) return f;
  const Severity sev = strict ? Severity::error : Severity::warning;
  char buf[480];
  if (f.with_point) {
    report_mixed(first.source(name_), d, diags, strict, f, first.letter, first.value, first.lii_mm);
  } else if (std::abs(largest.value * largest.lii_mm) < kTinyProgramMm) {
    // A consistent increment program (X76000 for 76 mm) is ordinary; one whose
    // largest word still reads under a millimetre was written for a control
    // that reads numbers as written.
    std::snprintf(buf, sizeof buf,
                  "no axis word has a decimal point and the largest, %c%g, reads as %g mm under dialect %s "
                  "(least input increments of %g mm): the whole program moves within %g mm, hops of "
                  "micrometres. A control that reads numbers as written (LinuxCNC) reads it as %g. Check the "
                  "dialect ({dialect} linuxcnc) or write the points",
                  largest.letter, largest.value, largest.value * largest.lii_mm, d.name.c_str(), largest.lii_mm,
                  std::abs(largest.value * largest.lii_mm), largest.value);
    diags.report(sev, largest.source(name_), largest.line, largest.col, buf);
  }
  if (tiny.letter) {
    std::snprintf(buf, sizeof buf,
                  "%c%g has no decimal point and reads as %g mm under dialect %s (least input increments of "
                  "%g mm): a sub-micrometre hop no control resolves. A control that reads numbers as written "
                  "reads it as %g",
                  tiny.letter, tiny.value, tiny.value * tiny.lii_mm, d.name.c_str(), tiny.lii_mm, tiny.value);
    diags.report(sev, tiny.source(name_), tiny.line, tiny.col, buf);
  }
  return f;
}

}  // namespace deflex::interp
