// fit::Surface (surface.hpp).
#include "deflex/fit/surface.hpp"

#include <stdexcept>

#include <CGAL/Orthogonal_k_neighbor_search.h>

#include "deflex/compensate/contact.hpp"
#include "deflex/stock/end_shape.hpp"
#include "point_index.hpp"

namespace deflex::fit {

// The kd-tree over the samples' positions (point_index.hpp).
namespace {
using detail::K;
using detail::PointMap;
using Search = CGAL::Orthogonal_k_neighbor_search<detail::Traits>;
using Tree = detail::Tree;
}  // namespace

struct Surface::Index {
  std::vector<K::Point_3> pts;
  std::unique_ptr<Tree> tree;
};

void append_samples(const compensate::Point& p, std::uint32_t index, const stiffness::Tool& t,
                    std::vector<SurfaceSample>& out) {
  if (p.air || p.plunge) return;
  if (!(p.flank && !p.flank_profile.empty())) {
    out.push_back({compensate::contact_point(p, t), p.normal, p.line, index, -1});
    return;
  }
  // A bull nose's corner generates no wall: its slices below the corner
  // radius are left out.
  const double r = stock::corner_radius_mm(t.type, t.diameter_mm / 2, t.corner_radius_mm);
  for (std::size_t k = 0; k < p.flank_profile.size(); ++k)
    if (p.flank_profile[k].z_mm >= r)
      out.push_back({compensate::flank_point(p, t, p.flank_profile[k].z_mm), p.normal, p.line, index, static_cast<int>(k)});
}

double sample_error(const compensate::Point& p, const SurfaceSample& s) {
  return s.slice < 0 ? p.error_mm : p.flank_profile[static_cast<std::size_t>(s.slice)].error_mm;
}

Surface::Surface(const std::vector<compensate::Point>& points,
                 const std::function<const stiffness::Tool*(int)>& tool_of)
    : index_(std::make_unique<Index>()) {
  slices_of_point_.resize(points.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    slices_of_point_[i] = static_cast<std::uint32_t>(points[i].flank_profile.size());
    if (const stiffness::Tool* t = tool_of(points[i].tool))
      append_samples(points[i], static_cast<std::uint32_t>(i), *t, samples_);
  }
  index_->pts.reserve(samples_.size());
  for (const SurfaceSample& s : samples_) index_->pts.emplace_back(s.at_mm.x(), s.at_mm.y(), s.at_mm.z());
  index_->tree = detail::build_tree(index_->pts);
}

Surface::Surface(Surface&&) noexcept = default;
Surface& Surface::operator=(Surface&&) noexcept = default;
Surface::~Surface() = default;

std::vector<double> Surface::errors(const std::vector<compensate::Point>& points) const {
  if (points.size() != slices_of_point_.size())
    throw std::logic_error("fit::Surface::errors: a simulation with other points than the surface's");
  std::vector<double> e(samples_.size());
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    const SurfaceSample& s = samples_[i];
    const compensate::Point& p = points[s.point];
    if (s.slice >= 0 && p.flank_profile.size() != slices_of_point_[s.point])
      throw std::logic_error("fit::Surface::errors: a flank profile with other slices than the surface's");
    e[i] = sample_error(p, s);
  }
  return e;
}

long Surface::nearest(const V3& p, double reach_mm) const {
  if (samples_.empty()) return -1;
  const PointMap map{&index_->pts};
  Search search(*index_->tree, K::Point_3(p.x(), p.y(), p.z()), 1, 0, true, Search::Distance(map));
  const auto it = search.begin();
  if (it == search.end() || it->second > reach_mm * reach_mm) return -1;
  return static_cast<long>(it->first);
}

}  // namespace deflex::fit
