// Where the program's cutting tools reach the part: the surface points at
// which the workpiece's compliance is needed (compensate/workpiece.hpp).
// Each cutting move's CL samples stand for the tool there, a cylinder from the
// tip up the flutes; a surface point lies in reach when some tool's cylinder,
// widened by a margin, holds it. The contact of a ball or a flat end, and a
// flank's wall at every height the flutes cover, all lie inside; a face
// turned away from every tool does not.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "deflex/engage/path.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/build.hpp"

namespace deflex::compensate {

// A point of the part's surface and the outward unit normal of its facet.
struct FacetPoint {
  Eigen::Vector3d point_mm, normal;
};

class ToolReach {
 public:
  // margin_mm widens every tool's reach (the interpolation's nodes beyond
  // the contact); tips closer than half of it count once.
  explicit ToolReach(double margin_mm);

  // The cutting moves (in program order, whole or piece by piece); a move
  // whose tool is not in the library is left out (the simulation reports it).
  void add(const std::vector<interp::Motion>& motions, const stiffness::ToolLibrary& tools,
           const std::function<std::string(const interp::Motion&)>& tool_of, const engage::PathOptions& path);

  // Whether a tool reaches p on a face of outward normal n: within its
  // radius plus the margin of the axis through some tip, from the margin
  // below the tip to the top of the flutes, and the face turned against the
  // tool's own surface there (a ball's, from its centre; a flat end's side,
  // radially out, or its bottom, down): the back of a thin wall is as near
  // as its face and the top of the wall beside the flutes, but no tool on
  // this side touches them.
  bool reaches(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& n) const;

  // Points on the triangles at most spacing_mm apart (each triangle's
  // vertices, and a grid over it), those a tool reaches, with their facet's
  // normal (outward: the triangles counter-clockwise seen from outside); one
  // per cell of spacing_mm and face.
  std::vector<FacetPoint> reached_points(const std::vector<stock::Triangle>& surface, double spacing_mm) const;

  std::size_t tips() const { return tips_; }

  struct Tip {
    Eigen::Vector3f tip_mm;
    float radius_mm, flutes_mm;
    bool ball;
  };

 private:
  using Key = std::int64_t;
  static constexpr double kColumnMm = 5;  // the tips indexed by columns of this width in x and y
  Key column(std::int64_t i, std::int64_t j) const;
  double margin_ = 1, reach_mm_ = 0;  // reach_mm_: the largest radius + margin added
  std::size_t tips_ = 0;
  static Key cell_key(std::int64_t i, std::int64_t j, std::int64_t k);
  std::unordered_map<std::string, std::unordered_set<Key>> seen_;  // per tool, its tips at half-margin resolution
  std::unordered_map<Key, std::vector<Tip>> columns_;
};

}  // namespace deflex::compensate
