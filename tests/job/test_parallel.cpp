// Many programs at once: two compensations run at the same time, each on a
// thread of its own in one process (as a batch driver or the Python module
// runs them), write exactly what each writes alone. Nothing in a run depends
// on another run, the clock (outside report.html's provenance) or the thread
// schedule.
#include <doctest/doctest.h>

#include <string>
#include <thread>

#include "support.hpp"

using namespace deflex;

TEST_SUITE("job") {
  TEST_CASE("two compensations at once write what each writes alone") {
    test::TempDir dir("parallel");
    const char* progs[] = {"zigzag_0", "contour"};
    auto settings = [&](const std::string& prog, const std::string& tag) {
      job::Settings s;
      s.program = "samples/strategies/" + prog + ".nc";
      s.stock = "samples/stock/freeform_stock.stl";
      s.material.material = "Al7075-T6";
      s.cell_mm = 0.1;
      s.output = dir / (prog + "_" + tag + ".nc");
      s.report_dir = dir / (prog + "_" + tag);
      return s;
    };
    // Together: both started before either ends.
    test::Outcome<job::CompensateResult> together[2];
    {
      std::jthread a([&] { together[0] = test::compensate_job(settings(progs[0], "par")); });
      std::jthread b([&] { together[1] = test::compensate_job(settings(progs[1], "par")); });
    }
    for (int i = 0; i < 2; ++i) {
      const std::string p = progs[i];
      CAPTURE(p);
      REQUIRE_MESSAGE(together[i].ok(), together[i].err);
      const auto alone = test::compensate_job(settings(p, "seq"));
      REQUIRE(alone.ok());
      CHECK(together[i].err == alone.err);
      const std::string a = dir / (p + "_par"), b = dir / (p + "_seq");
      const std::string out = test::read_file(a + ".nc");
      CHECK(out.size() > 1000);
      CHECK(out == test::read_file(b + ".nc"));
      CHECK(test::read_file(a + "/points.csv") == test::read_file(b + "/points.csv"));
      CHECK(test::read_file(a + "/summary.json") == test::read_file(b + "/summary.json"));
    }
  }
}
