// CGAL's kd-tree over points given by index (a sample's or a measured
// point's position), shared by fit::Surface and fit::Nearest. The points
// live in a vector the property map points into.
#pragma once
#include <cstddef>
#include <memory>
#include <vector>

#include <CGAL/Kd_tree.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>
#include <boost/property_map/property_map.hpp>

namespace deflex::fit::detail {

using K = CGAL::Simple_cartesian<double>;
struct PointMap {
  const std::vector<K::Point_3>* pts = nullptr;
  using key_type = std::size_t;
  using value_type = K::Point_3;
  using reference = const value_type&;
  using category = boost::readable_property_map_tag;
  friend reference get(const PointMap& m, std::size_t i) { return (*m.pts)[i]; }
};
using Traits = CGAL::Search_traits_adapter<std::size_t, PointMap, CGAL::Search_traits_3<K>>;
using Tree = CGAL::Kd_tree<Traits>;

// The tree over indices 0..pts.size()-1, built.
inline std::unique_ptr<Tree> build_tree(const std::vector<K::Point_3>& pts) {
  std::vector<std::size_t> ids(pts.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = i;
  auto tree = std::make_unique<Tree>(ids.begin(), ids.end(), Tree::Splitter(), Traits(PointMap{&pts}));
  tree->build();
  return tree;
}

}  // namespace deflex::fit::detail
