#include "deflex/diag/parallel_trace.hpp"

#include <mutex>

namespace deflex::diag {

namespace {

std::atomic<bool> g_on{false};
std::mutex g_mutex;  // the totals: one update per loop, not per task
ParallelTotals g_totals;
thread_local bool t_async = false;

}  // namespace

void set_parallel_trace(bool on) { g_on.store(on, std::memory_order_relaxed); }
bool parallel_trace_on() { return g_on.load(std::memory_order_relaxed); }

ParallelTotals parallel_totals() {
  std::lock_guard<std::mutex> lock(g_mutex);
  return g_totals;
}

AsyncScope::AsyncScope() : was_(t_async) { t_async = true; }
AsyncScope::~AsyncScope() { t_async = was_; }

void add_wait(double seconds) {
  std::lock_guard<std::mutex> lock(g_mutex);
  g_totals.wait_s += seconds;
}

TracedLoop::TracedLoop()
    : on_(parallel_trace_on()), async_(t_async), start_(on_ ? Clock::now() : Clock::time_point{}) {}

void TracedLoop::add(double seconds) {
  sum_.fetch_add(seconds, std::memory_order_relaxed);
  double m = max_.load(std::memory_order_relaxed);
  while (seconds > m && !max_.compare_exchange_weak(m, seconds, std::memory_order_relaxed)) {
  }
}

TracedLoop::~TracedLoop() {
  if (!on_) return;
  const double wall = std::chrono::duration<double>(Clock::now() - start_).count();
  std::lock_guard<std::mutex> lock(g_mutex);
  if (!async_) g_totals.loop_wall_s += wall;
  g_totals.task_sum_s += sum_.load(std::memory_order_relaxed);
  g_totals.task_max_s += max_.load(std::memory_order_relaxed);
  ++g_totals.loops;
}

}  // namespace deflex::diag
