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
// Background jobs (the simulator's commits, which run beside the controlling
// thread): their loops (AsyncScope) add their tasks to the work and their
// longest task to the critical path, and the controlling thread's waits for
// them (TracedWait) are not counted as serial time. So the critical path is
// counted as if each background job ran alone: an upper bound, and the
// parallelism a lower bound.
//
// Off by default: then a loop costs one relaxed load. Process-wide, so that the
// command line can show it (-v) without every layer passing it on.
#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>

namespace deflex::diag {

struct ParallelTotals {
  double loop_wall_s = 0;   // sum of the controlling thread's loops' wall times
  double wait_s = 0;        // its waits for background jobs
  double task_sum_s = 0;    // sum of all the loops' tasks' durations
  double task_max_s = 0;    // sum over the loops of the longest task
  std::uint64_t loops = 0;
};

void set_parallel_trace(bool on);
bool parallel_trace_on();
ParallelTotals parallel_totals();

// Marks the current thread as running a background job while it lives.
class AsyncScope {
 public:
  AsyncScope();
  ~AsyncScope();
  AsyncScope(const AsyncScope&) = delete;
  AsyncScope& operator=(const AsyncScope&) = delete;

 private:
  bool was_;
};

void add_wait(double seconds);

// The controlling thread waiting for a background job: f() timed when tracing.
template <class F>
void traced_wait(F&& f) {
  if (!parallel_trace_on()) {
    f();
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  f();
  add_wait(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

// One parallel loop: made before it forks, told each task's duration (from
// any thread), recorded when it goes out of scope.
class TracedLoop {
 public:
  using Clock = std::chrono::steady_clock;
  TracedLoop();
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
  const bool async_;  // in a background job
  const Clock::time_point start_;
  std::atomic<double> sum_{0}, max_{0};
};

}  // namespace deflex::diag
