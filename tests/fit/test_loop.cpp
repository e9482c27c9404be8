// The whole loop through the library: deflex testcut, deflex probe, the
// probe's LinuxCNC log as a hidden machine would leave it, deflex fit, and
// the fitted profile held out against another program.
#include <doctest/doctest.h>

#include <cstdio>
#include <random>

#include "deflex/job/fit.hpp"
#include "deflex/job/testcut.hpp"
#include "deflex/measure/probe.hpp"
#include "support.hpp"

// Every case of this file in the suite "fit" (ctest runs suites: cmake/tests.cmake).
TEST_SUITE_BEGIN("fit");

namespace deflex::test {

namespace {

const char* kBlock = "box:0,0,-30,210,210,0";

// The test cut of `tool` in Al6082-T4 on mill3 on `block` and its LinuxCNC
// probing program: DIR/testcut<suffix>.nc, .yaml and probe<suffix>.nc.
void testcut_and_probe(const TempDir& dir, const std::string& tool = "T6", const std::string& block = kBlock,
                       const std::string& suffix = "") {
  Streams st;
  job::TestCutSettings t;
  t.read.machine = kSrc + "/samples/machines/mill3.yaml";
  t.tool = tool;
  t.tool_file = kSrc + "/samples/tools.yaml";
  t.material.material = "Al6082-T4";
  t.material.material_file = kSrc + "/samples/materials.yaml";
  t.stock = block;
  t.output = dir / ("testcut" + suffix + ".nc");
  job::testcut(t, st.io);
  job::ProbeSettings p;
  p.plan = dir / ("testcut" + suffix + ".yaml");
  p.output = dir / ("probe" + suffix + ".nc");
  p.options.step_mm = 0.25;
  p.read.dialect = "linuxcnc";
  job::probe(p, st.out, st.io);
}

job::Settings testcut_on(const TempDir& dir, const std::string& machine, const std::string& block = kBlock,
                         const std::string& suffix = "") {
  job::Settings s = walls(machine);
  s.program = dir / ("testcut" + suffix + ".nc");
  s.stock = block;
  return s;
}

// What (PROBEOPEN) would log on `hidden`: per target the ball centre where it
// trips, the intended point moved out by the radius and the error there, with
// 1 um Gaussian noise; nine numbers per line as LinuxCNC writes them.
std::string probe_log(const TempDir& dir, const Simulated& hidden, const std::string& suffix = "") {
  const std::string probe = dir / ("probe" + suffix + ".nc");
  const auto targets = measure::read_probe_targets(read(probe), probe);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.001);
  const std::string log = dir / ("probe_results" + suffix + ".txt");
  std::ofstream o(log);
  for (const measure::ProbeTarget& t : targets) {
    const long k = hidden.surface->nearest(t.point_mm, 0.5);
    REQUIRE(k >= 0);
    const double e = hidden.errors[static_cast<std::size_t>(k)] + noise(rng);
    const fit::V3 c = t.point_mm + (t.ball_radius_mm + e) * t.normal;
    char line[160];
    std::snprintf(line, sizeof line, "%f %f %f %f %f %f %f %f %f\n", c.x(), c.y(), c.z(), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    o << line;
  }
  return log;
}

}  // namespace

TEST_CASE("fit loop: test cut, probe, log of a hidden machine, fit; the fitted profile predicts the side wall") {
  TempDir dir("loop");
  testcut_and_probe(dir);
  const std::string hidden = hidden_machine(dir, true, true);  // X, Y, clamp x0.6, forces x1.2
  const std::string log = probe_log(dir, simulate_on(testcut_on(dir, hidden)));
  job::FitSettings s;
  s.run = testcut_on(dir, kSrc + "/samples/machines/mill3.yaml");
  s.run.measured = log;
  s.run.probe_program = dir / "probe.nc";
  s.output = dir / "fitted.yaml";
  Streams st;
  const job::FitReport r = job::fit(s, st.out, st.io);
  CHECK(r.matched == r.observations);
  CHECK(r.features.size() == 12);  // every wall of the plan measured and named
  CHECK(r.all.rms_after_mm < 0.0013);
  CHECK(r.all.rms_before_mm > 2 * r.all.rms_after_mm);
  for (int k = 0; k < fit::kParams; ++k) CHECK(r.fit.params[k].fitted == r.fit.params[k].why_held.empty());

  // Held out: the side wall sample (the same tool), on the fitted profile and on the hidden machine.
  auto side_wall = [&](const std::string& machine) {
    job::Settings w = walls(machine);
    w.program = kSrc + "/samples/programs/side_wall.nc";
    w.stock = "box:0,-40,-30,100,0,0";
    return simulate_on(w);
  };
  const Simulated truth = side_wall(hidden), predicted = side_wall(s.output),
                  unfitted = side_wall(kSrc + "/samples/machines/mill3.yaml");
  double worst = 0, worst_unfitted = 0;
  for (std::size_t i = 0; i < truth.errors.size(); ++i) {
    const double allowed = std::max(0.1 * std::abs(truth.errors[i]), 0.001);
    worst = std::max(worst, std::abs(predicted.errors[i] - truth.errors[i]) / allowed);
    worst_unfitted = std::max(worst_unfitted, std::abs(unfitted.errors[i] - truth.errors[i]) / allowed);
  }
  CAPTURE(worst);
  CAPTURE(worst_unfitted);
  CHECK(worst <= 1.0);
  CHECK(worst_unfitted > 1.0);  // the starting profile does not pass it
}

}  // namespace deflex::test

namespace deflex::test {

TEST_CASE("fit loop: the test cuts of three tools, probed on the hidden machine, recover it within 5 %") {
  // The hidden machine: structure X and Y 40 % apart (x1.4, x1.2),
  // the clamp x0.6, the forces x1.2, plus 1 um noise on every probed point.
  // T6 (D12, 50 mm out), T1 (D10, 40) and T4 (D20, 65): each test cut of
  // deflex testcut, probed every 0.25 mm by deflex probe, logged as
  // LinuxCNC would, and fitted together from mill3.
  TempDir dir("loop");
  const std::string block = "box:-220,-220,-40,220,220,0";
  const std::string hidden = hidden_machine(dir, true, true), start = kSrc + "/samples/machines/mill3.yaml";
  job::FitSettings s;
  for (const std::string tool : {"T6", "T1", "T4"}) {
    testcut_and_probe(dir, tool, block, tool);
    job::Settings cut = testcut_on(dir, start, block, tool);
    cut.measured = probe_log(dir, simulate_on(testcut_on(dir, hidden, block, tool)), tool);
    cut.probe_program = dir / ("probe" + tool + ".nc");
    if (tool == "T6") s.run = cut;
    else s.more.push_back(cut);
  }
  Streams st;
  const job::FitReport r = job::fit(s, st.out, st.io);
  CHECK(r.matched == r.observations);
  CHECK(r.features.size() == 36);  // every wall of every test cut
  check_recovered(r.fit, {0.6, 1.0, 1.4, 1.2, 1.0, 1.2},
                  {fit::Param::clamp, fit::Param::structure_x, fit::Param::structure_y, fit::Param::coefficients});
  CHECK(r.all.rms_after_mm < 0.0012);
}

}  // namespace deflex::test

TEST_SUITE_END();
