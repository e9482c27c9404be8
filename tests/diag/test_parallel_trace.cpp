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
    const double work = after.work_s - before.work_s, path = after.path_s - before.path_s;
    CHECK(path > 0);
    CHECK(work > path);  // the two short tasks are off the critical path
    CHECK(after.serial_s >= before.serial_s);

    // A background job of two loops, waited for at once: the path grows by
    // at least its longest tasks, the work by all of its tasks.
    diag::set_parallel_trace(true);
    const diag::ParallelTotals b2 = diag::parallel_totals();
    diag::BackgroundJob job;
    {
      diag::AsyncScope in_job(&job);
      for (int k = 0; k < 2; ++k) {
        diag::TracedLoop loop;
        loop.task([&] { sink = sink + spin(100000); });
      }
    }
    diag::traced_wait(&job, [] {});
    const diag::ParallelTotals a2 = diag::parallel_totals();
    diag::set_parallel_trace(false);
    CHECK(a2.loops == b2.loops + 2);
    CHECK(job.path_s.load() > 0);
    CHECK(a2.path_s - b2.path_s >= job.path_s.load() - 1e-12);
    CHECK(a2.work_s - b2.work_s >= job.path_s.load() - 1e-12);
  }
}
