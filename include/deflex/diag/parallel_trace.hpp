// The available parallelism of a run, from a trace of its parallel loops.
//
// A run is one thread of control that now and then forks a parallel loop (TBB)
// and waits for it. Each loop, while tracing is on, records its wall time, the
// sum of its tasks' durations and its longest task. Over a stretch of wall time
// T of the controlling thread:
//   work          = T - sum(loop wall) + sum(task durations)
//   critical path = T - sum(loop wall) + sum(longest task of each loop)
// work / critical path is the speed-up that unlimited cores could give the run
// as it is structured (the serial stretches in full, each loop as long as its
// longest task): Amdahl's law measured rather than guessed. It holds for one
// controlling thread; a run with a second (compensate's simulation of the
// program as written) is not traced.
//
// Off by default: then a loop costs one relaxed load. Process-wide, so that the
// command line can show it (-v) without every layer passing it on.
#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>

namespace deflex::diag {

struct ParallelTotals {
  double loop_wall_s = 0;   // sum of the loops' wall times
  double task_sum_s = 0;    // sum of all their tasks' durations
  double task_max_s = 0;    // sum over the loops of the longest task
  std::uint64_t loops = 0;
};

void set_parallel_trace(bool on);
bool parallel_trace_on();
ParallelTotals parallel_totals();

// One parallel loop: made before it forks, told each task's duration (from
// any thread), recorded when it goes out of scope.
class TracedLoop {
 public:
  using Clock = std::chrono::steady_clock;
  TracedLoop() : on_(parallel_trace_on()), start_(on_ ? Clock::now() : Clock::time_point{}) {}
  ~TracedLoop();
  TracedLoop(const TracedLoop&) = delete;
  TracedLoop& operator=(const TracedLoop&) = delete;

  bool on() const { return on_; }
  // Runs f as one task of the loop, timed when tracing.
  template <class F>
  void task(F&& f) {
    if (!on_) {
      f();
      return;
    }
    const Clock::time_point t0 = Clock::now();
    f();
    add(std::chrono::duration<double>(Clock::now() - t0).count());
  }

 private:
  void add(double seconds);
  const bool on_;
  const Clock::time_point start_;
  std::atomic<double> sum_{0}, max_{0};
};

}  // namespace deflex::diag
