// The outward normal of the design surface at a CL sample: the direction the
// surface error e = delta . n and the mirror offset act along.
//
// Sources, best first (Point::normal_source, points.csv `normal_source`):
//   part    the part model (--part): the contact of the cutter with the design
//           surface at the programmed tip (part/part.hpp): for a ball end the
//           part point closest to its centre; for flat and bull-nose ends the
//           point closest to the active surface (corner torus, flank, end face),
//           searched from the side the tool geometry says cuts. Used where the
//           contact lies within part_reach_mm; farther, the tool is not at the
//           part surface and the next source applies.
//   path    ball ends without a part model: the normal of the tip surface fitted
//           through the neighbouring CL points of the same and the adjacent
//           passes (part/path_normals.hpp), which is the part's normal at the
//           contact point.
//   travel  the rule of the tool geometry and the programmed travel: the wall
//           (horizontal, on the side the engaged edge cuts) for a flat or
//           bull-nose flank, else the normal to the travel in its vertical
//           plane, upward. It cannot see a slope across the feed direction.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "deflex/engage/engagement.hpp"
#include "deflex/engage/path.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/part/part.hpp"
#include "deflex/part/path_normals.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::compensate {

enum class NormalSource : std::uint8_t { travel, path, part };
const char* to_string(NormalSource s);

struct SurfaceNormal {
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  NormalSource source = NormalSource::travel;
  double part_gap_mm = 0;  // part only: signed gap of the cutter to the part (> 0 stands off)
};

// A flat or bull-nose end cutting with its flank (a_p above the corner, a_e
// below the diameter): the travel rule's wall normal, and the flank error
// profile of the compensation (compensate.hpp).
bool flank_cut(const engage::Metrics& mt, const stiffness::Tool& t);

// The travel rule at a sample whose travel direction is that of `design`.
Eigen::Vector3d travel_normal(const engage::CLSample& cl, const engage::Metrics& mt, const stiffness::Tool& t,
                              const interp::Motion& design);

class DesignNormals {
 public:
  // design: the program as written (all motions; the path source uses the CL
  // samples of the cutting moves of each ball-end tool). part may be null.
  // tool_of(m): the tool id of a motion (Settings::tool_override or "T<n>").
  DesignNormals(const std::vector<interp::Motion>& design, const part::PartModel* part,
                const stiffness::ToolLibrary& tools, const engage::PathOptions& path, double part_reach_mm,
                const std::function<std::string(const interp::Motion&)>& tool_of);
  // The same for a program given in pieces: add() the motions of each, then
  // build() before the first at().
  DesignNormals(const part::PartModel* part, const stiffness::ToolLibrary& tools, const engage::PathOptions& path,
                double part_reach_mm, std::function<std::string(const interp::Motion&)> tool_of);
  void add(const std::vector<interp::Motion>& design);
  void build();
  DesignNormals(const DesignNormals&) = delete;

  // At a CL sample whose programmed (design) tip is design_tip_mm. Thread-safe.
  SurfaceNormal at(const engage::CLSample& cl, const engage::Metrics& mt, const stiffness::Tool& t,
                   const interp::Motion& design, const Eigen::Vector3d& design_tip_mm) const;

  bool has_part() const { return part_ != nullptr; }

 private:
  const part::PartModel* part_;
  double reach_mm_;
  const stiffness::ToolLibrary* tools_ = nullptr;
  engage::PathOptions path_options_;
  std::function<std::string(const interp::Motion&)> tool_of_;
  // The tip points of each ball-end tool, sorted and each once (a point a
  // program passes again, as a spring pass does, adds nothing to the surface):
  // memory grows with the surface, not with the program.
  struct Cloud {
    std::vector<Eigen::Vector3d> pts;
    std::size_t settled = 0;  // size after the last compaction
  };
  std::map<std::string, Cloud> clouds_;
  std::map<std::string, std::unique_ptr<part::PathNormals>> path_;  // per ball-end tool id
};

}  // namespace deflex::compensate
