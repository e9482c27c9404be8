// simulate --measured (job::simulate with Settings::measured): the
// prediction held against measured points, measured.csv and summary.json.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "support.hpp"

// Every case of this file in the suite "fit" (ctest runs suites: cmake/tests.cmake).
TEST_SUITE_BEGIN("fit");

namespace deflex::test {

namespace {

job::Settings walls() { return test::walls(kSrc + "/samples/machines/mill3.yaml"); }

// Surface points of the back wall (normal +Y) as mill3 predicts them, moved
// by `shift_mm` along Y and 1 um Gaussian noise, as a CMM's CSV.
std::string measured_csv(const TempDir& dir, double shift_mm, std::vector<double>* errors = nullptr) {
  Streams st;
  job::Run run = job::open(walls(), job::Purpose::fit, st.io);
  compensate::Settings cs = run.settings;
  cs.flank_profiles = true;
  const std::vector<compensate::Point> pts = compensate::simulate(run.motions, {}, run.physics, cs);
  const fit::Surface surface(pts, job::tool_of(run));
  const std::vector<double> e = surface.errors(pts);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.001);
  const std::string path = dir / "measured.csv";
  std::ofstream o(path);
  o << "x_mm,y_mm,z_mm\n";
  o.precision(9);
  for (double x : {30.0, 50.0, 70.0})
    for (double z = -11.5; z < -0.2; z += 0.5) {
      const long k = surface.nearest({x, 96.0, z}, 0.5);
      REQUIRE(k >= 0);
      const fit::SurfaceSample& s = surface.samples()[static_cast<std::size_t>(k)];
      const fit::V3 p = s.at_mm + (e[static_cast<std::size_t>(k)] + noise(rng)) * s.normal;
      o << p.x() << "," << p.y() + shift_mm << "," << p.z() << "\n";
      if (errors) errors->push_back(e[static_cast<std::size_t>(k)]);
    }
  return path;
}

std::size_t lines_of(const std::string& path) {
  std::ifstream f(path);
  std::size_t n = 0;
  for (std::string l; std::getline(f, l);) ++n;
  return n;
}

}  // namespace

TEST_CASE("simulate --measured: the machine that made the measurements agrees with them to the noise") {
  TempDir dir("measured");
  std::vector<double> truth;
  job::Settings s = walls();
  s.measured = measured_csv(dir, 0.0, &truth);
  s.report_dir = dir / "report";
  const auto o = simulate_job(s);
  REQUIRE(o.ok());
  const job::MeasuredComparison& m = *o.result->measured;
  REQUIRE(m.rows.size() == truth.size());
  CHECK(m.unmatched == 0);
  const fit::Agreement& a = m.agreement;
  CHECK(a.points == truth.size());
  CHECK(a.rms_difference_mm > 0.0006);  // the 1 um noise is there ...
  CHECK(a.rms_difference_mm < 0.0014);  // ... and nothing more
  CHECK(a.correlation > 0.95);
  CHECK(a.within_tolerance_share == 1.0);
  CHECK(a.rms_measured_mm > 0.01);      // a real error was measured, not zero against zero
  for (std::size_t i = 0; i < truth.size(); ++i) CHECK(m.rows[i].predicted_error_mm == deflex::test::within(truth[i], 1e-9));
  CHECK(lines_of(dir / "report/measured.csv") == truth.size() + 1);
  CHECK(o.result->summary["measured"]["compared"].get<std::size_t>() == truth.size());
  CHECK(o.err.find("predicted against measured over " + std::to_string(truth.size()) + " points") != std::string::npos);
}

TEST_CASE("simulate --measured: points off the cut surface have no prediction, and are said") {
  TempDir dir("measured");
  job::Settings s = walls();
  s.measured = measured_csv(dir, 3.0);  // 3 mm out into the air: the wrong work offset
  const auto o = simulate_job(s);
  REQUIRE(o.ok());
  const job::MeasuredComparison& m = *o.result->measured;
  CHECK(m.unmatched == m.rows.size());
  CHECK(m.agreement.points == 0);
  CHECK(o.err.find("warning: " + std::to_string(m.rows.size()) + " measured points of " + std::to_string(m.rows.size()) +
                   " lie farther than 0.500 mm") != std::string::npos);
}

TEST_CASE("simulate --measured: a malformed measurement stops the run before anything is simulated or written") {
  TempDir dir("measured");
  const std::string bad = dir / "bad.csv";
  std::ofstream(bad) << "x_mm,y_mm,z_mm\n1,2,3\n4,nan,6\n";
  job::Settings s = walls();
  s.measured = bad;
  s.report_dir = dir / "report";
  const auto o = simulate_job(s);
  REQUIRE_FALSE(o.ok());
  CHECK(o.what.find(bad + ":3:") != std::string::npos);
  CHECK((!std::filesystem::exists(dir / "report") || std::filesystem::is_empty(dir / "report")));
}

}  // namespace deflex::test

namespace deflex::test {

TEST_CASE("simulate --measured --reference: measured and predicted from the design surface, not the compensated path") {
  TempDir dir("measured");
  // The four walls compensated on mill3.
  job::Settings c = walls();
  c.output = dir / "comp.nc";
  REQUIRE(compensate_job(c).ok());
  // Points exactly on the designed back wall (y = 96): no error measured there.
  const std::string csv = dir / "on_design.csv";
  {
    std::ofstream o(csv);
    o << "x_mm,y_mm,z_mm\n";
    for (double z = -11.5; z < -0.2; z += 0.5) o << "50," << 96.0 << "," << z << "\n";
  }
  job::Settings s = walls();
  s.program = c.output;
  s.reference = walls().program;
  s.measured = csv;
  const auto o = simulate_job(s);
  REQUIRE(o.ok());
  const job::MeasuredComparison& m = *o.result->measured;
  REQUIRE(m.unmatched == 0);
  double largest_prediction = 0;
  for (const job::MeasuredRow& r : m.rows) {
    CHECK(std::abs(r.measured_error_mm) < 1e-6);  // against the design's envelope, not the compensated one's
    largest_prediction = std::max(largest_prediction, std::abs(r.predicted_error_mm));
  }
  // Compensated: the wall lands within the taper of its flank profile, far
  // less off the design than the program as written.
  job::Settings w = walls();
  w.measured = csv;
  const auto as_written = simulate_job(w);
  REQUIRE(as_written.ok());
  double largest_as_written = 0;
  for (const job::MeasuredRow& r : as_written.result->measured->rows)
    largest_as_written = std::max(largest_as_written, std::abs(r.predicted_error_mm));
  CAPTURE(largest_prediction);
  CAPTURE(largest_as_written);
  CHECK(largest_prediction < 0.5 * largest_as_written);
}

}  // namespace deflex::test

TEST_SUITE_END();
