#include "deflex/engage/simulator.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/diag/parallel_trace.hpp"
#include "deflex/stock/sweep.hpp"

namespace deflex::engage {

namespace {

// The sweeps a probe puts on the pending list for the call (an arc's chords,
// the motions ahead) come off again however the call ends.
class PendingForCall {
 public:
  explicit PendingForCall(std::vector<stock::LineSweep>& p) : p_(p), keep_(p.size()) {}
  ~PendingForCall() { p_.erase(p_.begin() + static_cast<std::ptrdiff_t>(keep_), p_.end()); }
  PendingForCall(const PendingForCall&) = delete;
  PendingForCall& operator=(const PendingForCall&) = delete;

 private:
  std::vector<stock::LineSweep>& p_;
  std::size_t keep_;
};

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double dist(const Point3& a, const Point3& b) {
  return std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
}

// b moved back toward a by `trim` (a itself when the piece is shorter).
Point3 trimmed(const Point3& a, const Point3& b, double trim) {
  const double l = dist(a, b);
  if (l <= trim) return a;
  const double t = (l - trim) / l;
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

// A line is one sweep from its start, an arc one per chord.
bool is_line(const interp::Motion& m) {
  return m.kind == interp::MotionKind::rapid || m.kind == interp::MotionKind::linear;
}

// The sweep of motion m (vertices v) up to just before its sample k, the
// stock's "current" part when k is evaluated: run(), probe() and probe_ahead()
// must build the same one for their points to agree bit for bit.
stock::LineSweep sweep_before(const stock::ToolProfile& tool, const interp::Motion& m, std::span<const Point3> v,
                              std::size_t k, double trim_mm) {
  const Point3& from = is_line(m) ? v[0] : v[k - 1];
  return stock::LineSweep(tool, from, trimmed(from, v[k], trim_mm));
}

// The simulator's arena (SimOptions::threads > 0), made once: an arena made
// per batch costs TBB a thread each time (55,000 threads created and ended in
// 45 s of a 1M-block compensation, a quarter of its time in the kernel).
template <class F>
void in_arena(tbb::task_arena* arena, F&& f) {
  if (arena) arena->execute(f);
  else f();
}

}  // namespace

Simulator::Simulator(stock::ZMap& z, const force::CutterSlices& cs, const Process& p, const SimOptions& o,
                     PointSink sink)
    : z_(z), eng_(cs, o.engage), proc_(p), o_(o), sink_(std::move(sink)) {
  keep_mm_ = o.keep_mm > 0 ? o.keep_mm : 2 * cs.cutter.diameter_mm + 4 * z.grid().cell_mm;
  if (o.threads > 0) arena_ = std::make_unique<tbb::task_arena>(o.threads);
  batch_mm_ = o.batch_mm > 0 ? o.batch_mm : cs.cutter.diameter_mm;
  if (o.max_pending < 1 || o.max_batch < 1) throw Error(ErrorKind::config, "simulation: max_pending and max_batch must be >= 1");
  if (!(o.trim_mm > 0)) throw Error(ErrorKind::config, "simulation: trim_mm must be > 0");
  if (o.threads < 0) throw Error(ErrorKind::config, "simulation: threads must be >= 0");
}

Simulator::~Simulator() {
  if (!commits_) return;
  try {
    wait_commit();
  } catch (...) {  // a destructor does not throw; the run failed already
  }
}

Simulator::TileBox Simulator::tiles_of(double x0_mm, double y0_mm, double x1_mm, double y1_mm) const {
  // Floor division: cells left of or below the grid fall in tile -1, which no
  // tile of the grid meets.
  auto tile = [](int cell) { return cell >= 0 ? cell / stock::ZMap::tile_cells : -1; };
  return {tile(z_.ix(x0_mm)), tile(z_.ix(x1_mm)), tile(z_.iy(y0_mm)), tile(z_.iy(y1_mm))};
}

Simulator::TileBox Simulator::read_box(const Point3& tip_mm) const {
  // The engagement reads the cells within the tool's radius and their
  // neighbours (bilinear lookups); the sample work the stock around the tip.
  const double r = eng_.tool().radius_mm + 2 * z_.grid().cell_mm;
  return tiles_of(tip_mm[0] - r, tip_mm[1] - r, tip_mm[0] + r, tip_mm[1] + r);
}

void Simulator::wait_commit() {
  if (!commit_running_) return;
  commit_running_ = false;
  diag::traced_wait(commit_job_.get(), [&] { in_arena(arena_.get(), [&] { commits_->wait(); }); });
  removed_ += commit_removed_;
  t_sweep_ += commit_s_;
  committing_.clear();
}

void Simulator::wait_commit_if(const TileBox& reads) {
  if (commit_running_ && reads.meets(commit_box_)) wait_commit();
}

void Simulator::evaluate_batch() {
  const std::size_t n = batch_.size();
  if (n == 0) return;
  if (commit_running_) {
    TileBox reads = read_box(batch_[0].cl.point.tip_mm);
    for (std::size_t i = 1; i < n; ++i) reads.join(read_box(batch_[i].cl.point.tip_mm));
    wait_commit_if(reads);
  }
  const double t0 = now_s();
  if (metrics_.size() < n) {
    metrics_.resize(n);
    engs_.resize(n);
  }
  auto one = [&](std::size_t i) {
    const Sample& s = batch_[i];
    const StockView view{&z_, std::span<const stock::LineSweep>(pend_.data(), s.pending), &s.current};
    if (o_.evaluate) metrics_[i] = eng_.evaluate(view, s.cl.point, proc_, engs_[i]);
    else metrics_[i] = Metrics{}, engs_[i] = force::Engagement{};
    if (work_) work_(i, s.cl, metrics_[i], engs_[i]);
  };
  // Traced as one loop of independent samples whatever the threads: the
  // structure's parallelism (diag/parallel_trace.hpp), not this run's.
  {
    diag::TracedLoop loop;
    auto task = [&](std::size_t i) { loop.task([&] { one(i); }); };
    if (o_.threads == 1 || n < 4) {
      for (std::size_t i = 0; i < n; ++i) task(i);
    } else {
      in_arena(arena_.get(), [&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 2), [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t i = r.begin(); i != r.end(); ++i) task(i);
        });
      });
    }
  }
  t_engage_ += now_s() - t0;
  // A sink may read the stock anywhere.
  wait_commit();
  if (sink_)
    for (std::size_t i = 0; i < n; ++i) {
      sink_slot_ = i;
      sinking_ = &batch_[i];
      sink_(batch_[i].cl, metrics_[i], engs_[i]);
    }
  sinking_ = nullptr;
  samples_ += n;
  batch_.clear();
}

StockView Simulator::sink_view() const {
  if (!sinking_) throw Error(ErrorKind::internal, "simulation: sink_view() outside a sink call");
  return {&z_, std::span<const stock::LineSweep>(pend_.data(), sinking_->pending), &sinking_->current};
}

void Simulator::commit_old(bool all) {
  std::size_t c = 0;
  while (c < pend_.size() &&
         (all || s_ - pend_end_s_[c] > keep_mm_ || pend_.size() - c > o_.max_pending))
    ++c;
  if (c == 0) {
    if (all) wait_commit();
    return;
  }
  wait_commit();  // one commit at a time, in order
  committing_.assign(pend_.begin(), pend_.begin() + static_cast<std::ptrdiff_t>(c));
  const bool start_cut = have_committed_end_ && committing_[0].a() == committed_end_;
  have_committed_end_ = true;
  committed_end_ = committing_.back().b();
  pend_.erase(pend_.begin(), pend_.begin() + static_cast<std::ptrdiff_t>(c));
  pend_end_s_.erase(pend_end_s_.begin(), pend_end_s_.begin() + static_cast<std::ptrdiff_t>(c));
  double x0 = committing_[0].x_min(), x1 = committing_[0].x_max(), y0 = committing_[0].y_min(),
         y1 = committing_[0].y_max();
  for (const stock::LineSweep& l : committing_) {
    x0 = std::min(x0, l.x_min());
    x1 = std::max(x1, l.x_max());
    y0 = std::min(y0, l.y_min());
    y1 = std::max(y1, l.y_max());
  }
  commit_box_ = tiles_of(x0, y0, x1, y1);
  if (!commits_) commits_ = std::make_unique<tbb::task_group>();
  commit_running_ = true;
  commit_job_ = diag::parallel_trace_on() ? std::make_unique<diag::BackgroundJob>() : nullptr;
  in_arena(arena_.get(), [&] {
    commits_->run([this, start_cut] {
      const diag::AsyncScope background(commit_job_.get());
      const double t0 = now_s();
      commit_removed_ = stock::sweep_lines(z_, committing_, start_cut);
      commit_s_ = now_s() - t0;
    });
  });
  if (all || !o_.commit_beside) wait_commit();
}

void Simulator::flush() {
  evaluate_batch();
  batch_start_s_ = s_;
  commit_old(false);
}

void Simulator::finish() {
  evaluate_batch();
  commit_old(true);
}

void Simulator::run(const interp::Motion& m) {
  const std::vector<Point3> v = motion_vertices(m, o_.path);
  const bool line = is_line(m);
  const bool sample = sink_ && (m.kind != interp::MotionKind::rapid || o_.sample_rapids);
  const stock::ToolProfile& tool = eng_.tool();
  const std::size_t motion_index = motions_++;
  const int n = static_cast<int>(v.size()) - 1;
  for (int k = 1; k <= n; ++k) {
    const Point3& vk = v[static_cast<std::size_t>(k)];
    // The XY feed direction is carried across plunges whether sampled or not
    // (probe() reads it).
    const CLSample cl = cl_sample(m, v, static_cast<std::size_t>(k), feed_);
    if (sample) {
      batch_.push_back(Sample{cl, sweep_before(tool, m, v, static_cast<std::size_t>(k), o_.trim_mm), pend_.size()});
      batch_.back().cl.motion = motion_index;
    }
    s_ += dist(v[static_cast<std::size_t>(k - 1)], vk);
    if (!line) {
      pend_.emplace_back(tool, v[static_cast<std::size_t>(k - 1)], vk);
      pend_end_s_.push_back(s_);
    }
    if (batch_.size() >= o_.max_batch) flush();  // mid-line is fine: the line is not pending yet
  }
  if (line) {
    pend_.emplace_back(tool, v[0], v.back());
    pend_end_s_.push_back(s_);
  }
  if (s_ - batch_start_s_ >= batch_mm_) flush();
}

Metrics Simulator::probe(const interp::Motion& m, std::span<const Point3> v, int k, CLSample& cl,
                         force::Engagement& out) {
  const int n = static_cast<int>(v.size()) - 1;
  if (k < 1 || k > n) throw Error(ErrorKind::internal, "simulation: probe of a sample outside the motion");
  const bool line = is_line(m);
  const stock::ToolProfile& tool = eng_.tool();
  const stock::LineSweep current = sweep_before(tool, m, v, static_cast<std::size_t>(k), o_.trim_mm);
  // An arc's chords before the sample are pending while it is evaluated; they
  // go on the pending list for the call and come off again.
  const PendingForCall restore(pend_);
  if (!line)
    for (int c = 1; c < k; ++c) pend_.emplace_back(tool, v[static_cast<std::size_t>(c - 1)], v[static_cast<std::size_t>(c)]);
  // The sample as run() would make it, the feed direction carried over the
  // vertices before it.
  std::array<double, 2> feed = feed_;
  for (int c = 1; c <= k; ++c) cl = cl_sample(m, v, static_cast<std::size_t>(c), feed);
  cl.motion = motions_;
  wait_commit_if(read_box(cl.point.tip_mm));
  const double t0 = now_s();
  const StockView view{&z_, std::span<const stock::LineSweep>(pend_.data(), pend_.size()), &current};
  const Metrics mt = eng_.evaluate(view, cl.point, proc_, out);
  t_engage_ += now_s() - t0;
  return mt;
}

std::size_t Simulator::probe_ahead(std::span<const interp::Motion> ms, const AheadWork& work) {
  if (sink_) throw Error(ErrorKind::internal, "simulation: probe_ahead() with a sink");
  // The samples as run() would batch them, the sweeps pending before each
  // put on the list for the call (and taken off again): the same views
  // probe() builds one at a time.
  struct Ahead {
    std::size_t i;
    int k;
    Sample s;
  };
  std::vector<Ahead> todo;
  const PendingForCall restore(pend_);
  std::array<double, 2> feed = feed_;
  double s = s_;
  const stock::ToolProfile& tool = eng_.tool();
  std::size_t covered = 0;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const interp::Motion& m = ms[i];
    const std::vector<Point3> v = motion_vertices(m, o_.path);
    const bool line = is_line(m);
    const bool sampled = m.kind != interp::MotionKind::rapid;
    const int n = static_cast<int>(v.size()) - 1;
    if (covered > 0 && sampled && todo.size() + static_cast<std::size_t>(n) > o_.max_batch) break;
    for (int k = 1; k <= n; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      CLSample cl = cl_sample(m, v, kk, feed);
      if (sampled) {
        cl.motion = motions_ + i;
        todo.push_back({i, k, Sample{cl, sweep_before(tool, m, v, kk, o_.trim_mm), pend_.size()}});
      }
      s += dist(v[kk - 1], v[kk]);
      if (!line) pend_.emplace_back(tool, v[kk - 1], v[kk]);
    }
    if (line) pend_.emplace_back(tool, v[0], v.back());
    ++covered;
    if (s - batch_start_s_ >= batch_mm_) break;  // run() would commit after this one
  }
  if (commit_running_ && !todo.empty()) {
    TileBox reads = read_box(todo[0].s.cl.point.tip_mm);
    for (const Ahead& a : todo) reads.join(read_box(a.s.cl.point.tip_mm));
    wait_commit_if(reads);
  }
  const double t0 = now_s();
  auto one = [&](const Ahead& a) {
    thread_local force::Engagement eng;
    const StockView view{&z_, std::span<const stock::LineSweep>(pend_.data(), a.s.pending), &a.s.current};
    Metrics mt;
    try {
      mt = eng_.evaluate(view, a.s.cl.point, proc_, eng);
    } catch (...) {
      return;  // probe() reports it when the driver gets there
    }
    work(a.i, a.k, a.s.cl, mt, eng);
  };
  if (o_.threads == 1 || todo.size() < 4) {
    for (const Ahead& a : todo) one(a);
  } else {
    in_arena(arena_.get(), [&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, todo.size(), 1),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t j = r.begin(); j != r.end(); ++j) one(todo[j]);
                        });
    });
  }
  t_engage_ += now_s() - t0;
  return covered;
}

}  // namespace deflex::engage
