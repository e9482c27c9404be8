// Hostile input: resource limits and integer ranges ("safe by default"). Each
// limit is a clear error at a line and column (or a usage error), never a hang,
// a crash or an allocation that fails later.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <unistd.h>
#include <sstream>
#include <string>

#include "../support.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;

namespace {
bool has(const std::string& s, const std::string& sub) { return s.find(sub) != std::string::npos; }

struct Null : interp::MotionSink {
  std::uint64_t n = 0;
  void motion(const interp::Motion&) override { ++n; }
};

// Interprets `text` with a block budget; returns the diagnostics as printed.
std::string run_budget(const std::string& text, std::uint64_t max_blocks, std::uint64_t* motions = nullptr) {
  gcode::Program prog(SourceText("t.nc", text));
  std::ostringstream err;
  Diagnostics d(&err, 0);
  interp::Options o;
  o.dialect = profile::load_dialect("fanuc");
  o.max_blocks = max_blocks;
  Null sink;
  interp::interpret(prog, o, d, sink);
  if (motions) *motions = sink.n;
  return err.str();
}

// Three nested subprograms of 9999 repeats each: 2e12 motions if nothing stops them.
const char* kExplosion =
    "G21 G90 G0 X0 Y0 Z0\nM98 P1 L9999\nM30\n"
    "O1\nM98 P2 L9999\nM99\nO2\nM98 P3 L9999\nM99\nO3\nG1 X1. F100\nG1 X0\nM99\n";
}  // namespace

TEST_SUITE("cli") {

TEST_CASE("limits: nested subprogram repeats stop at the block budget") {
  std::uint64_t motions = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const std::string err = run_budget(kExplosion, 1000, &motions);
  CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(5));
  CHECK(has(err, "error: more than 1000 blocks executed (subprogram and canned-cycle repeats); "
                 "max_blocks raises the limit"));  // the library's keyword: no Io names it as a flag here
  CHECK(motions <= 1000);
  // Within the budget the same program shape runs to the end.
  CHECK(run_budget("G21 G90 G0 X0 Y0 Z0\nM98 P1 L3\nM30\nO1\nG1 X1. F100\nM99\n", 1000).empty());
}

TEST_CASE("limits: canned-cycle repeats count motions against the budget") {
  // 9999 holes of 4 motions each.
  const std::string err = run_budget("G21 G90 G0 X0 Y0 Z10.\nG91 G81 X1. Z-1. R-8. K9999 F100\n", 500);
  CHECK(has(err, "t.nc:2:1: error: more than 500 motions"));
  CHECK(has(run_budget("G21 G90 G0 X0 Y0 Z10.\nG83 X1. Z-100. R2. Q0.001 F100\n", 1000), "2:20: error: peck depth Q gives more than 1000 pecks"));
}

TEST_CASE("limits: a line longer than 64 KiB is an error at its column, echoed in part") {
  const std::string text = "G21 G0 X0\nG1 X1. F100 (" + std::string(10'000'000, 'a') + ")\n";
  const std::string err = run_budget(text, 1000);
  CHECK(has(err, "t.nc:2:65537: error: line longer than 65536 bytes"));
  CHECK(err.size() < 2000);  // the 10 MB line is not echoed
  CHECK(has(err, "...aaa"));
}

TEST_CASE("limits: numbers that name integers are range-checked before conversion") {
  CHECK(has(run_budget("G21 G2199999999\n", 100), "1:5: error: G2199999999 is not a G code"));
  CHECK(has(run_budget("G21 M3870000000\n", 100), "1:5: error: M3870000000 is not an M code"));
  CHECK(has(run_budget("G21 G43 H6000000000\n", 100), "1:9: error: offset register H out of range: must be a whole number"));
  CHECK(has(run_budget("G21 G43 H-1\n", 100), "1:9: error: offset register H out of range: must be a whole number"));
  CHECK(has(run_budget("G21 G90 G0 X0 Y0 Z0\nG54.1 P1000\n", 100), "2:7: error: extended work offset P out of range"));
  CHECK(has(run_budget("G21 G90 G0 X0 Y0 Z0\nG30 P99999999999\n", 100), "2:5: error: G30 P out of range: must be a whole number from 2 to 4"));
  CHECK(has(run_budget("G21 G90 G0 X0 Y0 Z0\nM98 P1 L1.5\nM30\nO1\nM99\n", 100), "2:8: error: subprogram repeat count L"));
  // Fanuc's P rrrr nnnn with too many repeat digits (would wrap to a negative count).
  CHECK(has(run_budget("G21 G90 G0 X0 Y0 Z0\nM98 P429496729510010\nM30\nO10\nM99\n", 100),
            "2:5: error: subprogram repeat count over 9999"));
  // Ordinary codes are untouched.
  CHECK(run_budget("G21 G90 G0 X0 Y0 Z0 T12 M6\nG43 H12 Z5.\nM3 S1000\nM30\n", 100).empty());
}

TEST_CASE("limits: a stock box too large for a Z-map is a usage error before allocating") {
  try {
    stock::make_stock("box:0,0,-10,1e6,1e6,0");
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::settings);
    CHECK(has(e.what(), "cells, more than the limit"));
  }
  CHECK_THROWS_AS(stock::grid_covering(0, 0, 1e300, 1e300, 0.05), Error);
  CHECK(stock::zmap_from_box(stock::parse_box("box:0,0,-10,100,100,0")).grid().nx == 2000);
}

TEST_CASE("limits: integers in YAML are range-checked before conversion") {
  const std::string f = (std::filesystem::temp_directory_path() / ("deflex-limits-" + std::to_string(::getpid()) + ".yaml")).string();
  test::write_file(f, "name: x\ndecimal_point_rule: calculator\ndecimals_mm: 1.0e300\n");
  try {
    profile::load_dialect(f);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::config);
    CHECK(has(e.what(), ":3:14: error: decimals_mm must be in [0, 9]"));
  }
  // Fuzz finding (fuzz_machine): a dialect without `name` was an internal error (exit 70).
  test::write_file(f, "comment_style: paren\n");
  auto r = test::run_cli({"check", "tests/golden/wall.nc", "--dialect", f});
  CHECK(r.rc == 3);
  CHECK(has(r.err, "error: missing key 'name'"));
  std::remove(f.c_str());
}

TEST_CASE("limits: the CLI reports them with exit codes (--max-blocks, stock)") {
  const std::string f = (std::filesystem::temp_directory_path() / ("deflex-limits-" + std::to_string(::getpid()) + ".nc")).string();
  test::write_file(f, kExplosion);
  auto r = test::run_cli({"path", f, "--max-blocks", "2000"});
  CHECK(r.rc == 1);
  CHECK(has(r.err, "error: more than 2000 blocks executed"));
  CHECK(r.out.empty());  // no path cut off at the budget
  // The same nesting with 20 repeats a level runs within the budget and prints every motion.
  test::write_file(f, "G21 G90 G0 X0 Y0 Z0\nM98 P1 L20\nM30\nO1\nM98 P2 L20\nM99\nO2\nG1 X1. F100\nG1 X0\nM99\n");
  const auto ok = test::run_cli({"path", f, "--max-blocks", "2000"});
  CHECK(ok.rc == 0);
  CHECK(std::count(ok.out.begin(), ok.out.end(), '\n') == 1 + 20 * 20 * 2);
  CHECK(test::run_cli({"check", f, "--max-blocks", "0"}).rc == 2);
  std::remove(f.c_str());
  auto s = test::run_cli({"compensate", "tests/golden/wall.nc", "--stock", "box:0,0,-20,1e7,1e7,0"});
  CHECK(s.rc == 2);
  CHECK(has(s.err, "more than the limit"));
}

}  // TEST_SUITE
