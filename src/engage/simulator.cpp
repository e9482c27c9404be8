#include "deflex/engage/simulator.hpp"

#include <algorithm>
#include <cmath>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stock/sweep.hpp"

namespace deflex::engage {

namespace {

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

}  // namespace

Simulator::Simulator(stock::ZMap& z, const force::CutterSlices& cs, const Process& p, const SimOptions& o)
    : z_(z), eng_(cs, o.engage), proc_(p), o_(o) {
  keep_mm_ = o.keep_mm > 0 ? o.keep_mm : 2 * cs.cutter.diameter_mm + 4 * z.grid().cell_mm;
  if (o.max_pending < 1) throw Error(Exit::config, "simulation: max_pending must be >= 1");
  if (!(o.trim_mm > 0)) throw Error(Exit::config, "simulation: trim_mm must be > 0");
}

void Simulator::commit_front() {
  removed_ += stock::sweep_line(z_, pending_.front());
  pending_.erase(pending_.begin());
  pending_end_s_.erase(pending_end_s_.begin());
}

void Simulator::commit_old() {
  while (!pending_.empty() && (s_ - pending_end_s_.front() > keep_mm_ || pending_.size() > o_.max_pending))
    commit_front();
}

void Simulator::finish() {
  while (!pending_.empty()) commit_front();
}

void Simulator::run(const interp::Motion& m, const PointSink& sink) {
  const std::vector<Point3> v = motion_vertices(m, o_.path);
  const bool line = m.kind == interp::MotionKind::rapid || m.kind == interp::MotionKind::linear;
  const bool sample = sink && (m.kind != interp::MotionKind::rapid || o_.sample_rapids);
  const stock::ToolProfile& tool = eng_.tool();
  const std::size_t motion_index = motions_++;
  const int n = static_cast<int>(v.size()) - 1;
  for (int k = 1; k <= n; ++k) {
    const Point3& vk = v[static_cast<std::size_t>(k)];
    // A line is one pending volume from its start; an arc one per chord.
    const Point3& from = line ? v[0] : v[static_cast<std::size_t>(k - 1)];
    const bool extend = line && k > 1;
    if (sample) {
      CLSample s;
      s.point.tip_mm = vk;
      s.point.dir = motion_direction(m, v, static_cast<std::size_t>(k));
      const double h = std::hypot(s.point.dir[0], s.point.dir[1]);
      if (h > 1e-6) feed_ = {s.point.dir[0] / h, s.point.dir[1] / h};
      s.point.feed_x = feed_[0];
      s.point.feed_y = feed_[1];
      s.motion = motion_index;
      s.line = m.line;
      s.index = k;
      s.count = n;
      s.rapid = m.kind == interp::MotionKind::rapid;
      // The stock as cut so far: this motion up to just before the sample.
      const stock::LineSweep cur(tool, from, trimmed(from, vk, o_.trim_mm));
      if (extend) {
        pending_.back() = cur;
      } else {
        pending_.push_back(cur);
        pending_end_s_.push_back(s_);
      }
      const StockView view{&z_, pending_};
      const Metrics met = eng_.evaluate(view, s.point, proc_, e_);
      ++samples_;
      sink(s, met, e_);
      pending_.back() = stock::LineSweep(tool, from, vk);
    } else if (extend) {
      pending_.back() = stock::LineSweep(tool, from, vk);
    } else {
      pending_.emplace_back(tool, from, vk);
      pending_end_s_.push_back(s_);
    }
    s_ += dist(v[static_cast<std::size_t>(k - 1)], vk);
    pending_end_s_.back() = s_;
    commit_old();
  }
}

}  // namespace deflex::engage
