// job::rough: a roughing program generated from a finishing program, swept
// as an earlier operation (Settings::stock_from) before it. The plan itself
// is checked in tests/plan; here the call: its checks, what it writes, and
// what the finishing program meets afterwards. What `deflex rough` prints is
// in tests/cli/test_rough.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "deflex/job/check.hpp"
#include "deflex/job/stock.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

const std::string kFinish = "tests/engage/data/ball_finish.nc", kBox = "box:0,0,-10,40,30,0";

// One level of T3 on the box, `stepover_mm` between the lines.
job::RoughSettings one_level(double stepover_mm) {
  job::RoughSettings s;
  s.finish_program = kFinish;
  s.stock = kBox;
  s.rough_tool = "T3";
  s.stepdown_mm = 0;
  s.stepover_mm = stepover_mm;
  return s;
}

// The largest material removal rate (mm^3/s) of the points strictly inside
// the box along X. Not a_p: a thin layer over the whole groove engages the
// ball over the groove's full depth as well.
struct LargestMrr : job::Observer {
  double mm3_per_s = 0;
  bool wants_rows() const override { return true; }
  void row(const report::PointRow& r) override {
    if (r.tip_mm.x() > 10 && r.tip_mm.x() < 30) mm3_per_s = std::max(mm3_per_s, r.mrr_mm3_per_s);
  }
};

// The finish simulated on the box, after the earlier programs `before`.
double finish_mrr(const std::vector<job::EarlierOp>& before) {
  job::Settings s;
  s.program = kFinish;
  s.stock = kBox;
  s.material.material = "Al7075-T6";
  s.stock_from = before;
  test::Streams st;
  LargestMrr m;
  job::Run run = job::open(s, job::Purpose::simulate, st.io);
  (void)job::simulate(run, st.io, &m);
  return m.mm3_per_s;
}

// job::rough of `s`: the Error's kind and message (and that nothing was written).
std::pair<ErrorKind, std::string> refused(const job::RoughSettings& s) {
  test::Streams st;
  try {
    (void)job::rough(s, st.out, st.io);
  } catch (const Error& e) {
    CHECK(st.out.str().empty());
    return {e.kind(), e.what()};
  }
  FAIL("job::rough accepted it");
  return {};
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("rough: a roughing program before the ball finish; the finish then meets less than the box") {
    test::TempDir dir("rough");
    // A ball D6 follows the D10 groove 0.3 mm off, lines 1 mm apart, one level.
    job::RoughSettings s = one_level(1);
    s.plan.allowance_mm = 0.3;
    s.output = dir / "rough.nc";
    test::Streams st;
    const job::RoughResult r = job::rough(s, st.out, st.io);
    CHECK(r.name == s.output);
    CHECK(st.out.str().empty());  // into the file
    REQUIRE(r.plan.levels_mm.size() == 1);
    CHECK(std::fabs(r.plan.top_mm) < 0.0005);  // from Z0.000
    CHECK(r.plan.line_y_mm.size() == 31);
    CHECK(std::fabs(r.line_spacing_mm - 1) < 0.0005);
    CHECK(r.moves > 0);
    // The program reads back clean, like any program.
    job::CheckSettings cs;
    cs.program = s.output;
    test::Streams cst;
    CHECK(job::check(cs, cst.io).errors == 0);
    // To the output stream when no output file, the same bytes.
    job::RoughSettings to_stream = s;
    to_stream.output.clear();
    test::Streams ost;
    (void)job::rough(to_stream, ost.out, ost.io);
    CHECK(ost.out.str() == test::read_file(s.output));
    // The ball D10 at Z-3 in the box removes the groove's whole section (a
    // segment of 3 mm of a circle R5: 19.0 mm^2) at 20 mm/s; after the rough
    // a layer of about 0.3 mm over an arc of 11.6 mm (3.5 mm^2), plus scallops.
    const double on_box = finish_mrr({}), on_rough = finish_mrr({{s.output, ""}});
    const double segment = 25 * std::acos(2.0 / 5) - 2 * std::sqrt(25.0 - 4);
    CHECK(on_box == deflex::test::within(segment * 20, 0.02));
    CHECK(on_rough < 0.3 * on_box);
    CHECK(on_rough > 0.15 * on_box);
  }

  TEST_CASE("rough: the header names the spacing the lines have, the stepover spread evenly") {
    // 30 mm of stock at a stepover of at most 4 mm: 8 gaps of 3.75 mm.
    test::Streams st;
    const job::RoughResult r = job::rough(one_level(4), st.out, st.io);
    CHECK(r.plan.line_y_mm.size() == 9);
    CHECK(std::fabs(r.line_spacing_mm - 3.75) < 0.0005);
    const std::string out = st.out.str();
    CHECK(out.find("ALONG X, ONE LEVEL, LINES 3.750 MM APART - THE STEPOVER 4.000 SPREAD EVENLY OVER THE STOCK") !=
          std::string::npos);
    CHECK(out.find("STEPOVER 4.000 MM") == std::string::npos);
  }

  TEST_CASE("rough: refused before anything is computed") {
    auto with = [](auto edit) {
      job::RoughSettings s;
      s.finish_program = kFinish;
      s.stock = kBox;
      s.rough_tool = "T1";
      edit(s);
      return refused(s);
    };
    auto says = [](const std::pair<ErrorKind, std::string>& r, const std::string& what) {
      CAPTURE(r.second);
      CHECK(r.first == ErrorKind::settings);
      CHECK(r.second.find(what) != std::string::npos);
    };
    says(with([](job::RoughSettings& s) { s.finish_program = "-"; }), "must be a file, not standard input");
    says(with([](job::RoughSettings& s) { s.rough_tool = "T99"; }), "T99");
    says(with([](job::RoughSettings& s) { s.stepover_mm = 11; }), "the stepover must be");
    says(with([](job::RoughSettings& s) {
           s.stepover_mm = 0.0001;
           s.plan.sample_mm = 0.01;
         }),
         "floor samples");
    // Never over the input.
    const std::string finish = test::read_file(kFinish);
    CHECK(with([](job::RoughSettings& s) { s.output = kFinish; }).first == ErrorKind::settings);
    CHECK(test::read_file(kFinish) == finish);
    // The allowance above the stock top: nothing to rough.
    says(with([](job::RoughSettings& s) { s.plan.allowance_mm = 5; }), "nothing to rough");
  }
}
