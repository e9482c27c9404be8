// The workpiece's own compliance in simulate and compensate (--fixture): each
// refusal before the program is simulated, named by the setting, and on the
// thin-wall sample the error as the sum of the tool's and the workpiece's
// share, point by point.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "support.hpp"

using namespace deflex;

namespace {

const char* const kFixture = "box:-1,-1,-41,101,61,-39.9";  // the sample's bottom face

job::Settings thin_wall() {
  job::Settings s;
  s.program = "samples/programs/thin_wall.nc";
  s.read.machine = "samples/machines/mill3.yaml";
  s.tool_file = "samples/tools.yaml";
  s.material.material = "Al7075-T6";
  s.material.material_file = "samples/materials.yaml";
  s.stock = "samples/stock/thin_wall.stl";
  s.part.part = "samples/parts/thin_wall.stl";
  s.workholding.fixtures = {kFixture};
  return s;
}

// The same with a coarse mesh and field, enough to see the wall bend (4 mm
// elements, nodes 6 mm apart: seconds instead of the default's minutes).
job::Settings thin_wall_coarse() {
  job::Settings s = thin_wall();
  s.workholding.mesh_mm = 4;
  s.workholding.spacing_mm = 6;
  return s;
}

// The sample with no workpiece model (a rigid part).
job::Settings thin_wall_rigid() {
  job::Settings s = thin_wall();
  s.workholding = {};
  return s;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("--fixture: the part, a material by name with elastic constants, and boxes that hold it, or a located refusal") {
    job::Settings s = thin_wall();
    s.part.part.clear();
    auto o = test::simulate_job(s);
    CHECK(o.error == ErrorKind::settings);
    CHECK(has(o.what, "fixture: "));  // the job's keywords name the settings (the command line: its flags)
    CHECK(has(o.what, "part P"));

    s = thin_wall();
    s.material = {};
    s.material.kt = 800, s.material.kr = 300, s.material.ka = 100;
    o = test::simulate_job(s);
    CHECK(o.error == ErrorKind::settings);
    CHECK(has(o.what, "coefficients alone"));

    s = thin_wall();
    s.workholding.fixtures.push_back("box:200,200,200,210,210,210");
    o = test::simulate_job(s);
    CHECK(o.error == ErrorKind::settings);
    CHECK(has(o.what, "box:200,200,200,210,210,210"));

    s = thin_wall();
    s.workholding.fixtures = {"box:1,2,3"};
    o = test::simulate_job(s);
    CHECK(o.error == ErrorKind::settings);

    s = thin_wall();
    s.workholding.spacing_mm = -1;
    o = test::simulate_job(s);
    CHECK(o.error == ErrorKind::settings);
    CHECK(has(o.what, "workpiece_spacing_mm"));

    // A material entry without elastic: a config error at its line.
    const test::TempDir dir("workpiece-run");
    const std::string lib = (dir.p / "materials.yaml").string();
    test::write_file(lib, "materials:\n  soft:\n    model: mechanistic\n    source: a test\n    K_tc_N_per_mm2: 800\n    K_rc_N_per_mm2: 300\n    K_ac_N_per_mm2: 100\n");
    s = thin_wall();
    s.material.material = "soft";
    s.material.material_file = lib;
    o = test::simulate_job(s);
    CHECK(o.error == ErrorKind::config);
    CHECK(has(o.what, lib + ":3:5: error: material 'soft' has no elastic"));  // the entry's first key
  }

  TEST_CASE("thin-wall sample: the workpiece's share is what a rigid part misses, point by point") {
    // The share is exactly -delta_w . n on each point, the forces being the same.
    const test::TempDir dir("workpiece-share");
    job::Settings rigid = thin_wall_rigid(), held = thin_wall_coarse();
    rigid.report_dir = (dir.p / "rigid").string();
    held.report_dir = (dir.p / "held").string();
    const auto a = test::simulate_job(rigid), b = test::simulate_job(held);
    REQUIRE_MESSAGE(a.ok(), a.what);
    REQUIRE_MESSAGE(b.ok(), b.what);
    CHECK(has(b.err, "workpiece: "));
    {
      // Read in pieces (the program walked once more for the reach): the same points.
      const test::PieceLines pieces("8");
      job::Settings in_pieces = held;
      in_pieces.report_dir = (dir.p / "pieces").string();
      const auto c = test::simulate_job(in_pieces);
      REQUIRE_MESSAGE(c.ok(), c.what);
      CHECK(test::read_file(in_pieces.report_dir + "/points.csv") == test::read_file(held.report_dir + "/points.csv"));
    }
    const test::Csv ra = test::read_csv(rigid.report_dir + "/points.csv"), rb = test::read_csv(held.report_dir + "/points.csv");
    REQUIRE(ra.rows.size() == rb.rows.size());
    double largest_share = 0;
    for (std::size_t i = 0; i < ra.rows.size(); ++i) {
      CHECK(ra.rows[i].at(ra.col("workpiece_dy_mm")).empty());  // no workpiece model: no column values
      if (rb.rows[i].at(rb.col("workpiece_dy_mm")).empty()) continue;  // a point in the air
      const double share = -(rb.num(i, "workpiece_dx_mm") * rb.num(i, "nx") + rb.num(i, "workpiece_dy_mm") * rb.num(i, "ny") +
                             rb.num(i, "workpiece_dz_mm") * rb.num(i, "nz"));
      CHECK(std::fabs(rb.num(i, "surface_error_mm") - (ra.num(i, "surface_error_mm") + share)) < 3e-6);  // 6 decimals
      largest_share = std::max(largest_share, share);
    }
    // The wall (2 mm, 35 mm high) gives way more than the tool: tens of um.
    MESSAGE("thin wall: the workpiece's largest share ", 1000 * largest_share, " um");
    CHECK(largest_share > 0.01);
    CHECK(b.result->figures.error.max_abs > a.result->figures.error.max_abs + 0.005);
  }

  TEST_CASE("thin-wall sample: compensated with the workpiece, judged with it, at most 1 % of points outside") {
    // The mesh and field of the share test above. Judged as a machinist
    // would: `simulate --reference` of the written program with the wall
    // bending. A compensation that ignores the wall changes nothing (the
    // rigid prediction is inside the tolerance) and misses most points.
    const test::TempDir dir("workpiece-compensate");
    auto judged = [&](const std::string& program, const std::string& name) {
      job::Settings s = thin_wall_coarse();
      s.program = program;
      s.reference = "samples/programs/thin_wall.nc";
      s.report_dir = (dir.p / name).string();
      const auto o = test::simulate_job(s);
      REQUIRE_MESSAGE(o.ok(), o.what);
      return o.result->figures.error;
    };
    job::Settings rigid = thin_wall_rigid(), held = thin_wall_coarse();
    rigid.output = (dir.p / "rigid.nc").string();
    held.output = (dir.p / "held.nc").string();
    const auto a = test::compensate_job(rigid), b = test::compensate_job(held);
    REQUIRE_MESSAGE(a.ok(), a.what);
    REQUIRE_MESSAGE(b.ok(), b.what);
    CHECK(test::read_file(rigid.output) == test::read_file("samples/programs/thin_wall.nc"));
    const double tolerance_mm = 0.01;
    const report::ErrorStats missed = judged(rigid.output, "rigid"), kept = judged(held.output, "held");
    MESSAGE("thin wall, judged with the workpiece: compensated without it ", 100 * missed.share_out, " % outside (max ",
            1000 * missed.max_abs, " um); with it ", 100 * kept.share_out, " % (max ", 1000 * kept.max_abs, " um)");
    CHECK(missed.share_out > 0.5);
    CHECK(kept.points >= missed.points);
    CHECK(kept.share_out <= 0.01);
    // The worst point too: within a few micrometres of the tolerance (the
    // mirror's step limit at the arcs' ends), not the wall's tens.
    CHECK(kept.max_abs < 1.5 * tolerance_mm);
  }
}
