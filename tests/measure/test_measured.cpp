// measure::read_point_cloud and measure::read_measured: files by extension.
#include <doctest/doctest.h>

#include <fstream>

#include "deflex/measure/measured.hpp"
#include "support.hpp"
#include "../support.hpp"

using namespace deflex;
using deflex::test::error_text;

namespace {

void write(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

const std::string kProgram =
    "(DEFLEX PROBE 1 TOP AT 0.000 0.000 0.000 N 0.000 0.000 1.000 BALL 1.000)\nG38.2 Z-5. F100\n"
    "(DEFLEX PROBE 2 WX1 AT 10.000 5.000 -2.250 N 1.000 0.000 0.000 BALL 0.500)\nG38.2 X5. F100\n";

}  // namespace

TEST_SUITE("measure") {

TEST_CASE("point cloud from an STL: the distinct corners of its triangles, in order") {
  test::TempDir d("measure");
  // Two triangles sharing an edge: 4 distinct corners of 6.
  write(d / "scan.STL",
        "solid s\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n"
        " facet normal 0 0 1\n  outer loop\n   vertex 1 0 0\n   vertex 1 1 0.5\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid s\n");
  const auto s = measure::read_point_cloud(d / "scan.STL");
  REQUIRE(s.size() == 4);
  CHECK(s[0].p_mm == Eigen::Vector3d(0, 0, 0));
  CHECK(s[3].p_mm == Eigen::Vector3d(1, 1, 0.5));
  const measure::Measured m = measure::read_measured(d / "scan.STL");
  CHECK(m.form == measure::MeasuredForm::point_cloud);
  CHECK(m.samples.size() == 4);
}

TEST_CASE("read_measured: CSV and PLY by extension, logs sniffed and joined with the probe program") {
  test::TempDir d("measure");
  write(d / "cmm.csv", "x_mm,y_mm,z_mm\n1,2,3\n");
  const measure::Measured csv = measure::read_measured(d / "cmm.csv");
  CHECK(csv.form == measure::MeasuredForm::points_csv);
  REQUIRE(csv.samples.size() == 1);
  CHECK(csv.samples[0].p_mm == Eigen::Vector3d(1, 2, 3));

  write(d / "cloud.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\nproperty double z\n"
                         "end_header\n4 5 6\n");
  CHECK(measure::read_measured(d / "cloud.ply").samples.at(0).p_mm == Eigen::Vector3d(4, 5, 6));

  write(d / "probe.nc", kProgram);
  write(d / "dprnt.txt", "%\nPT2 X  10.5200 Y   5.0000 Z  -2.2500\nPT1 X   0.0000 Y   0.0000 Z   0.9900\n%\n");
  const measure::Measured dprnt = measure::read_measured(d / "dprnt.txt", d / "probe.nc");
  CHECK(dprnt.form == measure::MeasuredForm::dprnt);
  REQUIRE(dprnt.points.size() == 2);
  CHECK(dprnt.points[0].error_mm == doctest::Approx(-0.01));
  CHECK(dprnt.points[1].error_mm == doctest::Approx(0.02));

  write(d / "probe.log", "0.000000 0.000000 1.030000 0 0 0 0 0 0\n10.490000 5.000000 -2.250000 0 0 0 0 0 0\n");
  const measure::Measured log = measure::read_measured(d / "probe.log", d / "probe.nc");
  CHECK(log.form == measure::MeasuredForm::linuxcnc_log);
  REQUIRE(log.points.size() == 2);
  CHECK(log.points[0].error_mm == doctest::Approx(0.03));
  CHECK(log.points[1].error_mm == doctest::Approx(-0.01));
}

TEST_CASE("read_measured: a log without its probe program, an unreadable file, an unknown cloud") {
  test::TempDir d("measure");
  write(d / "probe.log", "0 0 1 0 0 0 0 0 0\n");
  CHECK(error_text([&] { measure::read_measured(d / "probe.log"); }, ErrorKind::settings).find("probe program") !=
        std::string::npos);
  CHECK(!error_text([&] { measure::read_measured(d / "missing.csv"); }, ErrorKind::io).empty());
  CHECK(error_text([&] { measure::read_point_cloud(d / "probe.log"); }).find("expected .ply or .stl") != std::string::npos);
}

}  // TEST_SUITE
