// Runs that pass every range check but mean nothing: a stock no cutting move
// reaches, a tolerance that moves nothing, a gain that over-corrects. Each is
// said by job::open() before the simulation (an error under strict), never a
// silent "0 points outside". The settings' own spelling (a flag or a job
// key) is left out of what is asserted: the command line names its options.
#include <doctest/doctest.h>

#include <optional>
#include <string>

#include "support.hpp"

using namespace deflex;

namespace {

// bear.nc's first 14 lines: a D10 flat end slotting 80 mm along X at Z-17.368.
const std::string kSlot =
    "T1M6\nG21\nG17\nG0Z20.000\nG0X0.000Y0.000S15000M3\nG0X0.001Y0.001Z10.000\nG1Z-17.368F6000.0\n"
    "G1X0.161\nX79.999\nY0.126\nY0.501\nX79.839\nX0.001\nY0.626\nM30\n";

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// The slot from the input stream on `stock`, one thread.
job::Settings slot_on(const std::string& stock) {
  job::Settings s;
  s.program = "-";
  s.stock = stock;
  s.threads = 1;
  return s;
}

// job::open() of `s` on the slot: the Error's kind, or nullopt when it opens.
std::optional<ErrorKind> open_fails(const job::Settings& s, test::Streams& st) {
  try {
    (void)job::open(s, job::Purpose::compensate, st.io);
  } catch (const Error& e) {
    return e.kind();
  }
  return std::nullopt;
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("a stock no cutting move reaches is said, with both extents, before anything is simulated") {
    for (const char* stock : {"box:500,500,-10,600,600,0",  // another part's blank
                              "box:0,0,-30,80,80,-20"}) {    // below every cut
      INFO(stock);
      const auto r = test::compensate_job(slot_on(stock), kSlot);
      REQUIRE(r.ok());
      CHECK(has(r.err, "warning: no cutting move reaches the stock: the cutting moves' tips span X 0.001..79.999 "
                       "Y 0.001..0.626 Z -17.368..10.000 mm (tools up to R 5.000 mm)"));
      CHECK(r.out == kSlot);  // nothing to move: the program as written
      // Strict: an input error from open() itself, before any simulation, nothing written.
      job::Settings strict = slot_on(stock);
      strict.read.strict = true;
      test::Streams st(kSlot);
      CHECK(open_fails(strict, st) == ErrorKind::input);
      CHECK(st.out.str().empty());
      CHECK(has(st.err.str(), "error: no cutting move reaches the stock"));
    }
    // A stock the plunge alone removes (an 80 mm part's blank typed in inch):
    // the moves reach it, but no point is in material after the plunge.
    const auto r = test::simulate_job(slot_on("box:0,0,-25,3.15,3.15,0"), kSlot);
    REQUIRE(r.ok());
    CHECK(has(r.err, "none of the 380 cutting points is in the stock"));
    CHECK(has(r.err, "[no_material]"));
    // The stock the program cuts: neither.
    const auto ok = test::simulate_job(slot_on("box:0,0,-25,80,80,0"), kSlot);
    REQUIRE(ok.ok());
    CHECK_FALSE(has(ok.err, "reaches the stock"));
    CHECK_FALSE(has(ok.err, "[no_material]"));
  }

  TEST_CASE("a tolerance at or over the offset cap and a gain over 1 are warned (settings errors when strict)") {
    const job::Settings base = slot_on("box:0,0,-25,80,80,0");
    job::Settings loose = base;
    loose.tolerance_mm = 1000;
    const auto t = test::compensate_job(loose, kSlot);
    REQUIRE(t.ok());
    CHECK(has(t.err, "warning: the tolerance 1000 mm"));
    CHECK(has(t.err, "is not below the offset cap max_offset_mm = 0.1 mm"));
    CHECK(t.out == kSlot);  // indeed nothing moved
    job::Settings over = base;
    over.gain = 2;
    const auto g = test::compensate_job(over, kSlot);
    REQUIRE(g.ok());
    CHECK(has(g.err, "over-corrects: at the mirror's fixed point the surface error becomes -1 times"));
    job::Settings at_cap = base;
    at_cap.tolerance_mm = 0.1;
    for (job::Settings strict : {over, at_cap}) {
      strict.read.strict = true;
      test::Streams st(kSlot);
      CHECK(open_fails(strict, st) == ErrorKind::settings);
    }
    // What is usual says nothing.
    job::Settings usual = base;
    usual.tolerance_mm = 0.01;
    usual.gain = 0.8;
    const auto ok = test::compensate_job(usual, kSlot);
    REQUIRE(ok.ok());
    CHECK_FALSE(has(ok.err, "the tolerance"));
    CHECK_FALSE(has(ok.err, "over-corrects"));
  }

  TEST_CASE("a run names what it used, in its text and in the summary") {
    const auto r = test::simulate_job(slot_on("box:0,0,-25,80,80,0"), kSlot);
    REQUIRE(r.ok());
    CHECK(r.result->used.text ==
          "used: machine mill3 (samples/machines/mill3.yaml, dialect fanuc); T1: flat D10 mm (samples/tools.yaml); "
          "material C35 (samples/materials.yaml); config config.yaml");
    const report::Json& js = r.result->summary.at("used");
    CHECK(js.at("machine") == "mill3");
    CHECK(js.at("dialect") == "fanuc");
    CHECK(js.at("tools") == report::Json::array({"T1: flat D10 mm"}));
    CHECK(js.at("material") == "C35 (samples/materials.yaml)");
    // T7's flutes are 15 mm long: 12.4 mm into a box with its top at Z-5.
    job::Settings t7 = slot_on("box:0,0,-25,80,80,-5");
    t7.tool = "T7";
    const auto c = test::compensate_job(t7, kSlot);
    REQUIRE(c.ok());
    CHECK(has(c.result->used.text, "; T7: ball D10 mm (samples/tools.yaml);"));
  }

  TEST_CASE("stock auto[:MARGIN] is the blank round the cutting moves and the tool, and says so") {
    // Tips X 0.001..79.999, Y 0.001..0.626, Z -17.368..10 (the plunge starts at
    // Z10); R 5 + 2 beyond them, 2 below, the top at the highest tip. T1's
    // flutes (22 mm) are shorter than the slot is deep in that blank (27.4 mm):
    // its shank follows the plunge (line 7) into the bore the flutes cut, and
    // the first move across (line 8) runs it 5.37 mm into the material, in the
    // auto blank as in the same box.
    const auto t1 = test::simulate_job(slot_on("auto:2"), kSlot);
    REQUIRE_FALSE(t1.ok());
    CHECK(has(t1.err, "auto:2 is the blank box:-6.999,-6.999,-19.368,86.999,7.626,10.000 (round the "
                      "cutting moves and the tool, 2 mm beyond them"));
    CHECK(has(t1.err, "<stdin>:8:1: error: the shank of T1 (diameter 10.00 mm from 22.0 mm above the tip) runs 5.37 mm"));
    const auto t1_box = test::simulate_job(slot_on("box:-6.999,-6.999,-19.368,86.999,7.626,10.000"), kSlot);
    REQUIRE_FALSE(t1_box.ok());
    CHECK(t1_box.err.substr(t1_box.err.find("<stdin>:8:1: error:")) == t1.err.substr(t1.err.find("<stdin>:8:1: error:")));
    // T4, a flat D20 with flutes 38 mm long, cuts it: R 10 + 2 beyond.
    job::Settings t4 = slot_on("auto:2");
    t4.tool = "T4";
    const auto r = test::simulate_job(t4, kSlot);
    REQUIRE(r.ok());
    CHECK(has(r.err, "note: "));
    CHECK(has(r.err, "auto:2 is the blank box:-11.999,-11.999,-19.368,91.999,12.626,10.000 (round the "
                     "cutting moves and the tool, 2 mm beyond them"));
    t4.stock = "box:-11.999,-11.999,-19.368,91.999,12.626,10.000";
    const auto same = test::simulate_job(t4, kSlot);
    REQUIRE(same.ok());
    const report::ErrorStats &a = r.result->figures.error, &b = same.result->figures.error;
    CHECK(a.points > 0);
    CHECK(a.points == b.points);
    CHECK(a.max_abs == b.max_abs);
    CHECK(a.rms == b.rms);
    CHECK(a.share_out == b.share_out);
    CHECK(a.max_under == b.max_under);
    CHECK(a.max_over == b.max_over);
    for (const char* bad : {"auto:-1", "automatic"}) {
      CAPTURE(bad);
      test::Streams st(kSlot);
      CHECK(open_fails(slot_on(bad), st) == ErrorKind::settings);
    }
  }
}
