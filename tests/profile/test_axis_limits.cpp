// The machine profile's axis_limits: section (machining time): what it reads,
// its defaults, and its errors at line:col.
#include <doctest/doctest.h>

#include <filesystem>
#include <unistd.h>

#include "../support.hpp"
#include "section_file.hpp"

using namespace deflex;
namespace fs = std::filesystem;

namespace {

struct Profile : test::SectionProfile {
  Profile() : SectionProfile("axis_limits") {}
};

}  // namespace

TEST_SUITE("profile") {

TEST_CASE("axis_limits: the sample machine's figures") {
  const auto m = profile::load_machine("mill3");
  CHECK(m.axis_limits.set);
  CHECK(m.axis_limits.max_feed_mm_per_min == std::array<double, 3>{15000, 15000, 12000});
  CHECK(m.axis_limits.rapid_mm_per_min == std::array<double, 3>{36000, 36000, 30000});
  CHECK(m.axis_limits.acceleration_mm_per_s2 == std::array<double, 3>{2500, 2500, 2000});
  CHECK(m.axis_limits.corner_tolerance_mm == 0.01);
}

TEST_CASE("axis_limits: absent keys keep the defaults, one number serves all axes") {
  Profile p;
  test::write_file(p.file, "name: m\n");
  const auto none = profile::load_machine(p.file);
  CHECK_FALSE(none.axis_limits.set);
  CHECK(none.axis_limits.acceleration_mm_per_s2 == std::array<double, 3>{2000, 2000, 2000});
  CHECK(none.axis_limits.rapid_mm_per_min == std::array<double, 3>{30000, 30000, 24000});
  const auto m = p.load("  acceleration_mm_per_s2: 3000\n");
  CHECK(m.axis_limits.set);
  CHECK(m.axis_limits.acceleration_mm_per_s2 == std::array<double, 3>{3000, 3000, 3000});
  CHECK(m.axis_limits.max_feed_mm_per_min == std::array<double, 3>{10000, 10000, 10000});
  CHECK(m.axis_limits.corner_tolerance_mm == 0.01);
  CHECK(p.load("  corner_tolerance_mm: 0.05\n").axis_limits.corner_tolerance_mm == 0.05);
}

TEST_CASE("axis_limits: unknown keys are errors at their line:col") {
  Profile p;
  CHECK(p.error("  max_jerk_mm_per_s3: 1e5\n")
            .find(p.file + ":3:3: error: unknown key 'max_jerk_mm_per_s3' in axis_limits (expected: "
                           "max_feed_mm_per_min, rapid_mm_per_min, acceleration_mm_per_s2, corner_tolerance_mm)") == 0);
  CHECK(p.error("  rapid_mm_per_min: {x: 1, y: 1, a: 1}\n")
            .find(p.file + ":3:34: error: unknown key 'a' in axis_limits.rapid_mm_per_min") == 0);
}

TEST_CASE("axis_limits: negative, zero, NaN, infinite, missing or mistyped values are errors at their line:col") {
  Profile p;
  CHECK(p.error("  max_feed_mm_per_min: {x: 1000, y: 1000, z: 500}\n  acceleration_mm_per_s2: {x: 1, y: -2, z: 3}\n")
            .find(p.file + ":4:37: error: axis_limits.acceleration_mm_per_s2.y must be > 0") == 0);
  CHECK(p.error("  corner_tolerance_mm: 0\n").find(p.file + ":3:24: error: corner_tolerance_mm must be > 0") == 0);
  CHECK(p.error("  rapid_mm_per_min: -1\n").find(p.file + ":3:21: error: axis_limits.rapid_mm_per_min must be > 0") ==
        0);
  CHECK(p.error("  rapid_mm_per_min: .nan\n")
            .find(p.file + ":3:21: error: axis_limits.rapid_mm_per_min must be finite") == 0);
  CHECK(p.error("  max_feed_mm_per_min: {x: .inf, y: 1, z: 1}\n")
            .find(p.file + ":3:28: error: axis_limits.max_feed_mm_per_min.x must be finite") == 0);
  CHECK(p.error("  max_feed_mm_per_min: {x: 1, y: 1}\n")
            .find(p.file + ":3:24: error: missing key 'z' in axis_limits.max_feed_mm_per_min") == 0);
  CHECK(p.error("  max_feed_mm_per_min: [1, 2, 3]\n")
            .find(p.file + ":3:24: error: axis_limits.max_feed_mm_per_min must be {x: .., y: .., z: ..}") == 0);
  CHECK(p.error("  - 1\n").find(p.file + ":3:3: error: axis_limits must be a map") == 0);
}

TEST_CASE("axis_limits: a bad value stops any command with exit 3") {
  Profile p;
  test::write_file((p.dir / "p.nc").string(), "G21 G90 G54\nG0 X0 Y0 Z10.\nM30\n");
  test::write_file(p.file, "name: m\naxis_limits:\n  acceleration_mm_per_s2: -1\n");
  const auto r = test::run_cli({"check", (p.dir / "p.nc").string(), "--machine", p.file});
  CHECK(r.rc == 3);
  CHECK(r.err.find(p.file + ":3:27: error: axis_limits.acceleration_mm_per_s2 must be > 0") == 0);
}

}  // TEST_SUITE
