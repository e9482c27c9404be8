// The workpiece's own compliance in simulate and compensate (--fixture): each
// refusal before the program is simulated, named by the setting, and on the
// thin-wall sample the error as the sum of the tool's and the workpiece's
// share, point by point.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <cstdint>
#include <vector>
#include <limits>

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

  TEST_CASE("thin-wall sample in stages: the material still to come off stiffens the wall, as (2 / 2.1)^3 at the top") {
    // The in-process stock contains the finished part, and an earlier stock
    // the later one: the workpiece's share at every point can only fall as
    // more of the stock is kept (a body with more material is stiffer under
    // the same clamp). At the first pass the wall is still 2.1 mm thick all
    // the way up (its 0.1 mm allowance on): a cantilever's compliance goes as
    // 1 / t^3, so its largest share is (2 / 2.1)^3 = 0.864 of the finished
    // wall's.
    const test::TempDir dir("workpiece-stages");
    auto shares = [&](int stages, std::string& err) {
      job::Settings s = thin_wall_coarse();
      s.workholding.stages = stages;
      s.report_dir = (dir.p / std::to_string(stages)).string();
      const auto o = test::simulate_job(s);
      REQUIRE_MESSAGE(o.ok(), o.what);
      err = o.err;
      const test::Csv c = test::read_csv(s.report_dir + "/points.csv");
      std::vector<std::pair<std::uint32_t, double>> v;  // line, share (NaN: in the air)
      for (std::size_t i = 0; i < c.rows.size(); ++i) {
        double share = std::nan("");
        if (!c.rows[i].at(c.col("workpiece_dy_mm")).empty())
          share = -(c.num(i, "workpiece_dx_mm") * c.num(i, "nx") + c.num(i, "workpiece_dy_mm") * c.num(i, "ny") +
                    c.num(i, "workpiece_dz_mm") * c.num(i, "nz"));
        v.emplace_back(static_cast<std::uint32_t>(c.num(i, "line")), share);
      }
      return v;
    };
    std::string e0, e1, e2;
    const auto finished = shares(0, e0), one = shares(1, e1), two = shares(2, e2);
    {
      // Read in pieces of 5 lines (a stage begins inside a piece): the same points.
      const test::PieceLines pieces("5");
      job::Settings s = thin_wall_coarse();
      s.workholding.stages = 2;
      s.report_dir = (dir.p / "pieces").string();
      const auto o = test::simulate_job(s);
      REQUIRE_MESSAGE(o.ok(), o.what);
      CHECK(test::read_file(s.report_dir + "/points.csv") == test::read_file((dir.p / "2").string() + "/points.csv"));
    }
    CHECK(!has(e0, "workpiece stage"));
    CHECK(has(e1, "workpiece stage 1 of 1, the in-process stock at line "));
    CHECK(has(e2, "workpiece stage 2 of 2, the in-process stock at line "));
    REQUIRE(finished.size() == two.size());
    REQUIRE(one.size() == two.size());
    const double slack_mm = 1e-5;  // points.csv's 6 decimals, the fields' nodes
    // The line where the finished wall gives way most: the top level's pass.
    std::uint32_t top = 0;
    double most = 0;
    for (std::size_t i = 0; i < two.size(); ++i) {
      if (std::isnan(two[i].second)) continue;
      if (finished[i].second > most) most = finished[i].second, top = finished[i].first;
      CHECK(one[i].second <= two[i].second + slack_mm);
      CHECK(two[i].second <= finished[i].second + slack_mm);
    }
    double top_finished = 0, top_staged = 0;
    for (std::size_t i = 0; i < two.size(); ++i)
      if (two[i].first == top && !std::isnan(two[i].second)) {
        top_finished = std::max(top_finished, finished[i].second);
        top_staged = std::max(top_staged, two[i].second);
      }
    MESSAGE("the pass where the wall gives way most (line ", top, "): its largest share ", 1000 * top_finished, " um finished, ",
            1000 * top_staged, " um in stages");
    REQUIRE(top_finished > 0.01);
    CHECK(top_staged / top_finished == deflex::test::within(std::pow(2.0 / 2.1, 3), 0.03));
  }

  TEST_CASE("workpiece stages: a count out of range is refused before the program is checked") {
    // A program with an error in it: the setting is what is refused (exit 2),
    // not the program (exit 4), so nothing is swept or meshed first.
    const test::TempDir dir("workpiece-stages-refused");
    job::Settings s = thin_wall();
    s.program = test::edited_copy(dir, "samples/programs/thin_wall.nc", "bad.nc", "N24 G01 X82.\n", "N24 G999 X82.\n");
    const auto bad = test::simulate_job(s);
    CHECK(bad.error == ErrorKind::input);  // the program's own error, with a valid count
    for (const int stages : {-1, job::kMaxWorkpieceStages + 1}) {
      s.workholding.stages = stages;
      const auto o = test::simulate_job(s);
      CHECK(o.error == ErrorKind::settings);
      CHECK(has(o.what, "workpiece_stages"));
    }
  }
}
