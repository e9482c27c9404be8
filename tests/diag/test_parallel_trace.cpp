// The trace behind `-v`'s parallelism line: what one loop records, and
// nothing when tracing is off.
#include <doctest/doctest.h>

#include <cmath>

#include "deflex/diag/parallel_trace.hpp"

using namespace deflex;

namespace {

// Some arithmetic the compiler cannot drop, for a task of measurable length.
double spin(int n) {
  double a = 0;
  for (int i = 1; i <= n; ++i) a += std::sqrt(static_cast<double>(i));
  return a;
}

}  // namespace

TEST_SUITE("diag") {
  TEST_CASE("parallel trace: a loop's tasks, its longest and its wall; nothing when off") {
    volatile double sink = 0;
    diag::set_parallel_trace(false);
    const diag::ParallelTotals before = diag::parallel_totals();
    {
      diag::TracedLoop loop;
      CHECK_FALSE(loop.on());
      loop.task([&] { sink = sink + spin(1000); });
    }
    CHECK(diag::parallel_totals().loops == before.loops);

    diag::set_parallel_trace(true);
    {
      diag::TracedLoop loop;
      REQUIRE(loop.on());
      for (int n : {20000, 200000, 20000}) loop.task([&] { sink = sink + spin(n); });
    }
    diag::set_parallel_trace(false);
    const diag::ParallelTotals after = diag::parallel_totals();
    CHECK(after.loops == before.loops + 1);
    const double sum = after.task_sum_s - before.task_sum_s, longest = after.task_max_s - before.task_max_s;
    const double wall = after.loop_wall_s - before.loop_wall_s;
    CHECK(longest > 0);
    CHECK(sum > longest);   // three tasks, the longest one of them
    CHECK(wall >= sum);     // run one after another on this thread
  }
}
