#include "deflex/diag/parallel_trace.hpp"

#include <algorithm>
#include <mutex>

namespace deflex::diag {

namespace {

using Clock = std::chrono::steady_clock;

std::atomic<bool> g_on{false};
std::mutex g_mutex;  // the state below: one update per loop, not per task
ParallelTotals g_totals;
Clock::time_point g_last;  // the controlling thread's last event
bool g_started = false;
thread_local BackgroundJob* t_job = nullptr;

// The controlling thread's serial stretch since its last event, onto the
// clock and the work (under g_mutex).
void serial_until(Clock::time_point now) {
  if (g_started) {
    const double s = std::chrono::duration<double>(now - g_last).count();
    g_totals.serial_s += s;
    g_totals.work_s += s;
    g_totals.path_s += s;
  }
  g_started = true;
  g_last = now;
}

}  // namespace

void set_parallel_trace(bool on) { g_on.store(on, std::memory_order_relaxed); }
bool parallel_trace_on() { return g_on.load(std::memory_order_relaxed); }

ParallelTotals parallel_totals() {
  std::lock_guard<std::mutex> lock(g_mutex);
  serial_until(Clock::now());
  return g_totals;
}

BackgroundJob::BackgroundJob() {
  if (!parallel_trace_on()) return;
  std::lock_guard<std::mutex> lock(g_mutex);
  serial_until(Clock::now());
  launch_s = g_totals.path_s;
}

AsyncScope::AsyncScope(BackgroundJob* job) : was_(t_job) { t_job = job; }
AsyncScope::~AsyncScope() { t_job = was_; }

void waited(const BackgroundJob& job, double since_s) {
  std::lock_guard<std::mutex> lock(g_mutex);
  // The stretch before the wait was serial work; the wait itself is not.
  const Clock::time_point now = Clock::now();
  serial_until(now - std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(since_s)));
  g_last = now;
  g_totals.path_s = std::max(g_totals.path_s, job.launch_s + job.path_s.load(std::memory_order_relaxed));
}

TracedLoop::TracedLoop() : on_(parallel_trace_on()), job_(t_job) {
  if (!on_ || job_) return;
  std::lock_guard<std::mutex> lock(g_mutex);
  serial_until(Clock::now());
}

void TracedLoop::add(double seconds) {
  sum_.fetch_add(seconds, std::memory_order_relaxed);
  double m = max_.load(std::memory_order_relaxed);
  while (seconds > m && !max_.compare_exchange_weak(m, seconds, std::memory_order_relaxed)) {
  }
}

TracedLoop::~TracedLoop() {
  if (!on_) return;
  const double sum = sum_.load(std::memory_order_relaxed), longest = max_.load(std::memory_order_relaxed);
  std::lock_guard<std::mutex> lock(g_mutex);
  g_totals.work_s += sum;
  ++g_totals.loops;
  if (job_) {
    job_->path_s.fetch_add(longest, std::memory_order_relaxed);
    return;
  }
  // The loop's wall time is not serial: on unlimited cores it lasts its longest task.
  g_last = Clock::now();
  g_totals.path_s += longest;
}

}  // namespace deflex::diag
