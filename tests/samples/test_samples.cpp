// The compensation samples (samples/generate.sh): the committed
// files are what the script writes; each program reads, interprets and checks
// clean on the sample machine and rewrites byte for byte; the ball-end CL points
// lie on the ball offset of the design surface (independent brute-force
// distance, not the script's closed forms); each stock loads and lies the
// allowance above the finished surface; the side wall cuts a_e 2.5, a_p 12 in
// down-milling on the box stock.
#include <doctest/doctest.h>


#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <vector>

#include "../support.hpp"
#include "deflex/engage/simulator.hpp"
#include "deflex/force/cutter.hpp"
#include "deflex/force/tool.hpp"
#include "deflex/profile/yaml.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;
namespace fs = std::filesystem;
using std::numbers::pi;

namespace {

const std::string kSamples = std::string(DEFLEX_SOURCE_DIR) + "/samples/";
const char* const kPrograms[] = {"six_surfaces.nc", "side_wall.nc", "freeform.nc", "thin_wall.nc"};
const char* const kStrategies[] = {"zigzag_0.nc", "zigzag_45.nc", "zigzag_90.nc", "contour.nc"};

// `name` under samples/programs/, or `folder` (e.g. "strategies/").
test::Interpreted interpret_sample(const std::string& name, const std::string& folder = "programs/") {
  const profile::MachineProfile m = profile::load_machine(kSamples + "machines/mill3.yaml");
  return test::interpret_text(test::read_file(kSamples + folder + name), "fanuc", &m);
}

// End points of the compensable G01 moves (the CL points a CAM system wrote).
std::vector<interp::Vec3> cl_points(const test::Interpreted& r) {
  std::vector<interp::Vec3> v;
  for (const auto& m : r.motions)
    if (m.compensable() && m.kind == interp::MotionKind::linear) v.push_back(m.end_mm);
  return v;
}

// The six-surface profile z = f(x) as documented in the program header
// (plane, incline up 20 deg, concave R 40, convex R 40, incline down, plane),
// written here independently of the script; flat beyond the part's ends.
double six_surface_z(double x) {
  const double t = std::tan(20 * pi / 180), h = 35 * t, s = std::sqrt(40.0 * 40 - 20 * 20);
  if (x <= 35) return 0;
  if (x <= 70) return (x - 35) * t;
  if (x <= 110) return h + s - std::sqrt(1600 - (x - 90) * (x - 90));
  if (x <= 150) return h - s + std::sqrt(1600 - (x - 130) * (x - 130));
  if (x <= 185) return h - (x - 150) * t;
  return 0;
}

// Distance from (x, z) to the six-surface profile: dense samples plus the corners.
double six_surface_distance(double x, double z, double reach) {
  double best = 1e300;
  auto at = [&](double u) { best = std::min(best, std::hypot(u - x, six_surface_z(u) - z)); };
  for (double u = x - reach; u <= x + reach; u += 0.005) at(u);
  for (double c : {35.0, 70.0, 110.0, 150.0, 185.0})
    if (std::fabs(c - x) <= reach) at(c);
  return best;
}

double freeform_z(double x, double y) { return 5 * std::sin(2 * pi * x / 60) * std::cos(2 * pi * y / 80); }

// Distance from p to the freeform surface: a coarse grid over the disc, then a fine one round the best.
double freeform_distance(const interp::Vec3& p, double reach) {
  double best = 1e300, bu = p[0], bv = p[1];
  for (double u = p[0] - reach; u <= p[0] + reach; u += 0.1)
    for (double v = p[1] - reach; v <= p[1] + reach; v += 0.1) {
      const double d = std::sqrt((u - p[0]) * (u - p[0]) + (v - p[1]) * (v - p[1]) +
                                 (freeform_z(u, v) - p[2]) * (freeform_z(u, v) - p[2]));
      if (d < best) best = d, bu = u, bv = v;
    }
  for (double u = bu - 0.1; u <= bu + 0.1; u += 0.002)
    for (double v = bv - 0.1; v <= bv + 0.1; v += 0.002) {
      const double dz = freeform_z(u, v) - p[2];
      best = std::min(best, std::sqrt((u - p[0]) * (u - p[0]) + (v - p[1]) * (v - p[1]) + dz * dz));
    }
  return best;
}

// Distance from c to the top of the stock: the cell-centre points (x, y, height)
// within `reach` in XY.
double stock_distance(const stock::ZMap& z, const interp::Vec3& c, double reach) {
  double best = 1e300;
  for (int j = z.iy(c[1] - reach); j <= z.iy(c[1] + reach); ++j)
    for (int i = z.ix(c[0] - reach); i <= z.ix(c[0] + reach); ++i) {
      if (!z.inside(i, j) || z.at(i, j) == stock::no_material) continue;
      const double dx = z.cx(i) - c[0], dy = z.cy(j) - c[1], dz = z.at(i, j) - c[2];
      best = std::min(best, std::sqrt(dx * dx + dy * dy + dz * dz));
    }
  return best;
}

std::string stock_spec(const std::string& yaml) {
  // Through the strict reader, as every YAML file deflex reads: a stray key fails.
  const std::string file = kSamples + "stock/" + yaml;
  const std::string v = yaml::Map(yaml::load_file(file), "stock file", file, {"stock"}).text("stock");
  return v.rfind("box:", 0) == 0 ? v : kSamples + "stock/" + v;
}

}  // namespace

TEST_SUITE("samples") {

TEST_CASE("samples: generate.sh reproduces the committed programs and stocks byte for byte") {
  const fs::path dir = fs::temp_directory_path() / "deflex_samples_regen";
  fs::remove_all(dir);
  const std::string cmd = "sh '" + kSamples + "generate.sh' '" + dir.string() + "' >/dev/null";
  REQUIRE(std::system(cmd.c_str()) == 0);
  for (const char* f : {"programs/six_surfaces.nc", "programs/side_wall.nc", "programs/freeform.nc",
                        "stock/six_surfaces_stock.stl", "stock/freeform_stock.stl", "stock/side_wall.yaml",
                        "stock/six_surfaces.yaml", "stock/freeform.yaml", "strategies/zigzag_0.nc",
                        "strategies/zigzag_45.nc", "strategies/zigzag_90.nc", "strategies/contour.nc",
                        "programs/thin_wall.nc", "parts/thin_wall.stl", "stock/thin_wall.stl", "stock/thin_wall.yaml"}) {
    CAPTURE(f);
    CHECK(test::read_file((dir / f).string()) == test::read_file(kSamples + f));
  }
  fs::remove_all(dir);
}

TEST_CASE("samples: each program checks clean on mill3, interprets, and rewrites byte for byte") {
  for (const char* name : kPrograms) {
    CAPTURE(name);
    const std::string path = kSamples + "programs/" + name;
    const std::string bytes = test::read_file(path);
    CHECK(bytes.size() < 2'000'000);
    CHECK(bytes.find('\r') == std::string::npos);
    const auto chk = test::run_cli({"check", path, "--machine", kSamples + "machines/mill3.yaml"});
    CHECK_MESSAGE(chk.rc == 0, chk.err);
    const auto rw = test::run_cli({"rewrite", path});
    CHECK(rw.rc == 0);
    CHECK(rw.out == bytes);
    const auto r = interpret_sample(name);
    CHECK_MESSAGE(r.errors == 0, r.diagnostics);
    CHECK(r.warnings == 0);
    CHECK(!cl_points(r).empty());
  }
}

TEST_CASE("samples: six-surface CL points are the ball (R 8) offset of the profile; stock 1.0 mm above it") {
  const auto r = interpret_sample("six_surfaces.nc");
  REQUIRE(r.errors == 0);
  const auto pts = cl_points(r);
  REQUIRE(pts.size() > 40000);
  const double R = 8, allowance = 1.0;
  double worst = 0;
  for (std::size_t k = 0; k < pts.size(); k += 3) {
    const auto& p = pts[k];
    worst = std::max(worst, std::fabs(six_surface_distance(p[0], p[2] + R, R + 0.1) - R));
  }
  // CL coordinates are written to 0.001 mm.
  CHECK(worst < 0.001);
  // Every surface is visited at every Y.
  double zmin = 1e300, zmax = -1e300, ymax = 0;
  for (const auto& p : pts) zmin = std::min(zmin, p[2]), zmax = std::max(zmax, p[2]), ymax = std::max(ymax, p[1]);
  CHECK(zmin == doctest::Approx(0));
  CHECK(zmax == deflex::test::within(18.098, 1e-4));
  CHECK(ymax == 78);

  stock::SolidOptions o;
  o.cell_mm = 0.1;
  const stock::ZMap z = stock::make_stock(stock_spec("six_surfaces.yaml"), o);
  CHECK(z.base_z_mm() == doctest::Approx(-40));
  CHECK(std::fabs(z.height_at(20, 39) - allowance) < 0.005);            // plane
  CHECK(std::fabs(z.height_at(130, 39) - (six_surface_z(130) + allowance)) < 0.005);  // top of the convex circle
  CHECK(z.height_at(-1, 39) == stock::no_material);
  CHECK(z.height_at(221, 39) == stock::no_material);
  // The ball centre lies R - allowance from the stock top wherever the ball is over the part.
  int n = 0;
  double lo = 1e300, hi = 0;
  for (std::size_t k = 0; k < pts.size(); k += 101) {
    const auto& p = pts[k];
    if (p[0] < R + 1 || p[0] > 220 - R - 1) continue;
    const double d = stock_distance(z, {p[0], p[1], p[2] + R}, R);
    lo = std::min(lo, d), hi = std::max(hi, d), ++n;
  }
  CHECK(n > 200);
  CHECK(lo > R - allowance - 0.01);
  CHECK(hi < R - allowance + 0.01);
}

TEST_CASE("samples: freeform CL points are the ball (R 5) offset of the surface; stock 0.3 mm above it") {
  const auto r = interpret_sample("freeform.nc");
  REQUIRE(r.errors == 0);
  const auto pts = cl_points(r);
  REQUIRE(pts.size() > 30000);
  const double R = 5, allowance = 0.3;
  double worst = 0;
  for (std::size_t k = 0; k < pts.size(); k += 53) {
    const auto& p = pts[k];
    worst = std::max(worst, std::fabs(freeform_distance({p[0], p[1], p[2] + R}, R + 0.2) - R));
  }
  CHECK(worst < 0.001);

  stock::SolidOptions o;
  o.cell_mm = 0.1;
  const stock::ZMap z = stock::make_stock(stock_spec("freeform.yaml"), o);
  CHECK(z.base_z_mm() == doctest::Approx(-30));
  int n = 0;
  double lo = 1e300, hi = 0;
  for (std::size_t k = 0; k < pts.size(); k += 97) {
    const auto& p = pts[k];
    if (p[0] < R + 1 || p[0] > 120 - R - 1 || p[1] < R + 1 || p[1] > 80 - R - 1) continue;
    const double d = stock_distance(z, {p[0], p[1], p[2] + R}, R);
    lo = std::min(lo, d), hi = std::max(hi, d), ++n;
  }
  CHECK(n > 200);
  // The STL top is a 1.5 x 2 mm grid of the exact offset: within ~0.03 mm of it.
  CHECK(lo > R - allowance - 0.04);
  CHECK(hi < R - allowance + 0.04);
}

TEST_CASE("samples: each strategy checks clean, rewrites byte for byte, rides the ball offset and covers the part") {
  const double R = 5, step = 2.0;
  for (const char* name : kStrategies) {
    CAPTURE(name);
    const std::string path = kSamples + "strategies/" + name;
    const std::string bytes = test::read_file(path);
    const auto chk = test::run_cli({"check", path, "--machine", kSamples + "machines/mill3.yaml"});
    CHECK_MESSAGE(chk.rc == 0, chk.err);
    CHECK(chk.err.empty());
    CHECK(test::run_cli({"rewrite", path}).out == bytes);
    const auto r = interpret_sample(name, "strategies/");
    REQUIRE(r.errors == 0);
    const auto pts = cl_points(r);
    REQUIRE(pts.size() > 10000);
    double worst = 0;
    for (std::size_t k = 0; k < pts.size(); k += 211)
      worst = std::max(worst, std::fabs(freeform_distance({pts[k][0], pts[k][1], pts[k][2] + R}, R + 0.2) - R));
    CHECK(worst < 0.001);
    // Coverage: every point of a 1 mm grid over the part lies within half a
    // step-over (and the 0.5 mm point spacing) of the tool path in XY.
    std::vector<std::vector<interp::Vec3>> bins(125 * 85);
    for (const auto& p : pts)
      if (p[0] > -2 && p[0] < 123 && p[1] > -2 && p[1] < 83)
        bins[static_cast<int>(p[1] + 2) * 125 + static_cast<int>(p[0] + 2)].push_back(p);
    double farthest = 0;
    for (int y = 0; y <= 80; ++y)
      for (int x = 0; x <= 120; ++x) {
        double best = 1e300;
        for (int j = y; j <= y + 3; ++j)  // bins of XY in [-2, +2) around (x, y)
          for (int i = x; i <= x + 3; ++i)
            for (const auto& p : bins[j * 125 + i]) best = std::min(best, std::hypot(p[0] - x, p[1] - y));
        farthest = std::max(farthest, best);
      }
    CHECK(farthest <= std::hypot(step / 2, 0.25) + 1e-6);
  }
}

TEST_CASE("samples: side wall cuts a_e 2.5, a_p 12 in down-milling on its box stock") {
  const std::string spec = stock_spec("side_wall.yaml");
  CHECK(spec == "box:0,-40,-30,100,0,0");
  stock::SolidOptions so;
  so.cell_mm = 0.1;
  stock::ZMap z = stock::make_stock(spec, so);
  const auto r = interpret_sample("side_wall.nc");
  REQUIRE(r.errors == 0);
  const force::Cutter c = force::cutter_of(stiffness::find_tool(stiffness::load_tool_library(kSamples + "tools.yaml"), "T6"));
  CHECK(c.diameter_mm == 12);
  CHECK(c.flutes == 4);
  CHECK(c.helix_deg == 45);
  const auto cs = force::make_slices(c, 0.1, 20);
  engage::SimOptions o;
  o.threads = 1;
  const engage::Process proc{0.1, 6366};
  struct Seen { double y, ae, ap, up; };
  std::vector<Seen> seen;
  engage::Simulator sim(z, cs, proc, o, [&](const engage::CLSample& s, const engage::Metrics& m, const force::Engagement&) {
    const auto& t = s.point.tip_mm;
    if (!s.rapid && t[0] > 30 && t[0] < 70 && std::fabs(t[2] + 12) < 1e-9) seen.push_back({t[1], m.ae_mm, m.ap_mm, m.up_share});
  });
  for (const auto& m : r.motions) sim.run(m);
  sim.finish();
  int pass1 = 0, pass2 = 0;
  for (const Seen& s : seen) {
    CAPTURE(s.y);
    (s.y > 2 ? pass1 : pass2)++;
    CHECK(s.ae == deflex::test::within(2.5, 0.04));   // the second pass sees the first one's wall to a cell
    CHECK(s.ap == deflex::test::within(12, 0.01));
    CHECK(s.up < 0.01);                                   // all removal on the down-milling side
  }
  CHECK(pass1 > 50);
  CHECK(pass2 > 50);
}

}  // TEST_SUITE
