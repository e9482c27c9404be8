// measure::read_linuxcnc_probe_log and measure::read_dprnt: the probe logs.
#include <doctest/doctest.h>

#include "deflex/measure/samples.hpp"
#include "support.hpp"

using namespace deflex;
using deflex::test::check_located;
using deflex::test::error_text;

namespace {
std::string log_error(const std::string& text) {
  return error_text([&] { measure::read_linuxcnc_probe_log(text, "probe.txt"); });
}
std::string dprnt_error(const std::string& text) {
  return error_text([&] { measure::read_dprnt(text, "dprnt.txt"); });
}
const std::string kZeros6 = " 0.000000 0.000000 0.000000 0.000000 0.000000 0.000000";
}  // namespace

TEST_SUITE("measure") {

TEST_CASE("LinuxCNC probe log: nine numbers a line as fprintf %f writes them; X Y Z kept") {
  const auto s = measure::read_linuxcnc_probe_log(
      "10.000000 5.000000 -2.250000" + kZeros6 + "\n-0.125000 1.500000 3.000000 90.000000 0 0 0 0 0\n", "probe.txt");
  REQUIRE(s.size() == 2);
  CHECK(s[0].p_mm == Eigen::Vector3d(10.0, 5.0, -2.25));
  CHECK(s[0].line == 1);
  CHECK(s[0].id == -1);
  CHECK(s[1].p_mm == Eigen::Vector3d(-0.125, 1.5, 3.0));
  CHECK(s[1].line == 2);
}

TEST_CASE("LinuxCNC probe log: 8 numbers, 10 numbers, NaN, an empty log are located errors") {
  const std::string eight = "1.000000 2.000000 3.000000 0.000000 0.000000 0.000000 0.000000 0.000000";
  check_located(log_error("1.0 2.0 3.0" + kZeros6 + "\n" + eight + "\n"), "probe.txt:2:" + std::to_string(eight.size() + 1),
                "expected 9 numbers (X Y Z A B C U V W", eight, static_cast<std::uint32_t>(eight.size() + 1));
  const std::string ten = "1 2 3 4 5 6 7 8 9 10";
  check_located(log_error(ten + "\n"), "probe.txt:1:19", "found 10", ten, 19);
  const std::string nan = "1.000000 2.000000 -nan" + kZeros6;
  check_located(log_error(nan + "\n"), "probe.txt:1:19", "Z: '-nan' is not a finite number", nan, 19);
  check_located(log_error(""), "probe.txt:1:1", "no probe positions in the log", "", 1);
}

TEST_CASE("DPRNT: blanks and leading zeros padding the numbers, '%' and blank lines, ids") {
  const auto s = measure::read_dprnt(
      "%\r\nPT12 X  12.3450 Y  -5.0000 Z  -2.2500\r\n\r\nPT3 X0005.0000 Y-  10.5 Z-.25\r\nPT 4 X+1. Y 0 Z 7\r\n%\r\n",
      "dprnt.txt");
  REQUIRE(s.size() == 3);
  CHECK(s[0].p_mm == Eigen::Vector3d(12.345, -5.0, -2.25));
  CHECK(s[0].id == 12);
  CHECK(s[0].line == 2);
  CHECK(s[1].p_mm == Eigen::Vector3d(5.0, -10.5, -0.25));
  CHECK(s[1].id == 3);
  CHECK(s[1].line == 4);
  CHECK(s[2].p_mm == Eigen::Vector3d(1.0, 0.0, 7.0));
  CHECK(s[2].id == 4);
}

TEST_CASE("DPRNT: a repeated id, a missing coordinate, another shape, junk are located errors") {
  check_located(dprnt_error("PT12 X1.0 Y2.0 Z3.0\n%\nPT12 X1.0 Y2.0 Z3.5\n"), "dprnt.txt:3:1",
                "point PT12 printed twice (first on line 1)", "PT12 X1.0 Y2.0 Z3.5", 1);
  check_located(dprnt_error("PT1 X 1.0 Y 2.0\n"), "dprnt.txt:1:16", "Z coordinate missing", "PT1 X 1.0 Y 2.0", 16);
  check_located(dprnt_error("PT1 X 1.0 Z 2.0\n"), "dprnt.txt:1:11", "expected Y, found 'Z'", "PT1 X 1.0 Z 2.0", 11);
  check_located(dprnt_error("PT1 X1.0 Y2.0 Z\n"), "dprnt.txt:1:16", "no number after Z", "PT1 X1.0 Y2.0 Z", 16);
  check_located(dprnt_error("MEASURED PART\n"), "dprnt.txt:1:1", "expected a line PT<id>", "MEASURED PART", 1);
  check_located(dprnt_error("PT0 X1 Y2 Z3\n"), "dprnt.txt:1:3", "expected the probe point's id", "PT0 X1 Y2 Z3", 3);
  check_located(dprnt_error("PT1 X1 Y2 Z3 *\n"), "dprnt.txt:1:14", "unexpected '*' after the Z coordinate", "PT1 X1 Y2 Z3 *", 14);
  check_located(dprnt_error("%\n\n"), "dprnt.txt:2:1", "no probe points", "", 1);
}

}  // TEST_SUITE
