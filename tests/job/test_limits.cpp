// Hostile input: resource limits and integer ranges ("safe by default"),
// through job::check and job::open. Each limit is a clear error at a line and
// column (or a settings error), never a hang, a crash or an allocation that
// fails later. The command line's exit codes for them are in
// tests/cli/test_limits.cpp.
#include <doctest/doctest.h>

#include <algorithm>
#include <sstream>
#include <string>

#include "deflex/job/check.hpp"
#include "deflex/stock/build.hpp"
#include "support.hpp"

using namespace deflex;

namespace {
bool has(const std::string& s, const std::string& sub) { return s.find(sub) != std::string::npos; }

// job::check of `text` (as the file t.nc) read as Fanuc with a block
// budget, no limit on the errors: its diagnostics as written.
std::string run_budget(const std::string& text, std::uint64_t max_blocks, std::uint64_t* motions = nullptr) {
  const test::TempDir dir("limits");
  test::write_file(dir / "t.nc", text);
  job::CheckSettings cs;
  cs.program = dir / "t.nc";
  cs.read.dialect = "fanuc";
  cs.read.max_blocks = max_blocks;
  cs.read.max_errors = 0;
  test::Streams st;
  const job::CheckResult r = job::check(cs, st.io);
  if (motions) *motions = r.stats.motions;
  return st.err.str();
}

// Three nested subprograms of 9999 repeats each: 2e12 motions if nothing stops them.
const char* kExplosion =
    "G21 G90 G0 X0 Y0 Z0\nM98 P1 L9999\nM30\n"
    "O1\nM98 P2 L9999\nM99\nO2\nM98 P3 L9999\nM99\nO3\nG1 X1. F100\nG1 X0\nM99\n";
}  // namespace

TEST_SUITE("job") {

TEST_CASE("limits: nested subprogram repeats stop at the block budget") {
  std::uint64_t motions = 0;
  // 9999^3 repeats: the budget, not the time it would take, ends it.
  const std::string err = run_budget(kExplosion, 1000, &motions);
  // (The setting is named by the front end: the command line's in tests/cli/test_limits.cpp.)
  CHECK(has(err, "error: more than 1000 blocks executed (subprogram and canned-cycle repeats); "));
  CHECK(has(err, " raises the limit"));
  CHECK(motions <= 1000);
  // Within the budget the same program shape runs to the end (the spindle
  // on: job::check warns of a cut without it).
  CHECK(run_budget("G21 G90 G0 X0 Y0 Z0 S1000 M3\nM98 P1 L3\nM30\nO1\nG1 X1. F100\nM99\n", 1000).empty());
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
  const test::TempDir dir("limits");
  const std::string f = dir / "d.yaml";
  test::write_file(f, "name: x\ndecimal_point_rule: calculator\ndecimals_mm: 1.0e300\n");
  try {
    profile::load_dialect(f);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::config);
    CHECK(has(e.what(), ":3:14: error: decimals_mm must be in [0, 9]"));
  }
  // Fuzz finding (fuzz_machine): a dialect without `name` was an internal
  // error (no deflex::Error: the command line's exit 70).
  test::write_file(f, "comment_style: paren\n");
  job::CheckSettings cs;
  cs.program = "tests/golden/wall.nc";
  cs.read.dialect = f;
  test::Streams st;
  try {
    (void)job::check(cs, st.io);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::config);
    CHECK(has(e.what(), "error: missing key 'name'"));
  }
}

TEST_CASE("limits: a stock box too large for a Z-map is refused by job::open before anything is built") {
  job::Settings s;
  s.program = "tests/golden/wall.nc";
  s.stock = "box:0,0,-20,1e7,1e7,0";
  test::Streams st;
  try {
    (void)job::open(s, job::Purpose::compensate, st.io);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::settings);
    CHECK(has(e.what(), "more than the limit"));
  }
}

}  // TEST_SUITE
