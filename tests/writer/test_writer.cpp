#include <doctest/doctest.h>

#include <filesystem>
#include <unistd.h>

#include "../support.hpp"
#include "deflex/writer/writer.hpp"

using namespace deflex;
namespace fs = std::filesystem;

TEST_SUITE("writer") {

TEST_CASE("numbers are formatted per dialect, always with a decimal point") {
  auto fanuc = profile::load_dialect("fanuc");
  CHECK(writer::format_number(12.5, false, fanuc) == "12.5");
  CHECK(writer::format_number(12.0, false, fanuc) == "12.");
  CHECK(writer::format_number(-0.00001, false, fanuc) == "0.");
  // No digit finer than the least input increment (0.001 mm, 0.0001 in).
  CHECK(writer::format_number(0.12345, false, fanuc) == "0.123");
  CHECK(writer::format_number(0.123456, true, fanuc) == "0.1235");
  profile::Dialect fine = fanuc;
  fine.decimals_mm = 5;  // asked for more than the control reads: still 3
  CHECK(writer::format_number(0.12345, false, fine) == "0.123");
  auto heid = profile::load_dialect("heidenhain-iso");
  CHECK(writer::format_number(12.5, false, heid) == "12.500");
  profile::Dialect nolead = fanuc;
  nolead.leading_zero = false;
  CHECK(writer::format_number(0.5, false, nolead) == ".5");
  CHECK(writer::format_number(-0.5, false, nolead) == "-.5");
}

TEST_CASE("numbers deflex writes follow the program's own style: decimals, trailing and leading zeros, blanks") {
  auto fanuc = profile::load_dialect("fanuc");
  auto style_of = [](const std::string& text) {
    gcode::Program p(SourceText("t.nc", text));
    return writer::learn_style(p);
  };
  // FreeCAD's posts: fixed 3 decimals on coordinates and feeds.
  const writer::NumberStyle fixed = style_of("G0 Z27.000\nG1 X10.000 Y18.125 F800.000\nX12.500\n");
  CHECK(fixed.blanks);
  CHECK(writer::format_number(26.99, false, fanuc, &fixed, 'Z') == "26.990");
  CHECK(writer::format_number(18, false, fanuc, &fixed, 'Y') == "18.000");
  CHECK(writer::format_number(612.5, false, fanuc, &fixed, 'F') == "612.500");
  CHECK(writer::format_number(1.25, false, fanuc, &fixed, 'I') == "1.250");  // I shares the coordinates' style
  // bear.nc: no blanks, 3 decimals on axes, 1 on F.
  const writer::NumberStyle bear = style_of("G0Z20.000\nG0X0.000Y0.000S15000M3\nG1Z-17.368F6000.0\nG1X0.161\nX79.999\n");
  CHECK_FALSE(bear.blanks);
  CHECK(writer::format_number(80.01, false, fanuc, &bear, 'X') == "80.010");
  CHECK(writer::format_number(612.5, false, fanuc, &bear, 'F') == "612.5");
  // cameo.nc trims: X-75., Y12.5; the dialect's rule stays.
  const writer::NumberStyle trimmed = style_of("N1 G0 X-75. Y12.5\nN2 G1 X3.125 Z-1.\n");
  CHECK(writer::format_number(18, false, fanuc, &trimmed, 'Y') == "18.");
  CHECK(writer::format_number(12.49, false, fanuc, &trimmed, 'X') == "12.49");
  // Mixed widths with a trailing zero here and there are no fixed style.
  const writer::NumberStyle mixed = style_of("G1 X1.50 Y2.125\nX3.1 Y4.25\nX5.375 Y6.5\n");
  CHECK(writer::format_number(2.5, false, fanuc, &mixed, 'X') == "2.5");
  // Leading zero as the program writes it.
  const writer::NumberStyle bare = style_of("G1 X.5 Y-.25\n");
  CHECK(writer::format_number(0.75, false, fanuc, &bare, 'X') == ".75");
  CHECK(writer::format_number(-0.75, false, fanuc, &bare, 'Y') == "-.75");
  // The value read back is the one rounded to the dialect: only zeros differ.
  CHECK(std::stod(writer::format_number(0.12345, false, fanuc, &fixed, 'X')) == std::stod("0.123"));
  // A rewriter inserts words and blocks without blanks into such a program.
  gcode::Program p(SourceText("t.nc", "G1X1.000\nX2.000\n"));
  gcode::Block b;
  Diagnostics diags(nullptr, 0);
  p.lex(2, b, diags);
  writer::Rewriter w(p, fanuc);
  w.insert_word(b.find('X')->end, 'Y', 0.5, false);
  w.insert_block_before(2, w.format_block(1, {{'X', 1.5}, {'Y', 0.25}, {'Z', 0}}, false, "", "G1"));
  CHECK(w.str() == "G1X1.000\nG1X1.500Y0.250Z0.000\nX2.000Y0.500\n");
}

TEST_CASE("no edit: output equals input, whatever its line ends") {
  for (std::string text : {std::string("%\r\nG0 X1\r\n%\r\n"), std::string("G0 X1\nG1 X2"), std::string(""),
                           std::string("(only a comment)\n\n\n"), std::string("G0 X1\n%\ntail without newline")}) {
    gcode::Program p(SourceText("t.nc", text));
    auto d = profile::load_dialect("fanuc");
    writer::Rewriter w(p, d);
    CHECK(w.str() == text);
  }
}

TEST_CASE("a changed number is spliced into its word; everything else is copied") {
  std::string text = "N10 G1 X 10 . 0 Y5.(keep) Z-1.\r\nN20 X20.\r\n";
  gcode::Program p(SourceText("t.nc", text));
  auto d = profile::load_dialect("fanuc");
  gcode::Block b;
  Diagnostics diags(nullptr, 0);
  p.lex(1, b, diags);
  writer::Rewriter w(p, d);
  w.set_number(*b.find('X'), 10.012, false);
  w.set_number(*b.find('Z'), -1.25, false);
  w.insert_word(b.find('Z')->end, 'F', 300, false);
  // The number is replaced; the space the programmer put after the letter stays.
  CHECK(w.str() == "N10 G1 X 10.012 Y5.(keep) Z-1.25 F300.\r\nN20 X20.\r\n");
}

TEST_CASE("inserted blocks take the line end of the block before them") {
  auto d = profile::load_dialect("fanuc");
  gcode::Program p(SourceText("t.nc", "G1 X1.\r\nG1 X2."));
  writer::Rewriter w(p, d);
  w.insert_block_after(1, "G1 X1.5");
  w.insert_block_after(2, "G1 X3.");
  CHECK(w.str() == "G1 X1.\r\nG1 X1.5\r\nG1 X2.\nG1 X3.");
}

TEST_CASE("inserted blocks follow the dialect: N numbers and comment style") {
  gcode::Program p(SourceText("t.nc", "N10 G1 X1. F100.\nX2.\n"));
  auto fanuc = profile::load_dialect("fanuc");
  writer::Rewriter wf(p, fanuc);
  CHECK(wf.format_block(2, {{'X', 1.5}, {'Z', -0.25}}, false, "split (deflex)") == "X1.5 Z-0.25 (split [deflex])");
  auto heid = profile::load_dialect("heidenhain-iso");
  writer::Rewriter wh(p, heid);
  // Line 2 has no N: the nearest numbered block before it is N10.
  CHECK(wh.format_block(2, {{'X', 1.5}}, false, "split") == "N11 X1.500 ; split");
  CHECK(writer::format_comment("a", heid) == "; a");
  // The next block after N10 (line 2 has none) takes the next free number.
  CHECK(wh.format_block(1, {{'X', 2}}, false, "", "G1") == "N12 G1 X2.000");
}

TEST_CASE("inserted blocks never share an N number: the free numbers of the gap, then none or a refusal") {
  gcode::Program p(SourceText("t.nc", "N10 G1 X0. F100.\nN20 X5.\nN22 X10.\n"));
  auto heid = profile::load_dialect("heidenhain-iso");  // requires N on every block
  writer::Rewriter wh(p, heid);
  CHECK(wh.format_block(1, {{'X', 1}}, false) == "N11 X1.000");
  CHECK(wh.format_block(1, {{'X', 2}}, false) == "N12 X2.000");
  CHECK(wh.format_block(2, {{'X', 6}}, false) == "N21 X6.000");
  try {
    (void)wh.format_block(2, {{'X', 7}}, false);
    FAIL("a second block between N20 and N22 must be refused");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::input);
    CHECK(std::string(e.what()).find("t.nc:3:1: error: no free N number between N20 and N22") != std::string::npos);
  }
  profile::Dialect inc = heid;
  inc.n_policy = profile::NPolicy::increment;  // numbers where there is room, else none
  writer::Rewriter wi(p, inc);
  CHECK(wi.format_block(2, {{'X', 6}}, false) == "N21 X6.000");
  CHECK(wi.format_block(2, {{'X', 7}}, false) == "X7.000");
}

TEST_CASE("blocks inserted before a line take that line's ending") {
  auto d = profile::load_dialect("fanuc");
  gcode::Program p(SourceText("t.nc", "G1 X1.\r\nG1 X2."));
  writer::Rewriter w(p, d);
  w.insert_block_before(2, "G1 X1.5");
  w.insert_block_before(1, "G0 X0.");
  CHECK(w.str() == "G0 X0.\r\nG1 X1.\r\nG1 X1.5\r\nG1 X2.");
}

TEST_CASE("a rewritten block over the dialect's line-length limit is an error") {
  auto d = profile::load_dialect("fanuc");
  d.max_line_length = 12;
  gcode::Program p(SourceText("t.nc", "G1 X1. Y1.\n"));
  gcode::Block b;
  Diagnostics diags(nullptr, 0);
  p.lex(1, b, diags);
  writer::Rewriter w(p, d);
  w.set_number(*b.find('X'), 1.2345, false);
  CHECK_THROWS_WITH_AS(w.str(), doctest::Contains("t.nc:1:1: error: rewritten block is 13 characters"), Error);
}

TEST_CASE("atomic write: never onto the input, no file left when writing fails") {
  fs::path dir = fs::temp_directory_path() / ("deflex-writer-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string in = (dir / "in.nc").string(), out = (dir / "out.nc").string();
  test::write_file(in, "G0 X1\n");
  CHECK_THROWS_AS(writer::write_file_atomically(in, in, [](std::ostream& o) { o << "x"; }), Error);
  fs::create_symlink(in, dir / "link.nc");
  CHECK_THROWS_AS(writer::write_file_atomically((dir / "link.nc").string(), in, [](std::ostream& o) { o << "x"; }), Error);
  CHECK(test::read_file(in) == "G0 X1\n");
  CHECK_THROWS(writer::write_file_atomically(out, in, [](std::ostream& o) {
    o << "partial";
    throw Error(ErrorKind::input, "stop");
  }));
  CHECK_FALSE(fs::exists(out));
  std::size_t files = 0;
  for (auto& e : fs::directory_iterator(dir)) { (void)e; ++files; }
  CHECK(files == 2);  // in.nc and link.nc: no temporary left behind
  writer::write_file_atomically(out, in, [](std::ostream& o) { o << "done"; });
  CHECK(test::read_file(out) == "done");
  fs::remove_all(dir);
}

}  // TEST_SUITE
