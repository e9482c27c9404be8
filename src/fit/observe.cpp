// fit::match() (observe.hpp).
#include "deflex/fit/observe.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>
#include <boost/property_map/property_map.hpp>

namespace deflex::fit {

double measured_error(const Observation& o, const SurfaceSample& s, const part::PartModel* part) {
  if (o.error_mm) return *o.error_mm;
  if (part) {
    const part::Contact c = part->closest(o.at_mm);
    return (o.at_mm - c.point_mm).dot(c.normal);
  }
  return (o.at_mm - s.at_mm).dot(s.normal);
}

Matching match(const Surface& surface, const std::vector<Observation>& obs, double reach_mm,
               const part::PartModel* part) {
  Matching m;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const Observation& o = obs[i];
    const long s = surface.nearest(o.at_mm, reach_mm);
    if (s < 0) {
      m.unmatched.push_back(i);
      continue;
    }
    const SurfaceSample& smp = surface.samples()[static_cast<std::size_t>(s)];
    m.matched.push_back({i, static_cast<std::size_t>(s), measured_error(o, smp, part)});
  }
  return m;
}

// CGAL's kd-tree over the observations (indices), searched with a sphere of
// the reach around each sample.
namespace {
using K = CGAL::Simple_cartesian<double>;
struct ObsMap {
  const std::vector<K::Point_3>* pts = nullptr;
  using key_type = std::size_t;
  using value_type = K::Point_3;
  using reference = const value_type&;
  using category = boost::readable_property_map_tag;
  friend reference get(const ObsMap& m, std::size_t i) { return (*m.pts)[i]; }
};
using Traits = CGAL::Search_traits_adapter<std::size_t, ObsMap, CGAL::Search_traits_3<K>>;
using Tree = CGAL::Kd_tree<Traits>;
using Sphere = CGAL::Fuzzy_sphere<Traits>;
}  // namespace

struct Nearest::Index {
  std::vector<K::Point_3> pts;
  std::unique_ptr<Tree> tree;
  std::vector<std::size_t> hits;
};

Nearest::Nearest(const std::vector<Observation>& obs, double reach_mm, std::function<const stiffness::Tool*(int)> tool_of)
    : index_(std::make_unique<Index>()), found_(obs.size()), reach_mm_(reach_mm), tool_of_(std::move(tool_of)) {
  for (const Observation& o : obs) index_->pts.emplace_back(o.at_mm.x(), o.at_mm.y(), o.at_mm.z());
  std::vector<std::size_t> ids(obs.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = i;
  index_->tree = std::make_unique<Tree>(ids.begin(), ids.end(), Tree::Splitter(), Traits(ObsMap{&index_->pts}));
  index_->tree->build();
}

Nearest::Nearest(Nearest&&) noexcept = default;
Nearest::~Nearest() = default;

void Nearest::add(const compensate::Point& p, const V3& offset) {
  const std::uint32_t index = points_++;
  const stiffness::Tool* t = tool_of_(p.tool);
  if (!t || found_.empty()) return;
  scratch_.clear();
  append_samples(p, index, *t, scratch_);
  const double along = offset.dot(p.normal);
  for (SurfaceSample& s : scratch_) {
    s.at_mm -= offset;
    index_->hits.clear();
    index_->tree->search(std::back_inserter(index_->hits),
                         Sphere(K::Point_3(s.at_mm.x(), s.at_mm.y(), s.at_mm.z()), reach_mm_, 0.0, Traits(ObsMap{&index_->pts})));
    for (std::size_t i : index_->hits) {
      const K::Point_3& q = index_->pts[i];
      const double d = (s.at_mm - V3(q.x(), q.y(), q.z())).norm();
      Found& f = found_[i];
      if (f.found && d > f.distance_mm) continue;
      f = {true, s, sample_error(p, s) + along, d};
    }
  }
}

Agreement agreement(const std::vector<double>& pred, const std::vector<double>& meas, double tol) {
  Agreement a;
  a.points = pred.size();
  if (pred.empty()) return a;
  const double n = static_cast<double>(pred.size());
  double sp = 0, sm = 0;
  std::size_t within = 0;
  for (std::size_t i = 0; i < pred.size(); ++i) {
    const double d = pred[i] - meas[i];
    a.rms_difference_mm += d * d;
    a.max_difference_mm = std::max(a.max_difference_mm, std::abs(d));
    a.rms_measured_mm += meas[i] * meas[i];
    a.max_measured_mm = std::max(a.max_measured_mm, std::abs(meas[i]));
    if (std::abs(d) <= tol) ++within;
    sp += pred[i], sm += meas[i];
  }
  a.rms_difference_mm = std::sqrt(a.rms_difference_mm / n);
  a.rms_measured_mm = std::sqrt(a.rms_measured_mm / n);
  a.within_tolerance_share = static_cast<double>(within) / n;
  double cpp = 0, cmm = 0, cpm = 0;
  for (std::size_t i = 0; i < pred.size(); ++i) {
    const double dp = pred[i] - sp / n, dm = meas[i] - sm / n;
    cpp += dp * dp, cmm += dm * dm, cpm += dp * dm;
  }
  a.correlation = pred.size() >= 3 && cpp > 0 && cmm > 0 ? cpm / std::sqrt(cpp * cmm)
                                                          : std::numeric_limits<double>::quiet_NaN();
  return a;
}

}  // namespace deflex::fit
