// Many programs at once: two compensations run as two
// processes at the same time, as GNU parallel runs them, write exactly what
// each writes alone. Nothing in a run depends on another process, the clock
// (outside report.html's provenance) or the thread schedule.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "../support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

TEST_SUITE("cli") {
  TEST_CASE("two compensations in parallel write what each writes alone") {
    std::string t = (fs::temp_directory_path() / "deflex-parallel-XXXXXX").string();
    const fs::path dir = mkdtemp(t.data());
    const char* progs[] = {"zigzag_0", "contour"};
    auto command = [&](const std::string& prog, const std::string& tag) {
      const fs::path out = dir / (prog + "_" + tag);
      return std::string(DEFLEX_BINARY) + " compensate samples/strategies/" + prog +
             ".nc --stock samples/stock/freeform_stock.stl --material Al7075-T6 --cell-mm 0.1 -o " +
             (out.string() + ".nc") + " --report " + out.string() + " 2>/dev/null";
    };
    // Together: both started before either ends (the shell's & and wait).
    const std::string together = "(" + command(progs[0], "par") + ") & (" + command(progs[1], "par") + ") & wait";
    REQUIRE(std::system(together.c_str()) == 0);
    for (const char* p : progs) {
      REQUIRE(std::system(command(p, "seq").c_str()) == 0);
      CAPTURE(p);
      const std::string a = (dir / (std::string(p) + "_par")).string(), b = (dir / (std::string(p) + "_seq")).string();
      const std::string out = test::read_file(a + ".nc");
      CHECK(out.size() > 1000);
      CHECK(out == test::read_file(b + ".nc"));
      CHECK(test::read_file(a + "/points.csv") == test::read_file(b + "/points.csv"));
      CHECK(test::read_file(a + "/summary.json") == test::read_file(b + "/summary.json"));
    }
    fs::remove_all(dir);
  }
}
