// Runs a motion sequence through the stock in program order: at every CL sample
// of a motion the engagement is evaluated on the stock as cut so far (the
// previous motions and this motion up to just before the sample), then the
// motion is cut into the stock.
//
// The most recent swept volumes stay "pending" (exact, analytic) instead of being
// rasterised into the Z-map at once, so the tool's own wake is resolved exactly
// rather than to a cell; a pending volume is committed to the Z-map when the path
// has moved on by keep_mm (default 2 D + 4 cells, after which its footprint no
// longer overlaps the tool's on a straight path), or when more than max_pending
// are waiting. Walls left by earlier passes are therefore resolved to the Z-map
// cell, the current pass exactly.
#pragma once
#include <memory>

#include <tbb/task_arena.h>
#include <tbb/task_group.h>
#include <algorithm>
#include <array>
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "deflex/engage/engagement.hpp"
#include "deflex/engage/path.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::diag {
class BackgroundJob;  // diag/parallel_trace.hpp
}

namespace deflex::engage {

struct SimOptions {
  PathOptions path;
  Options engage;
  double keep_mm = 0;             // 0: 2 D + 4 cells
  std::size_t max_pending = 256;  // checked when a batch is done
  double trim_mm = 1e-4;          // the current move counts up to this short of the sample
  bool sample_rapids = false;     // rapids are always cut, sampled only on request
  double batch_mm = 0;            // path length per batch; 0: D
  std::size_t max_batch = 256;    // CL samples per batch
  int threads = 0;                // 0: TBB's default (all cores); 1: sequential
  bool commit_beside = true;      // false: each commit done before anything goes on (the tests' reference)
  // false: the samples are not evaluated (the sink and the sample work get
  // empty metrics and engagement): the sweep alone, with the same samples,
  // batches and commits, so the stock a sink reads is the same.
  bool evaluate = true;
};

using PointSink = std::function<void(const CLSample&, const Metrics&, const force::Engagement&)>;
// Work on sample k (1..) of motion i of a Simulator::probe_ahead call.
using AheadWork = std::function<void(std::size_t i, int k, const CLSample&, const Metrics&, const force::Engagement&)>;
// Work on one sample done in parallel right after its engagement, before the
// sink sees the batch in program order (Simulator::set_sample_work). `slot`
// is the sample's place in its batch, so that the work can leave its result
// where the sink finds it (Simulator::sink_slot()).
using SampleWork = std::function<void(std::size_t slot, const CLSample&, const Metrics&, const force::Engagement&)>;

// Parallelism. The engagement at a CL sample depends on the stock and on the
// geometry of the path before it, and the path is known in advance: so the CL
// samples of a batch (batch_mm of path) are evaluated in parallel against the
// same Z-map, each seeing exactly the sweeps before it as pending volumes; then
// the sink is called in program order and the batch's old sweeps are committed
// (bands of tile rows in parallel). The commit runs beside what follows it (the
// next motions, the next batch's evaluations, probes) for as long as they read
// no tile it writes; whatever reads one waits for it, and the sinks always do.
// Results do not depend on the thread count.
class Simulator {
 public:
  // `z` is cut in place; it must outlive the simulator. The sink (may be empty)
  // receives every CL sample in program order, at the latest on finish().
  Simulator(stock::ZMap& z, const force::CutterSlices& cs, const Process& p, const SimOptions& o = {},
            PointSink sink = {});
  ~Simulator();  // waits for a commit in flight (its result is then dropped)
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  void run(const interp::Motion& m);

  // Evaluates CL sample k (1..count) of motion m, whose vertices are v
  // (motion_vertices(m, options().path)), against the stock as the motions run so
  // far left it plus m itself up to just before the sample, without cutting
  // anything: what run(m) would report for that sample. For a driver that
  // chooses each motion's end point from the engagement there (the mirror
  // method of deflex::compensate): probe, decide, then run() the chosen motion.
  // Sequential (one probe at a time); fills `cl` as run() would.
  Metrics probe(const interp::Motion& m, std::span<const Point3> v, int k, CLSample& cl, force::Engagement& out);
  // probe() of every CL sample of ms[0], ms[1], ... at once, in parallel: each
  // as run() of the motions in turn would meet it (the motions before it cut,
  // its own up to it), nothing cut. A driver that runs the motions unchanged
  // where it can (the mirror pass, where a point needs no offset) evaluates
  // ahead instead of one probe at a time. Covers the motions up to the first
  // whose run() would commit sweeps (the stock the later ones meet would
  // change) and, past the first motion, at most max_batch samples; returns how
  // many motions it covered. `work` is called concurrently, once per sample
  // whose engagement evaluated (one that threw is left out: probe() it to
  // get the error in order). Only for a simulator without a sink.
  std::size_t probe_ahead(std::span<const interp::Motion> ms, const AheadWork& work);
  const SimOptions& options() const { return o_; }
  // What is computed from a sample's engagement alone (its forces, its
  // deflection) runs with the evaluations, on as many threads, instead of
  // one by one in the sink. Called concurrently for different slots while
  // nothing cuts the stock; it may read the stock. Set before the first run().
  void set_sample_work(SampleWork w) { work_ = std::move(w); }
  // During a sink call: the slot its sample had in the sample work.
  std::size_t sink_slot() const { return sink_slot_; }
  // During a sink call: the stock as its sample met it (the Z-map, the sweeps
  // pending before it and its own motion up to it), for what reads the stock
  // beyond the tool (the holder and shank check): the sink sees the Z-map
  // with every commit before the sample's batch done, and no later one.
  StockView sink_view() const;
  // Evaluates what is left and commits every pending volume: the Z-map is then
  // the stock as cut by all motions run so far.
  void finish();

  double removed_mm3() const { return removed_; }  // committed so far
  std::size_t pending_count() const { return pend_.size(); }
  std::size_t samples() const { return samples_; }
  // Wall-clock time spent evaluating engagements and committing sweeps, s.
  double engage_seconds() const { return t_engage_; }
  double sweep_seconds() const { return t_sweep_; }
  const Engager& engager() const { return eng_; }

 private:
  struct Sample {
    CLSample cl;
    stock::LineSweep current;   // this motion up to just before the sample
    std::size_t pending = 0;    // sweeps of pend_ before it
  };
  // The Z-map tiles [i0, i1] x [j0, j1] (inclusive).
  struct TileBox {
    int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
    bool meets(const TileBox& o) const { return i0 <= o.i1 && o.i0 <= i1 && j0 <= o.j1 && o.j0 <= j1; }
    void join(const TileBox& o) {
      i0 = std::min(i0, o.i0), i1 = std::max(i1, o.i1), j0 = std::min(j0, o.j0), j1 = std::max(j1, o.j1);
    }
  };
  void flush();
  void evaluate_batch();
  void commit_old(bool all);
  TileBox tiles_of(double x0_mm, double y0_mm, double x1_mm, double y1_mm) const;
  TileBox read_box(const Point3& tip_mm) const;   // the tiles an evaluation at tip reads
  void wait_commit();                             // the commit in flight done, its results taken
  void wait_commit_if(const TileBox& reads);      // only if it writes one of these tiles

  stock::ZMap& z_;
  std::unique_ptr<tbb::task_arena> arena_;  // SimOptions::threads > 0
  Engager eng_;
  Process proc_;
  SimOptions o_;
  PointSink sink_;
  SampleWork work_;
  std::size_t sink_slot_ = 0;
  const Sample* sinking_ = nullptr;  // the sample a sink call is for
  double keep_mm_ = 0, batch_mm_ = 0;
  std::vector<stock::LineSweep> pend_;  // oldest first
  std::vector<double> pend_end_s_;      // path length at each one's end
  std::vector<Sample> batch_;
  std::vector<Metrics> metrics_;
  std::vector<force::Engagement> engs_;
  double s_ = 0, batch_start_s_ = 0;    // path length, mm
  std::array<double, 2> feed_{1, 0};
  bool have_committed_end_ = false;
  Point3 committed_end_{};
  double removed_ = 0;
  double t_engage_ = 0, t_sweep_ = 0;
  // The commit in flight (at most one): its sweeps, the tiles they write, its
  // results (taken by wait_commit).
  std::unique_ptr<tbb::task_group> commits_;
  std::vector<stock::LineSweep> committing_;
  TileBox commit_box_;
  bool commit_running_ = false;
  double commit_removed_ = 0, commit_s_ = 0;
  std::unique_ptr<diag::BackgroundJob> commit_job_;  // when tracing (diag/parallel_trace.hpp)
  std::size_t samples_ = 0;
  std::size_t motions_ = 0;
};

}  // namespace deflex::engage
