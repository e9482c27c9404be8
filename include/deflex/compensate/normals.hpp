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
//           contact point. Where those points do not determine it (the
//           first or last pass with no two passes on its one side within
//           reach, a single pass, points off a smooth surface), the source is
//           `undetermined`: the normal is the travel rule's guess, used for
//           the figures only, and compensation leaves the point alone (the
//           [left_alone] warning counts it).
//   travel  the rule of the tool geometry and the programmed travel: the wall
//           (horizontal, on the side the engaged edge cuts) for a flat or
//           bull-nose flank, else the normal to the travel in its vertical
//           plane, upward. It cannot see a slope across the feed direction.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>
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

enum class NormalSource : std::uint8_t { travel, path, part, undetermined };
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

// The path source fits each point's normal through the tip points of its
// ball-end tool's cutting moves within a window of the program: the block of
// kBlockMotions motions the point's motion lies in and the blocks before and
// after it (the same and the adjacent passes of any CAM path lie well within;
// a spring pass 10,000 passes later does not belong to the surface being cut).
// So memory is three blocks of points, whatever the program's length, and a
// program read in pieces gets the normals it gets whole.
class DesignNormals {
 public:
  static constexpr std::size_t kBlockMotions = 65536;
  // Appends the program's next motions to `more`; false at its end.
  using MotionSource = std::function<bool(std::vector<interp::Motion>& more)>;
  // design: the program as written (all motions). part may be null.
  // tool_of(m): the tool id of a motion (Settings::tool_override or "T<n>").
  DesignNormals(const std::vector<interp::Motion>& design, const part::PartModel* part,
                const stiffness::ToolLibrary& tools, const engage::PathOptions& path, double part_reach_mm,
                std::function<std::string(const interp::Motion&)> tool_of);
  // The same for a program read motion by motion as the normals need it: the
  // source runs ahead of the motion asked about by a block at most.
  DesignNormals(MotionSource source, const part::PartModel* part, const stiffness::ToolLibrary& tools,
                const engage::PathOptions& path, double part_reach_mm,
                std::function<std::string(const interp::Motion&)> tool_of);
  ~DesignNormals();
  DesignNormals(const DesignNormals&) = delete;

  // At a CL sample of the program's motion `motion` (its index; the design
  // motion), whose programmed tip is design_tip_mm. Thread-safe.
  SurfaceNormal at(const engage::CLSample& cl, const engage::Metrics& mt, const stiffness::Tool& t,
                   const interp::Motion& design, const Eigen::Vector3d& design_tip_mm, std::size_t motion) const;

  bool has_part() const { return part_ != nullptr; }
  // In pieces: no point of a motion before `motion` is asked about any more
  // (the memory of the windows behind it goes).
  void forget_before(std::size_t motion);

 private:
  using Clouds = std::map<std::string, std::vector<Eigen::Vector3d>>;  // per ball-end tool id
  using Trees = std::map<std::string, std::unique_ptr<part::PathNormals>>;
  void add_points(const interp::Motion& m, Clouds& into) const;
  const Clouds& block(std::size_t b) const;                    // under mutex_
  std::shared_ptr<const Trees> window(std::size_t b) const;    // under mutex_

  const part::PartModel* part_;
  double reach_mm_;
  const stiffness::ToolLibrary* tools_;
  engage::PathOptions path_options_;
  std::function<std::string(const interp::Motion&)> tool_of_;
  const std::vector<interp::Motion>* design_ = nullptr;  // whole program, or:
  mutable MotionSource source_;
  mutable std::size_t read_ = 0;  // motions the source gave
  mutable bool source_done_ = false;
  std::size_t forgotten_ = 0;     // blocks before it are dropped for good
  mutable std::mutex mutex_;
  mutable std::map<std::size_t, Clouds> blocks_;
  struct Window {
    std::shared_ptr<const Trees> trees;
    std::uint64_t used = 0;  // when last asked for (a whole program drops the least recent)
  };
  mutable std::map<std::size_t, Window> windows_;
  mutable std::uint64_t clock_ = 0;
};

}  // namespace deflex::compensate
