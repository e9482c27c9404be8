// The decimal-point trap: a program mixing axis words with and without a
// decimal point under a dialect that counts least input increments.
#include <doctest/doctest.h>

#include <fstream>
#include <sstream>
#include <tuple>

#include "../support.hpp"
#include "deflex/interp/decimal.hpp"
#include "deflex/interp/shape.hpp"

using namespace deflex;

TEST_SUITE("interp") {

TEST_CASE("decimal points: a mixed program is named at its first pointless word with both readings") {
  const gcode::Program p(SourceText("w.nc", "G21 G90\nG0 Z3.\nG1 X76 Z-1.25 F100.\nX80.\nY4\n"));
  std::ostringstream err;
  Diagnostics d(&err, 0);
  const auto f = interp::check_decimal_points(p, profile::load_dialect("fanuc"), d, false);
  CHECK(f.with_point == 3);
  CHECK(f.without_point == 2);
  CHECK(f.lines == 2);
  CHECK(d.warnings() == 1);
  CHECK(err.str().find("w.nc:3:4: warning: X76 has no decimal point") == 0);
  CHECK(err.str().find("reads it as 0.076") != std::string::npos);
  CHECK(err.str().find("(LinuxCNC) as 76") != std::string::npos);
  Diagnostics strict(nullptr, 0);
  interp::check_decimal_points(p, profile::load_dialect("fanuc"), strict, true);
  CHECK(strict.errors() == 1);
  // Calculator input reads them as written: nothing to say.
  Diagnostics calc(nullptr, 0);
  interp::check_decimal_points(p, profile::load_dialect("linuxcnc"), calc, true);
  CHECK(calc.errors() + calc.warnings() == 0);
  // All with points, or all without (a consistent increment program), or zeros only: nothing.
  for (const char* text : {"G0 X1. Y2.\nG1 Z-1. F5.\n", "G0 X1000 Y2000\nG1 Z-1000 F5\n", "G0 X1. Y0 Z0\n"}) {
    Diagnostics q(nullptr, 0);
    interp::check_decimal_points(gcode::Program(SourceText("t.nc", text)), profile::load_dialect("fanuc"), q, true);
    CHECK(q.errors() + q.warnings() == 0);
  }
}

TEST_CASE("decimal points: a word the lexer refuses (X11O., a letter O for a zero) is the lexer's to name first") {
  const std::string text = "G21 G90 G0 X0. Y0. Z5.\nG1 X11O. Y2. F100.\nM30\n";
  const test::CliResult r = test::run_cli({"check", "-"}, text);
  CHECK(r.rc == 1);
  const std::string first = r.err.substr(0, r.err.find('\n'));
  CHECK(first.find(":2:7: error: the letter 'O' where a digit was expected") != std::string::npos);
  CHECK(r.err.find("decimal point") == std::string::npos);
}

TEST_CASE("decimal points: a pointless program that reads as micrometre hops, and sub-micrometre words") {
  auto run = [](const char* text, const profile::Dialect& d, bool strict = false) {
    std::ostringstream err;
    Diagnostics q(&err, 0);
    interp::check_decimal_points(gcode::Program(SourceText("h.nc", text)), d, q, strict);
    return std::tuple{q.warnings(), q.errors(), err.str()};
  };
  const auto fanuc = profile::load_dialect("fanuc");
  // Written for LinuxCNC without points: under fanuc the largest word, Y80, is 0.08 mm.
  const auto [w, e, msg] = run("G21 G90\nG0 X10 Y20 Z3\nG1 Z-2 F500\nX76\nY80\nM30\n", fanuc);
  CHECK(w == 1);
  CHECK(msg.find("h.nc:5:1: warning: no axis word has a decimal point and the largest, Y80, reads as 0.08 mm") == 0);
  CHECK(msg.find("(LinuxCNC) reads it as 80") != std::string::npos);
  CHECK(std::get<1>(run("G0 X10 Y20\nG1 X76 F500\n", fanuc, true)) == 1);
  // The same program in inch increments (0.0001 in): Y80 is 0.2032 mm.
  CHECK(std::get<2>(run("G20 G90\nG0 X10 Y20\nG1 X76 Y80 F5\n", fanuc)).find("reads as 0.2032 mm") !=
        std::string::npos);
  // A consistent increment program reaching past a millimetre, or any program under calculator input: nothing.
  CHECK(std::get<0>(run("G0 X1500 Y20\nG1 X76 F500\n", fanuc)) == 0);
  CHECK(std::get<0>(run("G0 X10 Y20\nG1 X76 F500\n", profile::load_dialect("linuxcnc"))) == 0);
  // A dialect counting 0.1 um increments: X5 is a 0.5 um hop.
  auto fine = fanuc;
  fine.lii_mm = 1e-4;
  const auto [w2, e2, msg2] = run("G0 X10. Y20.\nG1 X10.5 F500.\nX5\n", fine);
  CHECK(w2 == 2);  // mixed, and the hop
  CHECK(msg2.find("h.nc:3:1: warning: X5 has no decimal point and reads as 0.0005 mm") != std::string::npos);
  CHECK(msg2.find("sub-micrometre hop") != std::string::npos);
}

TEST_CASE("decimal points: --strict stops check, path and compensate on the corpus's wave.gcode") {
  const std::string wave = "tests/data/corpus/wave.gcode";
  REQUIRE(std::ifstream(wave).good());
  const auto c = test::run_cli({"check", wave});
  CHECK(c.rc == 0);
  CHECK(c.err.find("wave.gcode:5:4: warning: Z3 has no decimal point") != std::string::npos);
  CHECK(test::run_cli({"check", wave, "--strict"}).rc == 1);
  const auto p = test::run_cli({"path", wave, "--strict"});
  CHECK(p.rc == 1);
  CHECK(p.out.empty());
  CHECK(test::run_cli({"check", wave, "--strict", "--dialect", "linuxcnc"}).rc == 0);
}

TEST_CASE("program shape: empty, CR-only line ends, no program end, and cutting at 0 rpm are warnings") {
  auto warnings = [](const std::string& text) {
    std::ostringstream err;
    Diagnostics d(&err, 0);
    interp::check_program_shape(gcode::Program(SourceText("s.nc", text)), d);
    return std::pair{d.warnings(), err.str()};
  };
  CHECK(warnings("").second.find("s.nc: warning: the program is empty") == 0);
  CHECK(warnings("%\n\n%\n").first == 1);
  const auto cr = warnings("G21 G90\rG0 X1.\rM30\r");
  CHECK(cr.second.find("s.nc:1:1: warning: the line ends are CR only") == 0);
  const auto cut = warnings("G21 G90\nG0 X1.\nG1 X2. F10.\n");
  CHECK(cut.first == 1);
  CHECK(cut.second.find("s.nc:3:1: warning: no program end") == 0);
  CHECK(warnings("G21 G90\nG0 X1.\nM30\n").first == 0);
  CHECK(warnings("%\nO1\nG0 X1.\nM02\n%\n").first == 0);
  // Cutting at 0 rpm: once, at the first such motion.
  const auto r = test::interpret_text("G21 G90\nG0 X0 Y0 Z1.\nS0 M3\nG1 Z-1. F100.\nX5.\nM30\n");
  REQUIRE(r.errors == 0);
  const SourceText src("t.nc", "");
  std::ostringstream err;
  Diagnostics d(&err, 0);
  interp::SpindleCheck sc(src, d);
  for (const auto& m : r.motions) sc.motion(m);
  CHECK(d.warnings() == 1);
  CHECK(err.str().find("t.nc:4:1: warning: cutting with the spindle at 0 rpm") == 0);
}

}  // TEST_SUITE
