// The decimal-point trap (docs/physics.md, 'The decimal point'): on a Fanuc-style control `X76`
// is 76 least input increments (0.076 mm), on LinuxCNC 76 mm. deflex reads it
// as the dialect says and never guesses; but a program that writes most axis
// words with a decimal point and some without was almost surely written for
// the other rule, and a move read the wrong way is a crash. This check finds
// such programs.
#pragma once
#include "deflex/diag/diagnostics.hpp"
#include "deflex/gcode/program.hpp"
#include "deflex/profile/profile.hpp"

namespace deflex::interp {

struct DecimalFinding {
  std::size_t with_point = 0;     // axis words (X Y Z I J K R) written with a decimal point
  std::size_t without_point = 0;  // non-zero axis words without one
  std::uint32_t first_line = 0, first_col = 0;
  std::size_t lines = 0;          // lines holding one of those
};

// A program with no decimal point at all whose largest axis word still reads
// under this many millimetres is taken for one written for calculator input.
// A finishing program for a slender mill moves at least a millimetre; a
// consistent increment program (X76000) passes.
inline constexpr double kTinyProgramMm = 1.0;

// Counts the axis words with and without a decimal point. Under a dialect that
// counts least input increments (under calculator input every reading is the
// number as written) it reports, with both readings, a warning (an error when
// `strict`) at: the first pointless word of a program that mixes both kinds;
// the largest word of a pointless program that reads under kTinyProgramMm;
// the first pointless word that reads under a micrometre (a dialect with a
// finer increment). Inch programs (G20) count lii_inch. Returns the counts.
DecimalFinding check_decimal_points(const gcode::Program& prog, const profile::Dialect& d, Diagnostics& diags,
                                    bool strict);

// The same over a program read in pieces (gcode/reader.hpp): add() each piece
// in order, then finish() reports what check_decimal_points would.
class DecimalCheck {
 public:
  explicit DecimalCheck(const profile::Dialect& d) : d_(d) {}
  void add(const gcode::Program& piece);
  // add() with the lines lexed by the caller: line() for each line of the
  // piece in order, `ok` what Program::lex returned.
  void line(const gcode::Program& piece, const gcode::Block& b, bool ok);
  DecimalFinding finish(Diagnostics& diags, bool strict);

 private:
  struct Word {  // a pointless word, and its line for the message
    char letter = 0;
    double value = 0, lii_mm = 0;
    std::uint32_t line = 0, col = 0;
    std::string text;
    SourceText source(const std::string& name) const { return SourceText(name, text, line); }
  };
  const profile::Dialect& d_;
  std::string name_;
  bool inch_ = false;
  DecimalFinding f_;
  Word first_, largest_, tiny_;  // the first pointless word, the largest one, the first sub-micrometre one
};

}  // namespace deflex::interp
