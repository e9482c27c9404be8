// In-process timings (Google Benchmark) of what whole-process timings cannot
// show: deflex starts in ~0.05 s (loading OpenCASCADE and its other libraries), far more than
// the beam table it computes. Build: cmake --build build --target deflex_bench;
// run from the repository root: build/deflex_bench.
#include <benchmark/benchmark.h>

#include "deflex/force/cutter.hpp"
#include "deflex/force/engagement.hpp"
#include "deflex/force/mechanistic.hpp"
#include "deflex/stiffness/beam.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/tool.hpp"

using namespace deflex;

// The whole C(h) table of the paper-001 tool on the sample machine (target < 10 ms).
static void BM_beam_table_T5_mill3(benchmark::State& st) {
  const auto lib = stiffness::load_tool_library("samples/tools.yaml");
  const auto m = stiffness::load_machine_stiffness("samples/machines/mill3.yaml");
  const auto& t = stiffness::find_tool(lib, "T5");
  for (auto _ : st) benchmark::DoNotOptimize(stiffness::beam_compliance(t, m, false));
}
BENCHMARK(BM_beam_table_T5_mill3)->Unit(benchmark::kMillisecond);

// Forces over one revolution at a ball-end finishing point (D10, a_p 0.5, a_e 0.5).
static void BM_forces_ball_D10_finish(benchmark::State& st) {
  force::Cutter c;
  c.type = stock::EndShape::ball;
  c.diameter_mm = 10;
  c.flutes = 2;
  c.helix_deg = 30;
  c.flute_length_mm = 15;
  const auto cs = force::make_slices(c, 0.05, 1.0);
  force::Engagement e;
  force::simple_engagement(cs, 0.5, 0.5, force::MillingMode::down, e);
  const auto grid = force::make_angle_grid(360);
  std::vector<force::Vec3> out(360);
  const force::Coefficients k{800, 300, 100, 20, 15, 5};
  for (auto _ : st) {
    force::revolution_forces(cs, grid, k, 0.05, e, out);
    benchmark::DoNotOptimize(force::summarize(out));
  }
}
BENCHMARK(BM_forces_ball_D10_finish)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
