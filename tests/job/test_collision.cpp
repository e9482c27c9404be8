// The holder and shank check as errors, through the job API: a finishing pass
// on the floor of a pocket 55.5 mm deep under a stick-out of 40 mm is an
// error at the plunge's line with the depth by hand (the walls stand to Z0,
// the holder's face at Z-55 + 40: 15 mm) and nothing is written; the same
// pass at a stick-out of 60 mm is clean; the pocket is the rest stock of an
// earlier program (Settings::stock_from), and without it the shank is buried
// in solid stock; check --stock finds the same line and depth by the sweep
// alone; the same at one thread and at two, and in pieces.
#include <doctest/doctest.h>

#include <filesystem>

#include "deflex/job/check.hpp"
#include "support.hpp"

using namespace deflex;

namespace {

// The pocket of tests/support.hpp's pocket_roughing() in the box, and its floor
// pass under T1 (stick-out 40 mm: short.nc) and T2 (60 mm: long.nc).
struct Pocket : test::TempDir {
  Pocket() : TempDir("job-collision") {
    test::write_file(*this / "tools.yaml", test::kPocketTools);
    test::write_file(*this / "rough.nc", test::pocket_roughing());
    test::write_file(*this / "short.nc", test::pocket_floor_pass(1));
    test::write_file(*this / "long.nc", test::pocket_floor_pass(2));
  }
  job::Settings settings(const std::string& program, bool rest_stock) const {
    job::Settings s;
    s.program = *this / program;
    s.tool_file = *this / "tools.yaml";
    s.material.material = "Al6082-T4";
    s.stock = "box:0,0,-80,100,100,0";
    if (rest_stock) s.stock_from.push_back({*this / "rough.nc", ""});
    s.output = *this / "out.nc";
    return s;
  }
  job::CheckResult check(const std::string& program, bool rest_stock, std::string& err, int threads = 0) const {
    job::CheckSettings cs;
    cs.threads = threads;
    cs.program = *this / program;
    cs.tool_file = *this / "tools.yaml";
    cs.stock = "box:0,0,-80,100,100,0";
    if (rest_stock) cs.stock_from.push_back({*this / "rough.nc", ""});
    test::Streams st;
    const job::CheckResult r = job::check(cs, st.io);
    err = st.err.str();
    return r;
  }
};

// The first line of `err` holding `what`, or "".
std::string line_with(const std::string& err, const std::string& what) {
  const std::size_t k = err.find(what);
  if (k == std::string::npos) return "";
  const std::size_t a = err.rfind('\n', k), b = err.find('\n', k);
  return err.substr(a == std::string::npos ? 0 : a + 1, b == std::string::npos ? std::string::npos : b - a - 1);
}

}  // namespace

TEST_SUITE("job") {

TEST_CASE("collision: the holder in a pocket deeper than the stick-out is an error at its line, nothing written") {
  const Pocket d;
  const auto o = test::compensate_job(d.settings("short.nc", true));
  REQUIRE_FALSE(o.ok());
  CHECK(o.error == ErrorKind::input);
  CHECK(o.what.find("the tool assembly runs into the stock; nothing compensated, nothing written") != std::string::npos);
  const std::string e = line_with(o.err, "[holder_collision]");
  // stock top 0 - (tip -55 + stick-out 40) = 15 mm, from the plunge on; 55 mm clears it.
  CHECK(e.starts_with(d / "short.nc" + ":5:1: error: the holder of T1 runs 15.00 mm into the material at its stick-out of 40.0 mm"));
  CHECK(e.find("on 2 lines") != std::string::npos);
  CHECK(e.find("a stick-out of at least 55.0 mm keeps the holder clear") != std::string::npos);
  CHECK(o.err.find("G1 Z-55. F300") != std::string::npos);  // the source line under it
  CHECK(o.err.find("shank_collision") == std::string::npos);  // the shank stays inside the pocket
  CHECK_FALSE(std::filesystem::exists(d / "out.nc"));
  // simulate stops on it too, and writes no report.
  job::Settings s = d.settings("short.nc", true);
  s.output.clear();
  s.report_dir = d / "report";
  const auto sim = test::simulate_job(s);
  REQUIRE_FALSE(sim.ok());
  CHECK(sim.error == ErrorKind::input);
  CHECK(line_with(sim.err, "[holder_collision]") == e);
  CHECK_FALSE(std::filesystem::exists(d / "report/summary.json"));
  CHECK_FALSE(std::filesystem::exists(d / "report/points.csv"));
}

TEST_CASE("collision: the same pocket with a longer stick-out is clean") {
  const Pocket d;
  const auto o = test::compensate_job(d.settings("long.nc", true));
  REQUIRE(o.ok());
  CHECK(o.err.find("collision") == std::string::npos);
  CHECK(std::filesystem::exists(d / "out.nc"));
  std::string err;
  const job::CheckResult r = d.check("long.nc", true, err);
  CHECK(r.errors == 0);
  CHECK(err.find("collision") == std::string::npos);
}

TEST_CASE("collision: the earlier program's rest stock is honoured") {
  // Without the roughing the pass plunges into solid stock: the plunge's
  // shank follows into the bore its flutes cut (line 5 is clean), and the
  // cut along X drives it (from the flutes' top, 20 mm above the tip) into
  // the material the flutes never reached: 0 - (-55 + 20) = 35 mm deep.
  const Pocket d;
  const auto solid = test::compensate_job(d.settings("long.nc", false));
  REQUIRE_FALSE(solid.ok());
  const std::string e = line_with(solid.err, "[shank_collision]");
  CHECK(e.starts_with(d / "long.nc" + ":6:1: error: the shank of T2 (diameter 10.00 mm from 20.0 mm above the tip) runs 35.00 mm"));
  CHECK(e.find("reach 55.0 mm above the tip") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(d / "out.nc"));
  std::string err;
  const job::CheckResult r = d.check("long.nc", false, err);
  CHECK(r.errors == 1);
  CHECK(line_with(err, "[shank_collision]") == e);
}

TEST_CASE("collision: check --stock gives compensate's line and depth, at one thread and at two") {
  const Pocket d;
  std::string first;
  for (int threads : {1, 2}) {
    CAPTURE(threads);
    job::Settings s = d.settings("short.nc", true);
    s.threads = threads;
    const auto o = test::compensate_job(s);
    REQUIRE_FALSE(o.ok());
    const std::string e = line_with(o.err, "[holder_collision]");
    REQUIRE_FALSE(e.empty());
    if (first.empty()) first = e;
    CHECK(e == first);
  }
  for (int threads : {1, 2}) {
    CAPTURE(threads);
    std::string err;
    const job::CheckResult r = d.check("short.nc", true, err, threads);
    CHECK(r.errors == 1);
    CHECK(line_with(err, "[holder_collision]") == first);
    CHECK(err.find("G1 Z-55. F300") != std::string::npos);
  }
}

TEST_CASE("collision: a program read in pieces gives the whole program's error, in compensate and check --stock") {
  const Pocket d;
  const auto whole = test::compensate_job(d.settings("short.nc", true));
  std::string whole_check;
  (void)d.check("short.nc", true, whole_check);
  const test::PieceLines two("2");
  const auto pieces = test::compensate_job(d.settings("short.nc", true));
  REQUIRE_FALSE(pieces.ok());
  CHECK(pieces.err == whole.err);
  CHECK(pieces.what == whole.what);
  CHECK_FALSE(std::filesystem::exists(d / "out.nc"));  // refused inside the write
  std::string err;
  CHECK(d.check("short.nc", true, err).errors == 1);
  CHECK(err == whole_check);
}

}  // TEST_SUITE
