#include <doctest/doctest.h>

#include <sstream>

#include "deflex/diag/diagnostics.hpp"

using namespace deflex;

TEST_SUITE("diag") {

TEST_CASE("the line index: LF, CRLF, a missing final newline, an empty file") {
  SourceText s("t.nc", "G0 X1\r\nG1 X2\n\nG1 X3");
  REQUIRE(s.line_count() == 4);
  CHECK(s.line_text(1) == "G0 X1");  // CR belongs to the line end
  CHECK(s.line_text(2) == "G1 X2");
  CHECK(s.line_text(3) == "");
  CHECK(s.line_text(4) == "G1 X3");
  CHECK(s.line_end_with_eol(1) == 7);
  CHECK(s.line_end_with_eol(4) == s.bytes().size());
  CHECK(s.line_of(0) == 1);
  CHECK(s.line_of(7) == 2);
  CHECK(s.line_of(static_cast<std::uint32_t>(s.bytes().size()) - 1) == 4);
  CHECK(SourceText("e.nc", "").line_count() == 0);
  CHECK(SourceText("n.nc", "G0\n").line_count() == 1);
}

TEST_CASE("errors and warnings are counted; the error limit stops a run") {
  std::ostringstream out;
  Diagnostics d(&out, 2);
  SourceText s("t.nc", "G1 X1\n");
  d.report(Severity::warning, s, 1, 4, "w");
  CHECK(d.warnings() == 1);
  CHECK_FALSE(d.too_many());
  d.report(Severity::error, s, 1, 1, "e1");
  CHECK_FALSE(d.too_many());
  d.report(Severity::error, s, 1, 1, "e2");
  CHECK(d.too_many());
  CHECK(d.errors() == 2);
  CHECK(d.all().size() == 3);
  Diagnostics unlimited(nullptr, 0);
  for (int i = 0; i < 100; ++i) unlimited.report(Severity::error, "f", "x");
  CHECK_FALSE(unlimited.too_many());
}

TEST_CASE("the caret stands under the column, tabs kept as tabs; no location, no excerpt") {
  Diagnostic d{Severity::error, "t.nc", 1, 4, "bad", "\tX@"};
  CHECK(format(d) == "t.nc:1:4: error: bad\n  \tX@\n  \t  ^\n");
  Diagnostic n{Severity::note, "t.nc", 0, 0, "whole file", ""};
  CHECK(format(n) == "t.nc: note: whole file\n");
}

TEST_CASE("control bytes of the input never reach the terminal: shown as \\xNN, the caret still under its column") {
  const Diagnostic d{Severity::error, "a\x1b[2Jb.nc", 1, 9, "bad \x07 word", "G1 X1 \x1b[31mQ5\r"};
  const std::string f = format(d);
  for (char c : f) CHECK((c == '\n' || c == '\t' || static_cast<unsigned char>(c) >= 0x20));
  CHECK(f.find("a\\x1b[2Jb.nc:1:9: error: bad \\x07 word") == 0);
  CHECK(f.find("  G1 X1 \\x1b[31mQ5\\x0d\n") != std::string::npos);
  // Column 9 is the '3' after the escape byte at column 7: the indent of 2,
  // then 6 + 4 (the escape) + 1 columns in.
  CHECK(f.find("\n" + std::string(13, ' ') + "^\n") != std::string::npos);
}

}  // TEST_SUITE
