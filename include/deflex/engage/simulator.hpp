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
#include <array>
#include <cstddef>
#include <functional>
#include <vector>

#include "deflex/engage/engagement.hpp"
#include "deflex/engage/path.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::engage {

struct SimOptions {
  PathOptions path;
  Options engage;
  double keep_mm = 0;             // 0: 2 D + 4 cells
  std::size_t max_pending = 256;
  double trim_mm = 1e-4;          // the current move counts up to this short of the sample
  bool sample_rapids = false;     // rapids are always cut, sampled only on request
};

using PointSink = std::function<void(const CLSample&, const Metrics&, const force::Engagement&)>;

class Simulator {
 public:
  // `z` is cut in place; it must outlive the simulator.
  Simulator(stock::ZMap& z, const force::CutterSlices& cs, const Process& p, const SimOptions& o = {});

  // Engagement at each CL sample of m (to `sink`, may be empty), then m is cut.
  void run(const interp::Motion& m, const PointSink& sink);
  // Commits every pending volume: the Z-map is then the stock as cut so far.
  void finish();

  double removed_mm3() const { return removed_; }  // committed so far
  std::size_t pending_count() const { return pending_.size(); }
  std::size_t samples() const { return samples_; }
  const Engager& engager() const { return eng_; }

 private:
  void commit_front();
  void commit_old();

  stock::ZMap& z_;
  Engager eng_;
  Process proc_;
  SimOptions o_;
  double keep_mm_ = 0;
  std::vector<stock::LineSweep> pending_;  // oldest first
  std::vector<double> pending_end_s_;      // path length at each one's end
  double s_ = 0;                           // path length so far, mm
  std::array<double, 2> feed_{1, 0};
  force::Engagement e_;
  double removed_ = 0;
  std::size_t samples_ = 0;
  std::size_t motions_ = 0;
};

}  // namespace deflex::engage
