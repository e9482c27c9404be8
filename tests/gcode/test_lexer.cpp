#include <doctest/doctest.h>

#include <memory>
#include <sstream>

#include "deflex/gcode/program.hpp"

using namespace deflex;
using namespace deflex::gcode;

namespace {
struct Lexed {
  Block b;
  bool ok;
  std::string diags;
};
Lexed lex1(const std::string& text, std::uint32_t line = 1) {
  static std::unique_ptr<Program> keep;
  keep = std::make_unique<Program>(SourceText("t.nc", text));
  std::ostringstream err;
  Diagnostics d(&err, 0);
  Lexed r;
  r.ok = keep->lex(line, r.b, d);
  r.diags = err.str();
  return r;
}
std::string text_of(const std::string& src, std::uint32_t b, std::uint32_t e) { return src.substr(b, e - b); }
}  // namespace

TEST_SUITE("gcode") {

TEST_CASE("words know their letter, value and byte range") {
  std::string src = "N10 G01 X-12.5 Y.25 Z3\n";
  Lexed l = lex1(src);
  REQUIRE(l.ok);
  REQUIRE(l.b.words.size() == 5);
  CHECK(l.b.words[2].letter == 'X');
  CHECK(l.b.words[2].value == -12.5);
  CHECK(l.b.words[2].has_point);
  CHECK(text_of(src, l.b.words[2].begin, l.b.words[2].end) == "X-12.5");
  CHECK(text_of(src, l.b.words[2].num_begin, l.b.words[2].end) == "-12.5");
  CHECK(l.b.words[3].value == 0.25);
  CHECK_FALSE(l.b.words[4].has_point);
  CHECK(l.b.words[1].code10() == 10);
}

TEST_CASE("no-space style, lower case and spaces inside words") {
  Lexed a = lex1("G1Z-17.368F6000.0");
  REQUIRE(a.b.words.size() == 3);
  CHECK(a.b.words[1].value == -17.368);
  CHECK(a.b.words[2].value == 6000.0);
  Lexed b = lex1("g 0 1 x - 1 2 . 5 y3");
  REQUIRE(b.ok);
  REQUIRE(b.b.words.size() == 3);
  CHECK(b.b.words[0].letter == 'G');
  CHECK(b.b.words[0].code10() == 10);
  CHECK(b.b.words[1].letter == 'X');
  CHECK(b.b.words[1].value == -12.5);
}

TEST_CASE("comments in parentheses and after a semicolon keep their ranges") {
  std::string src = "G0 (rapid) X1 ; to the start\r\n";
  Lexed l = lex1(src);
  REQUIRE(l.b.comments.size() == 2);
  CHECK(text_of(src, l.b.comments[0].begin, l.b.comments[0].end) == "(rapid)");
  CHECK(text_of(src, l.b.comments[1].begin, l.b.comments[1].end) == "; to the start");
  CHECK(l.b.text_end == src.size() - 2);  // CRLF is the line end, not text
  CHECK(l.b.end == src.size());
}

TEST_CASE("G54.1 and other decimal codes") {
  Lexed l = lex1("G54.1 P3");
  CHECK(l.b.words[0].code10() == 541);
  Lexed m = lex1("G54.15");
  CHECK(m.b.words[0].code10() == -1);
}

TEST_CASE("block delete, program number, percent") {
  CHECK(lex1("/G1 X1").b.block_delete);
  CHECK(lex1("/2 G1 X1").b.block_delete_level == 2);
  Lexed o = lex1("O1234 (MAIN)");
  CHECK(o.b.kind == LineKind::program_number);
  CHECK(o.b.program_number == 1234);
  Lexed c = lex1(":0042");
  CHECK(c.b.kind == LineKind::program_number);
  CHECK(c.b.program_number == 42);
  CHECK(lex1("%").b.kind == LineKind::percent);
}

TEST_CASE("text after the closing percent is ignored but kept") {
  Program p(SourceText("t.nc", "%\nG0 X1\n%\ngarbage ### here\n"));
  CHECK(p.closing_percent_line() == 3);
  Block b;
  Diagnostics d(nullptr, 0);
  CHECK(p.lex(4, b, d));
  CHECK(b.kind == LineKind::ignored);
  CHECK(d.errors() == 0);
}

TEST_CASE("a missing final newline and CRLF are line ends, not text") {
  Program p(SourceText("t.nc", "G0 X1\r\nG1 X2"));
  CHECK(p.line_count() == 2);
  Block b;
  Diagnostics d(nullptr, 0);
  p.lex(2, b, d);
  CHECK(b.words.size() == 2);
  CHECK(b.end == 12);
}

TEST_CASE("macro B is recognised, never parsed as words") {
  CHECK(lex1("#100=5.").b.macro);
  CHECK(lex1("G1 X#100").b.macro);
  CHECK(lex1("IF [#1 GT 2] GOTO 10").b.macro);
  CHECK(lex1("WHILE [#1 LT 3] DO1").b.macro);
  CHECK(lex1("END1").b.macro);
  CHECK(lex1("N10 GOTO 20").b.macro);
  CHECK(lex1("o100 sub").b.macro);  // LinuxCNC O-words
  CHECK_FALSE(lex1("G1 X1").b.macro);
}

TEST_CASE("letters that form no word are named as such, not as macro B") {
  // FreeCAD's Fanuc post starts with the file name: no G-code at all.
  Lexed h = lex1("profile.nc (Exported by FreeCAD)");
  CHECK_FALSE(h.ok);
  CHECK_FALSE(h.b.macro);
  CHECK(h.diags.find("t.nc:1:1: error: letters that form no word: 'p' is not followed by a number ('profile.nc')") == 0);
  Lexed x = lex1("G1 XY1.");
  CHECK_FALSE(x.b.macro);
  CHECK(x.diags.find("t.nc:1:4: error: letters that form no word: 'X'") == 0);
  // A letter with a space and then a letter is an address without a number.
  CHECK(lex1("G1 X Y1.").diags.find("t.nc:1:4: error: address 'X' has no number") == 0);
}

TEST_CASE("a letter O where a digit was expected is named at the O") {
  Lexed o = lex1("G1 X11O. Y2.");
  CHECK_FALSE(o.ok);
  CHECK(o.diags.find("t.nc:1:7: error: the letter 'O' where a digit was expected") == 0);
  CHECK(lex1("O1000 (a program number)").ok);
}

TEST_CASE("lexical errors name the column") {
  Lexed a = lex1("G1 X1 (no end");
  CHECK_FALSE(a.ok);
  CHECK(a.diags.find("t.nc:1:7: error: comment not closed") != std::string::npos);
  Lexed b = lex1("G1 X1 $");
  CHECK(b.diags.find("t.nc:1:7: error: unexpected character '$'") != std::string::npos);
  Lexed c = lex1("G1 X");
  CHECK(c.diags.find("t.nc:1:4: error: address 'X' has no number") != std::string::npos);
  Lexed d = lex1("G1 (a (b) c)");
  CHECK(d.diags.find("nested '('") != std::string::npos);
}

TEST_CASE("diagnostic format: file:line:col, source line, caret") {
  Lexed a = lex1("G1 X1 $");
  CHECK(a.diags == "t.nc:1:7: error: unexpected character '$'\n  G1 X1 $\n        ^\n");
}

}  // TEST_SUITE
