// measure::read_points_csv: a CMM's CSV export.
#include <doctest/doctest.h>

#include "deflex/measure/samples.hpp"
#include "support.hpp"

using namespace deflex;
using deflex::test::check_located;
using deflex::test::error_text;

namespace {
std::string csv_error(const std::string& text) {
  return error_text([&] { measure::read_points_csv(text, "p.csv"); });
}
}  // namespace

TEST_SUITE("measure") {

TEST_CASE("points CSV: comments, blank lines, other columns and ids; exact values") {
  const auto s = measure::read_points_csv(
      "# exported by the CMM\nid,x_mm,y_mm,z_mm,dev\n1,10.0,5.0,-2.25,0.01\n\n7, 10.5 ,+5,-2.25e0,n/a\n", "p.csv");
  REQUIRE(s.size() == 2);
  CHECK(s[0].p_mm == Eigen::Vector3d(10.0, 5.0, -2.25));
  CHECK(s[0].id == 1);
  CHECK(s[0].line == 3);
  CHECK(s[1].p_mm == Eigen::Vector3d(10.5, 5.0, -2.25));
  CHECK(s[1].id == 7);
  CHECK(s[1].line == 5);
}

TEST_CASE("points CSV: columns in any order and case, CRLF, quoted names, no id") {
  const auto s = measure::read_points_csv("\"Z_MM\",y_mm,X_mm\r\n-2.25,5,0.1\r\n", "p.csv");
  REQUIRE(s.size() == 1);
  CHECK(s[0].p_mm == Eigen::Vector3d(0.1, 5.0, -2.25));
  CHECK(s[0].id == -1);
}

TEST_CASE("points CSV: NaN, infinity, junk in a number are located errors") {
  check_located(csv_error("x_mm,y_mm,z_mm\n1,nan,3\n"), "p.csv:2:3", "y_mm: 'nan' is not a finite number", "1,nan,3", 3);
  check_located(csv_error("x_mm,y_mm,z_mm\n1,2,-inf\n"), "p.csv:2:5", "z_mm: '-inf' is not a finite number", "1,2,-inf", 5);
  check_located(csv_error("x_mm,y_mm,z_mm\n1x,2,3\n"), "p.csv:2:1", "x_mm: '1x' is not a number", "1x,2,3", 1);
  check_located(csv_error("x_mm,y_mm,z_mm\n1,,3\n"), "p.csv:2:3", "y_mm: an empty field is not a number", "1,,3", 3);
}

TEST_CASE("points CSV: a header in inches or without units says so") {
  check_located(csv_error("x_in,y_in,z_in\n0.1,0.2,0.3\n"), "p.csv:1:1", "column 'x_in' is in inches", "x_in,y_in,z_in", 1);
  check_located(csv_error("x,y,z\n1,2,3\n"), "p.csv:1:1", "column 'x' gives no unit", "x,y,z", 1);
  check_located(csv_error("x_mm,y_mm\n1,2\n"), "p.csv:1:1", "no column z_mm", "x_mm,y_mm", 1);
  check_located(csv_error("x_mm,y_mm,z_mm,X_MM\n1,2,3,4\n"), "p.csv:1:16", "column 'X_MM' given twice",
                "x_mm,y_mm,z_mm,X_MM", 16);
}

TEST_CASE("points CSV: a byte order mark is read past; ';' as separator is an error") {
  CHECK(measure::read_points_csv("\xEF\xBB\xBFx_mm,y_mm,z_mm\n1,2,3\n", "p.csv").at(0).p_mm == Eigen::Vector3d(1, 2, 3));
  check_located(csv_error("x_mm;y_mm;z_mm\n1,5;2;3\n"), "p.csv:1:1", "fields separated by ';'", "x_mm;y_mm;z_mm", 1);
}

TEST_CASE("points CSV: a missing point coordinate, extra junk, a repeated id") {
  check_located(csv_error("x_mm,y_mm,z_mm\n1,2\n"), "p.csv:2:4", "expected 3 fields as the header names, found 2", "1,2", 4);
  check_located(csv_error("x_mm,y_mm,z_mm\n1,2,3,4\n"), "p.csv:2:6", "found 4", "1,2,3,4", 6);
  check_located(csv_error("id,x_mm,y_mm,z_mm\n1,1,2,3\n1,4,5,6\n"), "p.csv:3:1", "id 1 given twice (first on line 2)",
                "1,4,5,6", 1);
  check_located(csv_error("id,x_mm,y_mm,z_mm\n0,1,2,3\n"), "p.csv:2:1", "id '0' is not a positive whole number", "0,1,2,3", 1);
}

TEST_CASE("points CSV: an empty file, no header, no points") {
  check_located(csv_error(""), "p.csv:1:1", "the file is empty", "", 1);
  check_located(csv_error("# only a comment\n"), "p.csv:1:1", "no header", "# only a comment", 1);
  check_located(csv_error("1,2,3\n"), "p.csv:1:1", "the first line is data, not a header", "1,2,3", 1);
  check_located(csv_error("x_mm,y_mm,z_mm\n\n"), "p.csv:1:1", "no points after the header", "x_mm,y_mm,z_mm", 1);
}

}  // TEST_SUITE
