// The machine profile's spindle: section (power and torque against speed): what
// it reads, the torque it allows, and its errors at line:col.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <unistd.h>

#include "../support.hpp"
#include "section_file.hpp"

using namespace deflex;
namespace fs = std::filesystem;

namespace {

struct Profile : test::SectionProfile {
  Profile() : SectionProfile("spindle") {}
};

}  // namespace

TEST_SUITE("profile") {

TEST_CASE("spindle: the sample machine's S1 and S6 curves, and the torque each allows") {
  const auto m = profile::load_machine("mill3");
  REQUIRE(m.spindle.set);
  CHECK(m.spindle.max_rpm == 12000);
  REQUIRE(m.spindle.s6);
  const profile::SpindleCurve& s1 = m.spindle.s1;
  // Constant torque to the base speed, then constant power: M = P / w.
  CHECK(s1.allowed_torque_Nm(500) == doctest::Approx(70));
  CHECK(s1.allowed_torque_Nm(6000) == doctest::Approx(11000 / (2 * std::numbers::pi * 6000 / 60)));
  CHECK(s1.allowed_power_kW(6000) == doctest::Approx(11));
  CHECK(s1.allowed_power_kW(750) == doctest::Approx(70 * 2 * std::numbers::pi * 750 / 60 / 1000));
  CHECK(m.spindle.s6->allowed_power_kW(8000) == doctest::Approx(15));
  // Without the section nothing is rated.
  Profile p;
  test::write_file(p.file, "name: m\n");
  CHECK_FALSE(profile::load_machine(p.file).spindle.set);
}

TEST_CASE("spindle: a power curve alone, a torque curve alone, linear between their points") {
  Profile p;
  const auto power = p.load("  max_rpm: 8000\n  S1: {rpm: [0, 2000, 8000], power_kW: [0, 20, 20]}\n");
  const double w1000 = 2 * std::numbers::pi * 1000 / 60;
  CHECK(power.spindle.s1.allowed_power_kW(1000) == doctest::Approx(10));
  CHECK(power.spindle.s1.allowed_torque_Nm(1000) == doctest::Approx(10000 / w1000));
  CHECK(power.spindle.s1.allowed_power_kW(9000) == doctest::Approx(20));  // past the last point: its value
  CHECK_FALSE(power.spindle.s6);
  const auto torque = p.load("  max_rpm: 8000\n  S1: {rpm: [0, 8000], torque_Nm: [100, 20]}\n");
  CHECK(torque.spindle.s1.allowed_torque_Nm(4000) == doctest::Approx(60));
}

TEST_CASE("spindle: a malformed curve is a located error") {
  Profile p;
  const std::string f = p.file + ":";
  CHECK(p.error("  S1: {rpm: [0, 1000], power_kW: [0, 5]}\n") == f + "3:3: error: missing key 'max_rpm' in spindle");
  CHECK(p.error("  max_rpm: 9000\n") == f + "3:3: error: missing key 'S1' in spindle");
  CHECK(p.error("  max_rpm: 9000\n  S1: {rpm: [100, 1000], power_kW: [1, 5]}\n") ==
        f + "4:13: error: spindle.S1.rpm must start at 0 (the curve covers every speed the program may ask)");
  CHECK(p.error("  max_rpm: 9000\n  S1: {rpm: [0, 1000, 1000], power_kW: [0, 5, 5]}\n") ==
        f + "4:13: error: spindle.S1.rpm must be strictly increasing");
  CHECK(p.error("  max_rpm: 9000\n  S1: {rpm: [0, 1000], power_kW: [0, 5, 5]}\n") ==
        f + "4:34: error: spindle.S1.power_kW has 3 values, rpm 2 values");
  CHECK(p.error("  max_rpm: 9000\n  S1: {rpm: [0, 1000]}\n") == f + "4:7: error: spindle.S1 needs power_kW, torque_Nm or both");
  CHECK(p.error("  max_rpm: 9000\n  S1: {rpm: [0, 1000], power_kW: [0, -5]}\n") ==
        f + "4:38: error: spindle.S1.power_kW must be >= 0");
  CHECK(p.error("  max_rpm: 9000\n  S1: {rpm: [0, 1000], power_kW: [0, 5], torque_Nm: [60, 60]}\n") ==
        f + "4:34: error: spindle.S1 at 1000 rpm: 60.0 N m is 6.28 kW (P = M 2 pi n / 60), not 5.00 kW: the two curves "
            "disagree by more than 10 %");
  CHECK(p.error("  max_rpm: 9000\n  S1: {rpm: [0, 1000], power_kW: [0, 0]}\n") ==
        f + "4:7: error: spindle.S1 allows no torque at 1000 rpm");
  CHECK(p.error("  max_rpm: 9000\n  S1: {rpm: [0, 1000], power_kW: [0, 5]}\n  S7: {}\n").find(
            "unknown key 'S7' in spindle (expected: max_rpm, source, S1, S6)") != std::string::npos);
}

}  // TEST_SUITE
