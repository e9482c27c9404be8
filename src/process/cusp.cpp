// Cusp height per CL point (include/deflex/process/cusp.hpp; Mikó et al., Eq. 1-7).
#include "deflex/process/cusp.hpp"

#include "deflex/diag/parallel_trace.hpp"

#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Search_traits_2.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/property_map.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <memory>
#include <span>
#include <numbers>
#include <stdexcept>

namespace deflex::process {

double cusp_alpha3_rad(double milling_direction_rad, double inclination_rad) {
  return std::atan(std::sin(milling_direction_rad) * std::tan(inclination_rad));  // Eq. 4
}

double cusp_height_mm(double effective_diameter_mm, double stepover_mm, double alpha3_rad) {
  const double r = effective_diameter_mm / 2;
  const double half = stepover_mm / (2 * std::cos(alpha3_rad));  // Eq. 7
  if (!(half < r)) return r;
  return r - std::sqrt(r * r - half * half);
}

namespace {

using K = CGAL::Simple_cartesian<double>;
// The kd-tree holds a block's sample numbers; their XY positions come through
// a property map. It hands out references to points stored once per block: a
// map that returns points by value makes CGAL's adapter copy each point it
// reads into a shared_ptr (an allocation per point visited in every search).
struct XyMap {
  using key_type = std::size_t;
  using value_type = K::Point_2;
  using reference = const value_type&;
  using category = boost::lvalue_property_map_tag;
  const K::Point_2* xy;
  friend reference get(const XyMap& m, std::size_t i) { return m.xy[i]; }
};
using Traits = CGAL::Search_traits_adapter<std::size_t, XyMap, CGAL::Search_traits_2<K>>;
using Tree = CGAL::Kd_tree<Traits>;
using Circle = CGAL::Fuzzy_sphere<Traits>;

constexpr double kRad = std::numbers::pi / 180;

// Horizontal unit direction of travel; zero for a vertical or missing one.
Eigen::Vector2d horizontal(const Eigen::Vector3d& v) {
  const Eigen::Vector2d h(v.x(), v.y());
  const double n = h.norm();
  return n > 1e-9 * std::max(1.0, v.norm()) ? Eigen::Vector2d(h / n) : Eigen::Vector2d::Zero();
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// A pass generates its surface whether or not a given sample of it met
// material (the ends of a raster often run in air): every sample of a ball
// travelling sideways may be a neighbour; only samples in material get a cusp.
bool sideways(const CuspSample& s) { return s.profile_diameter_mm > 0 && horizontal(s.feed_dir).norm() > 0; }

}  // namespace

// One block of samples and the kd-tree over those of them travelling
// sideways, built once when the block is whole: a sample's window is its own
// block's tree and the trees of the blocks beside it, so every sample goes
// into one tree, not into one per window that holds it.
struct detail::CuspBlock {
  std::size_t first = 0;  // the number of its first sample
  std::vector<CuspSample> s;
  std::vector<K::Point_2> xy;
  std::vector<std::size_t> idx;  // sideways samples, indices into s
  std::unique_ptr<Tree> tree;    // null until whole (and while it holds no sideways sample)
  bool built = false;

  void build() {
    if (built) return;
    built = true;
    xy.reserve(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
      xy.emplace_back(s[i].tip_mm.x(), s[i].tip_mm.y());
      if (sideways(s[i])) idx.push_back(i);
    }
    if (idx.empty()) return;
    tree = std::make_unique<Tree>(idx.begin(), idx.end(), Tree::Splitter(), Traits(XyMap{xy.data()}));
    tree->build();
  }
};

namespace {

using Block = detail::CuspBlock;

// The nearest neighbouring pass on one side so far: its distance across, the
// distance to its sample and that sample's number. Equally near samples are
// ordered by their number, so the result does not depend on the order the
// trees hand the samples out (nor on which tree holds which).
struct Side {
  double across = CuspResult::none, dist = HUGE_VAL;
  std::size_t number = 0;
  void offer(double a, double d, std::size_t n) {
    if (d < dist || (d == dist && n < number)) across = a, dist = d, number = n;
  }
};

// The nearest neighbouring pass on each side of sample p within radius r of
// it, among the samples of the window's blocks: the distance across the feed
// (NaN where none).
std::pair<double, double> stepovers(const CuspSample& p, std::span<const Block* const> window, double r,
                                    std::vector<std::size_t>& near) {
  const double de = p.profile_diameter_mm;
  const Eigen::Vector2d t = horizontal(p.feed_dir), xy = p.tip_mm.head<2>();
  const double parallel = std::cos(30 * kRad);
  Side left, right;
  for (const Block* b : window) {
    if (!b->tree) continue;
    near.clear();
    b->tree->search(std::back_inserter(near), Circle(K::Point_2(xy.x(), xy.y()), r, 0.0, Traits(XyMap{b->xy.data()})));
    for (std::size_t j : near) {
      const CuspSample& q = b->s[j];
      const Eigen::Vector2d tq = horizontal(q.feed_dir);
      if (std::fabs(tq.dot(t)) < parallel) continue;
      const Eigen::Vector2d d = q.tip_mm.head<2>() - xy;
      const double across = std::fabs(cross(tq, d)), along = t.dot(d);  // to the line of q's travel
      // Not another pass: q could lie on p's own path bent no tighter than the
      // ball's radius (a closed contour coming round to its start), or retrace it.
      if (across < 1e-3 + along * along / de || across > de) continue;
      // Per side the neighbour's sample nearest to p, which lies closest to the
      // foot of the perpendicular; the distance to its line of travel does not
      // depend on how far along its pass the sample fell (exact on straight passes).
      (cross(t, d) > 0 ? left : right).offer(across, d.norm(), b->first + j);
    }
  }
  return {left.across, right.across};
}

// As above within D_e, searched in circles growing from 1 mm: a side's nearest
// neighbour found within r is the one a search over all of D_e finds (it is
// the nearest), so only the cost changes: a finishing step-over is found in the
// first circle instead of among the thousands of samples a 16 mm ball covers.
std::pair<double, double> stepovers(const CuspSample& p, std::span<const Block* const> window,
                                    std::vector<std::size_t>& near) {
  const double de = p.profile_diameter_mm;
  for (double r = std::min(de, 1.0);; r = std::min(de, 2 * r)) {
    const auto lr = stepovers(p, window, r, near);
    if ((!std::isnan(lr.first) && !std::isnan(lr.second)) || r >= de) return lr;
  }
}

// The cusp result of sample p (in material, travelling sideways).
CuspResult cusp_at(const CuspSample& p, std::span<const Block* const> window, std::vector<std::size_t>& near) {
  CuspResult r;
  if (!p.normal_known) return r;
  const Eigen::Vector3d n = p.normal.normalized();
  const double alpha1 = std::acos(std::clamp(n.z(), -1.0, 1.0));
  r.inclination_deg = alpha1 / kRad;
  // The fall line is the horizontal part of the outward normal (it points downhill).
  const Eigen::Vector2d fall = horizontal(n), t = horizontal(p.feed_dir);
  const double a = fall.norm() > 0 ? std::acos(std::min(1.0, std::fabs(t.dot(fall)))) : 0.0;
  r.direction_deg = fall.norm() > 0 ? a / kRad : CuspResult::none;
  const double alpha3 = cusp_alpha3_rad(a, alpha1);
  r.alpha3_deg = alpha3 / kRad;
  const auto [left, right] = stepovers(p, window, near);
  for (double ae : {left, right}) {
    if (std::isnan(ae)) continue;
    const double c = cusp_height_mm(p.profile_diameter_mm, ae, alpha3);
    if (std::isnan(r.height_mm) || c > r.height_mm) { r.height_mm = c; r.stepover_mm = ae; }
  }
  return r;
}

}  // namespace

CuspStream::CuspStream(std::size_t block) : block_(std::max<std::size_t>(1, block)) {}
CuspStream::~CuspStream() = default;
CuspStream::CuspStream(CuspStream&&) noexcept = default;

void CuspStream::add(const CuspSample& s) {
  if (blocks_.empty() || blocks_.back()->s.size() == block_) {
    blocks_.push_back(std::make_unique<detail::CuspBlock>());
    blocks_.back()->first = size_;
  }
  blocks_.back()->s.push_back(s);
  ++size_;
  // Block b is done once block b + 1 is whole.
  if (size_ % block_ == 0) {
    blocks_.back()->build();
    if (size_ >= 2 * block_) solve(size_ / block_ - 2);
  }
}

void CuspStream::finish() {
  if (!blocks_.empty()) blocks_.back()->build();
  // The blocks not solved yet (a second call finds none).
  for (std::size_t b = (ready_ + block_ - 1) / block_; b * block_ < size_; ++b) solve(b);
}

void CuspStream::solve(std::size_t b) {
  // The blocks before the window are not needed again.
  while (blocks_base_ + 1 < b) {
    blocks_.pop_front();
    ++blocks_base_;
  }
  const Block& own = *blocks_[b - blocks_base_];
  std::vector<const Block*> window;
  for (std::size_t k = b ? b - 1 : 0; k <= b + 1 && k < blocks_base_ + blocks_.size(); ++k)
    window.push_back(blocks_[k - blocks_base_].get());
  const std::size_t n = own.s.size();
  std::vector<CuspResult> out(n);
  // Each point reads the trees and writes its own result: in parallel, the
  // same results whatever the threads. Isolated: a caller holding a lock (the
  // report's recorder) must not be handed an outer task that takes it again.
  if (own.tree) {
    tbb::this_task_arena::isolate([&] {
      diag::TracedLoop loop;
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        loop.task([&] {
          std::vector<std::size_t> near;
          for (std::size_t i = r.begin(); i != r.end(); ++i)
            if (own.s[i].cutting && sideways(own.s[i])) out[i] = cusp_at(own.s[i], window, near);
        });
      });
    });
  }
  results_.insert(results_.end(), out.begin(), out.end());
  ready_ = own.first + n;
}

const CuspResult& CuspStream::result(std::size_t i) const {
  if (i < results_base_ || i >= ready_) throw std::out_of_range("CuspStream::result");
  return results_[i - results_base_];
}

void CuspStream::forget_before(std::size_t i) {
  for (; results_base_ < std::min(i, ready_); ++results_base_) results_.pop_front();
}

std::vector<CuspResult> cusp_heights(const std::vector<CuspSample>& s, std::size_t block) {
  CuspStream cs(block);
  for (const CuspSample& x : s) cs.add(x);
  cs.finish();
  std::vector<CuspResult> out(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) out[i] = cs.result(i);
  return out;
}

}  // namespace deflex::process
