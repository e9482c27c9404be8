// The available parallelism of a run, from a trace of its task graph.
//
// A run is one thread of control that forks parallel loops (TBB) and waits for
// them, and launches background jobs (the simulator's commits) that it waits
// for later. While tracing is on, every task's duration is recorded, and the
// trace replays the run on unlimited cores: a virtual clock of the controlling
// thread advances by its serial stretches as measured, by each loop's longest
// task (not its wall time), and at a wait for a background job to the job's
// own finish (its launch plus its loops' longest tasks), if that is later.
//   work          = the serial stretches + every task's duration
//   critical path = the virtual clock
// work / critical path is the speed-up unlimited cores could give the run as
// it is structured: Amdahl's law measured rather than guessed, with the
// overlap the background jobs allow. It holds for one controlling thread; a
// run with a second (compensate's simulation of the program as written) is
// not reported.
//
// Off by default: then a loop costs one relaxed load. Process-wide, so that the
// command line can show it (-v) without every layer passing it on.
#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>

namespace deflex::diag {

struct ParallelTotals {
  double work_s = 0;  // serial stretches and tasks
  double path_s = 0;  // the virtual clock: the critical path
  double serial_s = 0;
  std::uint64_t loops = 0;
};

void set_parallel_trace(bool on);
bool parallel_trace_on();
// The totals up to now (the serial stretch since the last event included);
// called on the controlling thread.
ParallelTotals parallel_totals();

// A background job: made on the controlling thread when it is launched, run
// under its AsyncScope (the job's loops count towards it, not towards the
// controlling thread), waited for with traced_wait.
class BackgroundJob {
 public:
  BackgroundJob();  // at launch
  double launch_s = 0;                 // the virtual clock at launch
  std::atomic<double> path_s{0};       // its loops' longest tasks
};

// Marks the current thread as running the job while it lives.
class AsyncScope {
 public:
  explicit AsyncScope(BackgroundJob* job);
  ~AsyncScope();
  AsyncScope(const AsyncScope&) = delete;
  AsyncScope& operator=(const AsyncScope&) = delete;

 private:
  BackgroundJob* was_;
};

void waited(const BackgroundJob& job, double since_s);

// The controlling thread waiting for a job (may be null: untraced): f() timed.
template <class F>
void traced_wait(const BackgroundJob* job, F&& f) {
  if (!job || !parallel_trace_on()) {
    f();
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  f();
  waited(*job, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
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
  BackgroundJob* const job_;  // in a background job: its loops count there
  std::atomic<double> sum_{0}, max_{0};
};

}  // namespace deflex::diag
