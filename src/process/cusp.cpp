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
// The kd-tree holds sample indices; their XY positions come through a property map.
struct XyMap {
  using key_type = std::size_t;
  using value_type = K::Point_2;
  using reference = value_type;
  using category = boost::readable_property_map_tag;
  const std::vector<CuspSample>* s;
  friend value_type get(const XyMap& m, std::size_t i) {
    const Eigen::Vector3d& p = (*m.s)[i].tip_mm;
    return {p.x(), p.y()};
  }
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

// The nearest neighbouring pass on each side of sample i within radius r of
// it: the distance across the feed (NaN where none).
std::pair<double, double> stepovers(const std::vector<CuspSample>& s, const Tree& tree, std::size_t i, double r,
                                    std::vector<std::size_t>& near) {
  const CuspSample& p = s[i];
  const double de = p.profile_diameter_mm;
  const Eigen::Vector2d t = horizontal(p.feed_dir), xy = p.tip_mm.head<2>();
  near.clear();
  tree.search(std::back_inserter(near), Circle(K::Point_2(xy.x(), xy.y()), r, 0.0, Traits(XyMap{&s})));
  double left = CuspResult::none, right = CuspResult::none;
  double left_dist = HUGE_VAL, right_dist = HUGE_VAL;
  const double parallel = std::cos(30 * kRad);
  for (std::size_t j : near) {
    const CuspSample& q = s[j];
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
    const bool on_left = cross(t, d) > 0;
    double& dist = on_left ? left_dist : right_dist;
    if (d.norm() < dist) {
      dist = d.norm();
      (on_left ? left : right) = across;
    }
  }
  return {left, right};
}

// As above within D_e, searched in circles growing from 1 mm: a side's nearest
// neighbour found within r is the one a search over all of D_e finds (it is
// the nearest), so only the cost changes: a finishing step-over is found in the
// first circle instead of among the thousands of samples a 16 mm ball covers.
std::pair<double, double> stepovers(const std::vector<CuspSample>& s, const Tree& tree, std::size_t i,
                                    std::vector<std::size_t>& near) {
  const double de = s[i].profile_diameter_mm;
  for (double r = std::min(de, 1.0);; r = std::min(de, 2 * r)) {
    const auto lr = stepovers(s, tree, i, r, near);
    if ((!std::isnan(lr.first) && !std::isnan(lr.second)) || r >= de) return lr;
  }
}

// The cusp result of sample i (in material, travelling sideways).
CuspResult cusp_at(const std::vector<CuspSample>& s, const Tree& tree, std::size_t i, std::vector<std::size_t>& near) {
  const CuspSample& p = s[i];
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
  const auto [left, right] = stepovers(s, tree, i, near);
  for (double ae : {left, right}) {
    if (std::isnan(ae)) continue;
    const double c = cusp_height_mm(p.profile_diameter_mm, ae, alpha3);
    if (std::isnan(r.height_mm) || c > r.height_mm) { r.height_mm = c; r.stepover_mm = ae; }
  }
  return r;
}

}  // namespace

namespace {

// The results of samples [first, last) of `s`, their neighbours searched among
// all of `s`.
void cusp_over(const std::vector<CuspSample>& s, std::size_t first, std::size_t last, std::vector<CuspResult>& out) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (sideways(s[i])) idx.push_back(i);
  if (idx.empty()) return;
  Tree tree(idx.begin(), idx.end(), Tree::Splitter(), Traits(XyMap{&s}));
  tree.build();
  // Each point reads the tree and writes its own result: in parallel, the
  // same results whatever the threads. Isolated: a caller holding a lock (the
  // report's recorder) must not be handed an outer task that takes it again.
  tbb::this_task_arena::isolate([&] {
    diag::TracedLoop loop;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
      loop.task([&] {
        std::vector<std::size_t> near;
        for (std::size_t i = r.begin(); i != r.end(); ++i)
          if (s[i].cutting && sideways(s[i])) out[i - first] = cusp_at(s, tree, i, near);
      });
    });
  });
}

}  // namespace

CuspStream::CuspStream(std::size_t block) : block_(std::max<std::size_t>(1, block)) {}

void CuspStream::add(const CuspSample& s) {
  samples_.push_back(s);
  ++size_;
  // Block b is done once block b + 1 is whole.
  if (size_ % block_ == 0 && size_ >= 2 * block_) solve(size_ / block_ - 2);
}

void CuspStream::finish() {
  // The blocks not solved yet (a second call finds none).
  for (std::size_t b = (ready_ + block_ - 1) / block_; b * block_ < size_; ++b) solve(b);
}

void CuspStream::solve(std::size_t b) {
  const std::size_t first = b * block_, last = std::min(size_, first + block_);
  const std::size_t w0 = b ? first - block_ : 0, w1 = std::min(size_, last + block_);
  // The samples before the window are not needed again.
  while (samples_base_ < w0) {
    samples_.pop_front();
    ++samples_base_;
  }
  const std::vector<CuspSample> window(samples_.begin(), samples_.begin() + static_cast<std::ptrdiff_t>(w1 - w0));
  std::vector<CuspResult> out(last - first);
  cusp_over(window, first - w0, last - w0, out);
  results_.insert(results_.end(), out.begin(), out.end());
  ready_ = last;
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
