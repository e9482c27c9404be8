// What a run checks and says, through the job API: what the simulation needs
// is checked first, at the line, and nothing is written when it fails (the
// Error's kind is what the command line's exit code comes from); what is
// physically doubtful is warned at the worst line and kept in the summary.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "support.hpp"

using namespace deflex;
namespace fs = std::filesystem;

namespace {

const char* kWall = "samples/programs/side_wall.nc";

job::Settings on_wall(const std::string& program) {
  job::Settings s;
  s.program = program;
  s.material.material = "Al6082-T4";
  s.stock = "box:0,-40,-30,100,0,0";
  return s;
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("fail fast, say where: what the simulation needs is checked first, at the line, nothing written") {
    test::TempDir d("failfast");
    const std::string out = d / "out.nc", in = d / "in.nc";
    auto run = [&](const std::string& text, auto edit) {
      test::write_file(in, text);
      job::Settings s = on_wall(in);
      s.output = out;
      edit(s);
      return test::compensate_job(s);
    };
    const auto as_is = [](job::Settings&) {};
    const std::string no_s = "G21 G90 G54\nT6 M6\nM3\nG0 X-10. Y3.5 Z5.\nG1 Z-12. F1000.\nX110.\nM30\n";
    const auto r = run(no_s, as_is);
    CHECK(r.error == ErrorKind::input);
    CHECK(r.err.find("in.nc:5:1: error: cutting with no spindle speed") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    // The spindle setting supplies it.
    CHECK(run(no_s, [](job::Settings& s) { s.spindle_rpm = 6366; }).ok());
    CHECK(fs::exists(out));
    fs::remove(out);
    // A move far outside the machine's travel: refused before any simulation.
    const auto far = run("G21 G90 G54\nT6 M6\nS6000 M3\nG0 X-10. Y3.5 Z5.\nG1 Z-12. F1000.\nX100000.\nM30\n", as_is);
    CHECK(far.error == ErrorKind::input);
    CHECK(far.err.find("in.nc:6:1: error: X travels to") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    // A T word the library lacks: the library's (config) error; a tool
    // setting it lacks, or a negative thread count: a settings error.
    const auto t9 = run("G21 G90 G54\nT9 M6\nS6000 M3\nG0 X-10. Y3.5 Z5.\nG1 Z-12. F1000.\nX110.\nM30\n", as_is);
    CHECK(t9.error == ErrorKind::config);
    CHECK(t9.err.find("in.nc:5:1: error: tool T9 is not in the tool library") != std::string::npos);
    const auto t99 = run(no_s, [](job::Settings& s) {
      s.spindle_rpm = 6366;
      s.tool = "T99";
    });
    CHECK(t99.error == ErrorKind::settings);
    CHECK(t99.what.find("T99") != std::string::npos);
    CHECK(run(no_s, [](job::Settings& s) {
            s.spindle_rpm = 6366;
            s.threads = -1;
          }).error == ErrorKind::settings);
    CHECK_FALSE(fs::exists(out));
  }

  TEST_CASE("plausibility warnings: compiler style in the messages at the worst line, and in the summary") {
    // The side wall as designed: no warning of the plausibility tests; the
    // stability check finds its a_p of 12 mm above the modelled limit
    // (test_stability_limits.cpp checks that limit), and says only that.
    const auto ok = test::simulate_job(on_wall(kWall));
    REQUIRE(ok.ok());
    const report::Json& warned = ok.result->summary.at("warnings");
    REQUIRE(warned.size() == 1);
    CHECK(warned[0].at("kind") == "chatter");
    CHECK(ok.err.find("warning:") == ok.err.rfind("warning:"));
    // The same path with the D6 ball T3 (flutes 9 mm) 8 mm into a raw box
    // (top Z-4): deeper than its radius, a raw blank that needs roughing.
    job::Settings s = on_wall(kWall);
    s.tool = "T3";
    s.stock = "box:0,-40,-30,100,10,-4";
    const auto r = test::simulate_job(s);
    INFO(r.err);
    REQUIRE(r.ok());
    CHECK(r.err.find("side_wall.nc:16:1: warning: a_p up to") != std::string::npos);
    CHECK(r.err.find("[roughing]") != std::string::npos);
    CHECK(r.err.find("N22 X110.") != std::string::npos);  // the source line under it
    std::vector<std::string> kinds;
    for (const auto& w : r.result->summary.at("warnings")) kinds.push_back(w.at("kind"));
    CHECK(std::find(kinds.begin(), kinds.end(), "roughing") != kinds.end());
    // 12 mm into the wall's raw box (top Z0), 3 mm above the flutes: the neck
    // (D5.6 from 9 mm above the tip) rubs in the material it has not cut, an
    // error at the pass's line (0 - (-12 + 9) = 3 mm), and no report.
    s.stock = "box:0,-40,-30,100,10,0";
    const auto deep = test::simulate_job(s);
    REQUIRE_FALSE(deep.ok());
    CHECK(deep.error == ErrorKind::input);
    CHECK(deep.err.find("side_wall.nc:16:1: error: the neck of T3 (diameter 5.60 mm from 9.0 mm above the tip) runs 3.00 mm "
                        "into the material") != std::string::npos);
    CHECK(deep.err.find("[shank_collision]") != std::string::npos);
  }
}
