// Speed benchmark, skipped by default. Run with
//   build/deflex_tests -tc="bench*" --no-skip      (bench/engage.sh)
// A ball-end D10 finishing pass on the default Z-map (0.05 mm): zig-zag along X
// over a 100 x 60 mm box, a_p 0.3 mm, step-over 0.5 mm; forces over one
// revolution (360 steps, 400 slices of 0.05 mm) at every CL point.
#include <doctest/doctest.h>

#include "../support.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "deflex/engage/simulator.hpp"
#include "deflex/force/mechanistic.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;
using namespace deflex::engage;

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

interp::Motion g1(stock::Point3 a, stock::Point3 b) { return test::linear_motion(a, b, 2000); }

// Zig-zag passes; `seg_mm` > 0 splits each pass into CAM-like short G1 moves
// following a gentle wave z = -a_p + 0.2 sin(x / 5) (a finishing path over a
// free-form surface), else one straight G1 per pass.
std::vector<interp::Motion> finishing_path(int passes, double seg_mm) {
  std::vector<interp::Motion> ms;
  const double ap = 0.3, step = 0.5, x0 = -6, x1 = 106;
  auto zf = [&](double x) { return seg_mm > 0 ? -ap + 0.2 * std::sin(x / 5) : -ap; };
  stock::Point3 p{x0, 5, zf(x0)};
  for (int k = 0; k < passes; ++k) {
    const double y = 5 + k * step;
    const bool fwd = k % 2 == 0;
    const double xa = fwd ? x0 : x1, xb = fwd ? x1 : x0;
    if (k > 0) {
      const stock::Point3 q{xa, y, zf(xa)};
      ms.push_back(g1(p, q));
      p = q;
    }
    const int n = seg_mm > 0 ? static_cast<int>((x1 - x0) / seg_mm) : 1;
    for (int s = 1; s <= n; ++s) {
      const double x = xa + (xb - xa) * s / n;
      const stock::Point3 q{x, y, zf(x)};
      ms.push_back(g1(p, q));
      p = q;
    }
  }
  return ms;
}

void measure(const char* name, const std::vector<interp::Motion>& path, SimOptions so,
             double cell_mm = stock::default_cell_mm, stock::EndShape type = stock::EndShape::ball,
             double corner_mm = 0) {
  force::Cutter c;
  c.type = type;
  c.corner_radius_mm = corner_mm;
  c.diameter_mm = 10;
  c.flutes = 2;
  c.helix_deg = 30;
  c.flute_length_mm = 20;
  const force::CutterSlices cs = force::make_slices(c, 0.05, 20);
  const force::AngleGrid grid = force::make_angle_grid(360);
  force::Coefficients k;
  k.Ktc_N_per_mm2 = 3600;  // Smaoui 2011 C35 (docs/physics.md, 'Cutting coefficients')
  k.Krc_N_per_mm2 = 3400;
  k.Kac_N_per_mm2 = 500;
  const Process proc{0.1, 8000};
  const auto blank = stock::parse_box("box:0,0,-20,100,60,0");
  std::printf("%s\n", name);
  for (const int threads : {1, 0}) {
    so.threads = threads;
    stock::ZMap z = stock::zmap_from_box(blank, cell_mm);
    std::vector<force::Vec3> F(360);
    std::size_t n = 0, engaged = 0;
    double t_forces = 0, peak = 0;
    Simulator sim(z, cs, proc, so, [&](const CLSample&, const Metrics& m, const force::Engagement& e) {
      ++n;
      engaged += !m.air_cut;
      const auto t0 = Clock::now();
      force::revolution_forces(cs, grid, k, proc.fz_mm, e, F);
      t_forces += seconds_since(t0);
      for (const auto& f : F) peak = std::max(peak, f.norm());
    });
    const auto t0 = Clock::now();
    for (const interp::Motion& m : path) sim.run(m);
    sim.finish();
    const double t_all = seconds_since(t0);
    CHECK(engaged > n / 2);
    CHECK(peak > 0);
    const double N = static_cast<double>(n);
    std::printf("  threads %-7s %zu CL points (%zu engaged), peak |F| %.0f N\n", threads ? "1" : "default", n, engaged, peak);
    std::printf("    engagement alone              %9.0f CL points/s\n", N / sim.engage_seconds());
    std::printf("    forces alone (sequential)     %9.0f CL points/s\n", N / t_forces);
    std::printf("    engagement + forces           %9.0f CL points/s\n", N / (sim.engage_seconds() + t_forces));
    std::printf("    sweeps into the Z-map         %9.3f s\n", sim.sweep_seconds());
    std::printf("    whole simulation              %9.0f CL points/s (%.2f s)\n", N / t_all, t_all);
    std::printf("    stock memory                  %9.1f MB\n", z.allocated_bytes() / 1e6);
  }
}

}  // namespace

TEST_SUITE("engage") {

TEST_CASE("bench engage: ball D10 finishing, long G1 passes, CL every 0.1 mm" * doctest::skip()) {
  SimOptions so;
  so.path.cl_spacing_mm = 0.1;
  measure("long G1 passes, CL every 0.1 mm", finishing_path(20, 0), so);
}

TEST_CASE("bench engage: ball D10 finishing, CAM-like 0.5 mm G1 segments on a wave" * doctest::skip()) {
  SimOptions so;
  so.path.cl_spacing_mm = 0.5;
  measure("CAM-like 0.5 mm G1 segments on a wave", finishing_path(20, 0.5), so);
}

TEST_CASE("bench engage: the same on a 0.1 mm Z-map (roughing resolution)" * doctest::skip()) {
  SimOptions so;
  so.path.cl_spacing_mm = 0.5;
  measure("CAM-like 0.5 mm G1 segments on a wave, 0.1 mm cells", finishing_path(20, 0.5), so, 0.1);
}

TEST_CASE("bench engage: bull nose D10 r1, CAM-like 0.5 mm G1 segments on a wave" * doctest::skip()) {
  SimOptions so;
  so.path.cl_spacing_mm = 0.5;
  measure("bull nose D10 r1, CAM-like 0.5 mm G1 segments on a wave", finishing_path(20, 0.5), so,
          stock::default_cell_mm, stock::EndShape::bull, 1.0);
}

}  // TEST_SUITE
