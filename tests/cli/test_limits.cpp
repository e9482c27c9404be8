// Hostile input on the command line: --max-blocks and its exit codes, and
// no path printed cut off at the budget. The limits themselves are
// tests/job/test_limits.cpp.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "../support.hpp"

using namespace deflex;

namespace {
bool has(const std::string& s, const std::string& sub) { return s.find(sub) != std::string::npos; }

// Three nested subprograms of 9999 repeats each: 2e12 motions if nothing stops them.
const char* kExplosion =
    "G21 G90 G0 X0 Y0 Z0\nM98 P1 L9999\nM30\n"
    "O1\nM98 P2 L9999\nM99\nO2\nM98 P3 L9999\nM99\nO3\nG1 X1. F100\nG1 X0\nM99\n";
}  // namespace

TEST_SUITE("cli") {

TEST_CASE("limits: the CLI reports them with exit codes (--max-blocks)") {
  const std::string f = (std::filesystem::temp_directory_path() / ("deflex-limits-" + std::to_string(::getpid()) + ".nc")).string();
  test::write_file(f, kExplosion);
  auto r = test::run_cli({"path", f, "--max-blocks", "2000"});
  CHECK(r.rc == 1);
  CHECK(has(r.err, "error: more than 2000 blocks executed (subprogram and canned-cycle repeats); --max-blocks "
                   "raises the limit"));
  CHECK(r.out.empty());  // no path cut off at the budget
  // The same nesting with 20 repeats a level runs within the budget and prints every motion.
  test::write_file(f, "G21 G90 G0 X0 Y0 Z0\nM98 P1 L20\nM30\nO1\nM98 P2 L20\nM99\nO2\nG1 X1. F100\nG1 X0\nM99\n");
  const auto ok = test::run_cli({"path", f, "--max-blocks", "2000"});
  CHECK(ok.rc == 0);
  CHECK(std::count(ok.out.begin(), ok.out.end(), '\n') == 1 + 20 * 20 * 2);
  CHECK(test::run_cli({"check", f, "--max-blocks", "0"}).rc == 2);
  std::remove(f.c_str());
}

}  // TEST_SUITE
