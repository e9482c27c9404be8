// The physics under the golden wall runs (tests/golden/compensate_wall.*,
// simulate_reference.*). Those files are regression snapshots of deflex's own
// output; these cases check what a wrong physics change would break even after
// the snapshots were regenerated: the offset is the predicted error and moves
// the tool into the material, the tool bends as a stepped cantilever, and the
// error left after an offset is the error as written minus that offset.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <regex>
#include <set>

#include "../support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

using test::TempDir;

// The arguments of tests/golden/<name>.args, `more` after them.
std::vector<std::string> golden_args(const std::string& name, const std::vector<std::string>& more) {
  std::vector<std::string> args;
  std::istringstream in(test::read_file("tests/golden/" + name + ".args"));
  for (std::string l; std::getline(in, l);)
    if (!l.empty()) args.push_back(l);
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

// wall.nc: T1 (D 10 mm) at Y-3 along X at Z-10 on the stock box X0..100,
// Y0..20, Z-20..0: a_e 2 mm, a_p 10 mm, the material on +Y. Its rows of
// points.csv on the steady part of the wall, X 20..80 mm.
std::vector<std::size_t> wall_rows(const test::Csv& pts) {
  std::vector<std::size_t> v;
  for (std::size_t i = 0; i < pts.rows.size(); ++i)
    if (pts.num(i, "x_mm") >= 20 && pts.num(i, "x_mm") <= 80) v.push_back(i);
  return v;
}

// The Y word of the blocks N6-N8 (the wall) of a program.
// Where the wall blocks N6-N8 of a written program end in Y (mm), as the
// control reads them: a block that leaves Y out holds the Y before it.
std::vector<double> wall_y_mm(const std::string& program) {
  std::vector<double> ys;
  std::set<std::string> lines;  // line numbers of N6-N8, as `path --lines` prints them
  std::istringstream in(program);
  std::uint32_t n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    if (std::regex_search(line, std::regex("^N[678] X"))) lines.insert(std::to_string(n));
  }
  std::istringstream path(test::run_cli({"path", "--lines", "-"}, program).out);
  for (std::string line, kind; std::getline(path, line);) {
    std::istringstream row(line);
    std::string at;
    double x = 0, y = 0;
    if (row >> at >> kind >> x >> y && lines.count(at)) ys.push_back(y);
  }
  return ys;
}

}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("golden compensate_wall: the offset is the predicted error, into the material") {
    TempDir dir;
    const test::CliResult r = test::run_cli(golden_args("compensate_wall", {"--report", dir / "rep"}));
    REQUIRE(r.rc == 0);
    CHECK(r.out == test::read_file("tests/golden/compensate_wall.stdout"));  // the snapshot's run
    const test::Csv pts = test::read_csv(dir / "rep/points.csv");
    const std::vector<std::size_t> wall = wall_rows(pts);
    REQUIRE(wall.size() >= 100);
    const double tolerance_mm = 0.002, e_mm = pts.num(wall[0], "surface_error_as_written_mm");
    for (std::size_t i : wall) {
      CAPTURE(pts.num(i, "x_mm"));
      // The material pushes the tool out of the cut (-Y) and it bends that way,
      // leaving material on the wall (an undercut, positive) beyond the tolerance.
      CHECK(pts.num(i, "ny") == -1);  // the wall's normal, out of the material
      CHECK(pts.num(i, "Fy_N") < 0);
      CHECK(pts.num(i, "dy_mm") < 0);
      CHECK(pts.num(i, "surface_error_as_written_mm") == doctest::Approx(e_mm));
      // The mirror with gain 1 (P_comp = P - e n): the point moves by the error
      // along -n, into the material (+Y); points.csv prints 4 decimals.
      CHECK(pts.num(i, "offset_mm") == doctest::Approx(-e_mm));
      CHECK(std::fabs(pts.num(i, "y_mm") - (-3 + e_mm)) <= 0.5e-4 + 1e-9);
    }
    CHECK(e_mm > tolerance_mm);
    // The program written: the wall blocks moved by the same amount, to the
    // dialect's 3 decimals.
    const std::vector<double> ys = wall_y_mm(r.out);
    REQUIRE(ys.size() == 3);
    for (double y : ys) CHECK(std::fabs(y - (-3 + e_mm)) <= 0.5e-3 + 1e-9);
  }

  TEST_CASE("golden compensate_wall, the tool alone: its compliance is the stepped Timoshenko cantilever's") {
    // T1 of samples/tools.yaml: D 10 mm, stickout 40 mm, flutes 22 mm long
    // with an equivalent diameter 0.82 D, carbide (E 600 GPa, Poisson 0.22).
    // Loaded and measured at the middle of the cut band (a_p 10 mm: 5 mm above
    // the tip, a = 35 mm from the holder face), a cantilever of I = pi d^4 / 64
    // bends by F / E * int_0^a (a - s)^2 / I(s) ds (Euler-Bernoulli: for one
    // section 64 F a^3 / (3 pi E d^4), Bagci & Yuncuoglu 2017 Eq. 4;
    // shank and flutes as two sections, Smaoui
    // 2011 Eq. 9-17; docs/physics.md), plus the shear term
    // F * int_0^a ds / (k G A(s)), k = 6 (1 + nu) / (7 + 6 nu) for a circle
    // (Cowper 1966, "The shear coefficient in Timoshenko's beam theory").
    const double pi = std::numbers::pi;
    const double E_MPa = 600000, nu = 0.22, G_MPa = E_MPa / (2 * (1 + nu)), k = 6 * (1 + nu) / (7 + 6 * nu);
    const double shank_d_mm = 10, flute_d_mm = 0.82 * 10, a_mm = 35, flute_part_mm = 22 - 5;
    const double shank_part_mm = a_mm - flute_part_mm;
    const double I_shank_mm4 = pi * std::pow(shank_d_mm, 4) / 64, I_flute_mm4 = pi * std::pow(flute_d_mm, 4) / 64;
    const double A_shank_mm2 = pi * shank_d_mm * shank_d_mm / 4, A_flute_mm2 = pi * flute_d_mm * flute_d_mm / 4;
    const double bending_mm_per_N =
        (std::pow(a_mm, 3) - std::pow(flute_part_mm, 3)) / (3 * E_MPa * I_shank_mm4) +
        std::pow(flute_part_mm, 3) / (3 * E_MPa * I_flute_mm4);
    const double shear_mm_per_N = shank_part_mm / (k * G_MPa * A_shank_mm2) + flute_part_mm / (k * G_MPa * A_flute_mm2);
    const double want_mm_per_N = bending_mm_per_N + shear_mm_per_N;
    CHECK(want_mm_per_N == deflex::test::within(5.78e-5, 0.01));  // the worked figure: 5.53e-5 + 0.26e-5

    TempDir dir;
    const test::CliResult r = test::run_cli(golden_args("compensate_wall", {"--tool-only", "--report", dir / "rep"}));
    REQUIRE(r.rc == 0);
    const test::Csv pts = test::read_csv(dir / "rep/points.csv");
    const std::vector<std::size_t> wall = wall_rows(pts);
    REQUIRE(wall.size() >= 100);
    for (std::size_t i : wall) {
      CAPTURE(pts.num(i, "x_mm"));
      // Round and clamped on the axis: the same compliance along X and Y, the
      // deflection along the force (5 % for what the closed form leaves out:
      // the load spread over the band, the 4 decimals of points.csv).
      CHECK(pts.num(i, "dx_mm") / pts.num(i, "Fx_N") == deflex::test::within(want_mm_per_N, 0.05));
      CHECK(pts.num(i, "dy_mm") / pts.num(i, "Fy_N") == deflex::test::within(want_mm_per_N, 0.05));
    }
  }

  TEST_CASE("golden simulate_reference: the error left is the error as written minus the offset") {
    // wall_comp.nc is wall.nc with the wall moved by a fixed offset into the
    // material. Five micrometres more a_e change the force by a few per mille,
    // so the error it leaves is the error as written less that offset (an
    // overcut where the offset is the larger).
    TempDir dir;
    const test::CliResult ref = test::run_cli(golden_args("simulate_reference", {"--report", dir / "comp"}));
    REQUIRE(ref.rc == 0);
    CHECK(ref.out == test::read_file("tests/golden/simulate_reference.stdout"));  // the snapshot's run
    const test::CliResult written =
        test::run_cli({"simulate", "tests/golden/wall.nc", "--stock", "box:0,0,-20,100,20,0", "--tolerance", "0.002",
                       "--threads", "1", "--report", dir / "written"});
    REQUIRE(written.rc == 0);
    const std::vector<double> ys = wall_y_mm(test::read_file("tests/golden/wall_comp.nc"));
    REQUIRE(ys.size() == 3);
    const double offset_mm = ys[0] + 3;
    CHECK(offset_mm > 0);  // into the material, +Y
    const test::Csv w = test::read_csv(dir / "written/points.csv"), c = test::read_csv(dir / "comp/points.csv");
    const std::vector<std::size_t> ww = wall_rows(w), cw = wall_rows(c);
    REQUIRE(ww.size() >= 100);
    REQUIRE(cw.size() >= 100);
    const double e_written_mm = w.num(ww[0], "surface_error_mm");
    CHECK(e_written_mm > 0.002);  // undercut beyond the tolerance
    for (std::size_t i : cw) {
      CAPTURE(c.num(i, "x_mm"));
      CHECK(std::fabs(c.num(i, "surface_error_mm") - (e_written_mm - offset_mm)) <= 1e-4);
    }
  }
}
