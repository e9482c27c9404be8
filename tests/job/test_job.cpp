// The job API (include/deflex/job/job.hpp) against the command line that
// drives it: the same bytes and figures, the points an observer gets are
// points.csv's, a cancelled run writes nothing, and every check of the
// settings runs before anything is read.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

using test::TempDir;

// tests/golden/compensate_wall.args as settings: the wall on its box stock.
job::Settings wall_settings() {
  job::Settings s;
  s.program = "tests/golden/wall.nc";
  s.stock = "box:0,0,-20,100,20,0";
  s.tolerance_mm = 0.002;
  s.threads = 1;
  return s;
}

using test::Streams;

// Keeps every row and counts the progress calls; cancels at the first one when asked.
struct Watch : job::Observer {
  bool cancel = false;
  int progress_calls = 0;
  std::vector<report::PointRow> rows;
  void progress(const std::string&, double) override { ++progress_calls; }
  bool cancelled() override { return cancel; }
  bool wants_rows() const override { return true; }
  void row(const report::PointRow& r) override { rows.push_back(r); }
};

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("job::compensate writes the command line's bytes, and its summary is the CLI's summary.json") {
    TempDir t;
    const auto cli = test::run_cli({"compensate", "tests/golden/wall.nc", "--stock", "box:0,0,-20,100,20,0",
                                    "--tolerance", "0.002", "--threads", "1", "--report", t / "cli"});
    REQUIRE(cli.rc == 0);
    Streams s;
    job::Run run = job::open(wall_settings(), job::Purpose::compensate, s.io);
    const job::CompensateResult r = job::compensate(run, s.out, s.io);
    CHECK(s.out.str() == cli.out);
    CHECK(s.out.str() != test::read_file("tests/golden/wall.nc"));  // something was compensated
    const report::Json file = report::Json::parse(test::read_file(t / "cli/summary.json"));
    CHECK(report::Json::parse(report::document(r.summary)) == file);
    CHECK(r.result.compensated_points > 0);
    CHECK(r.figures.error.max_abs < r.figures.error_as_written.max_abs);
    // The messages are the command line's, which then prints the figures itself.
    const std::string api = s.err.str();
    CHECK(cli.err.compare(0, api.size(), api) == 0);
    CHECK(cli.err.substr(api.size()).starts_with("tests/golden/wall.nc: 5 points compensated"));
  }

  TEST_CASE("the observer's rows are points.csv's, value for value within its decimals") {
    TempDir t;
    job::Settings st = wall_settings();
    st.report_dir = t / "report";
    Streams s;
    Watch w;
    job::Run run = job::open(st, job::Purpose::simulate, s.io);
    const job::SimulateResult r = job::simulate(run, s.io, &w);
    const test::Csv csv = test::read_csv(t / "report/points.csv");
    REQUIRE(csv.rows.size() == w.rows.size());
    REQUIRE(!w.rows.empty());
    CHECK(w.progress_calls > 0);
    for (std::size_t i = 0; i < w.rows.size(); ++i) {
      const report::PointRow& row = w.rows[i];
      CAPTURE(i);
      CHECK(csv.num(i, "line") == row.line);
      CHECK(std::fabs(csv.num(i, "x_mm") - row.tip_mm.x()) <= 0.5e-4);
      CHECK(std::fabs(csv.num(i, "Fy_N") - row.force_N.y()) <= 0.5e-2);
      CHECK(std::fabs(csv.num(i, "surface_error_mm") - row.surface_error_mm) <= 0.5e-6);
      CHECK(csv.rows[i][csv.col("normal_source")] == row.normal_source);
    }
    CHECK(r.figures.error.points > 0);
  }

  TEST_CASE("a cancelled run writes no program and leaves no report file") {
    TempDir t;
    job::Settings st = wall_settings();
    st.output = t / "out.nc";
    st.report_dir = t / "report";
    Streams s;
    Watch w;
    w.cancel = true;
    job::Run run = job::open(st, job::Purpose::compensate, s.io);
    CHECK_THROWS_AS(job::compensate(run, s.out, s.io, &w), job::Cancelled);
    CHECK(!fs::exists(t / "out.nc"));
    CHECK(!fs::exists(t / "report/points.csv"));
    CHECK(s.out.str().empty());
  }

  TEST_CASE("open() checks every setting before it reads the program") {
    job::Settings st = wall_settings();
    st.program = "/nonexistent/deflex-job.nc";  // would be an I/O error when read
    st.tolerance_mm = -1;
    Streams s;
    try {
      (void)job::open(st, job::Purpose::compensate, s.io);
      FAIL("open() accepted a negative tolerance");
    } catch (const Error& e) {
      CHECK(e.kind() == ErrorKind::settings);
      CHECK(std::string(e.what()).find("tolerance") != std::string::npos);
    }
  }

  TEST_CASE("open() reads a long program in pieces where the purpose allows, whole where it does not") {
    ::setenv("DEFLEX_CHUNK_LINES", "4", 1);
    job::Settings st = wall_settings();
    Streams s;
    const job::Run c = job::open(st, job::Purpose::compensate, s.io);
    const job::Run m = job::open(st, job::Purpose::compare, s.io);
    st.reference = st.program;
    const job::Run r = job::open(st, job::Purpose::simulate, s.io);
    ::unsetenv("DEFLEX_CHUNK_LINES");
    CHECK(c.pieces != nullptr);
    CHECK(c.motions.empty());
    CHECK(m.pieces == nullptr);
    CHECK(!m.motions.empty());
    CHECK(r.pieces == nullptr);  // judged against a reference: the pairing needs the whole program
    CHECK(c.motion_count == m.motions.size());
  }
}
