// What simulate() and the mirror stream share (compensate.cpp, mirror.cpp):
// the tool models, the per-point physics, one run through the stock. Private
// to src/compensate/.
#pragma once
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "deflex/compensate/collision.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/engage/simulator.hpp"
#include "deflex/force/cutter.hpp"
#include "deflex/force/flank.hpp"
#include "deflex/force/mechanistic.hpp"
#include "deflex/stability/model.hpp"
#include "deflex/stiffness/beam.hpp"

namespace deflex::compensate::detail {

// A copy of a Z-map through its public tile interface (a simulation cuts its
// own copy of the initial stock).
stock::ZMap clone(const stock::ZMap& z);

// Everything about one tool that the simulation needs, built once.
struct ToolModel {
  stiffness::Tool tool;
  force::CutterSlices slices;
  stiffness::ComplianceTable compliance;
  force::AngleGrid grid;
  // Flat and bull-nose ends (flank cuts): C(z, z') between the slices of the
  // tool chain alone (axisymmetric: the same in any frame turned about Z), and
  // the machine structure's constant 3x3 in series, machine axes, added per
  // point in the feed frame.
  force::SliceCompliance flank_c;
  stiffness::Compliance structure = stiffness::Compliance::Zero();
  Assembly assembly;  // its neck, shank and the machine's holder (collision.hpp)
  // The stability limit at each immersion (Point::ap_limit_mm); null where
  // the tool has no dynamic model, stability_unchecked saying why.
  std::shared_ptr<const stability::LimitCache> stability;
  std::string stability_unchecked;
};

const ToolModel& model_for(std::map<std::string, ToolModel>& cache, const std::string& id, const Physics& ph,
                           const Settings& s);

// The per-point physics of one CL sample: forces, deflection, surface error.
// Shared by simulate() and the mirror stream, so both report the same numbers.
// m: the motion as run; design: as programmed (the surface normal's), the
// program's motion `index` (the normals' window).
// a, b: the offsets of the run motion's start and end from the design's, so
// that the design tip of the sample (the surface normal's) is known.
// limits: what --feed-limit keeps the point within (Point::feed_share).
struct FeedLimits {
  double force_N = 0;                              // 0: no feed limit, feed_share stays 1
  const profile::SpindleRating* spindle = nullptr;  // its S1 curve too (null: none)
};
FeedLimits feed_limits(const Physics& ph, const Settings& s);
Point point_of(const engage::CLSample& cl, const engage::Metrics& mt, const force::Engagement& eng, const ToolModel& tm,
               const interp::Motion& m, const interp::Motion& design, std::size_t index, const V3& a, const V3& b,
               const DesignNormals& normals, const force::Coefficients& k, const FeedLimits& limits,
               const WorkpieceCompliance* workpiece, std::vector<force::Vec3>& rev, bool keep_profile = false);

// A sample's point with its place alone (line, motion's tool, tip): the
// point of a run without physics (Settings::geometry_only), and where
// point_of starts.
Point geometry_point(const engage::CLSample& cl, const interp::Motion& design);

// Point::stock_depth_mm (see its definition).
double stock_depth(const stock::ZMap& z, const engage::CLSample& cl, double r);

// Motion m with its start moved by a and its end (and an arc's centre) by b.
interp::Motion moved(interp::Motion m, const V3& a, const V3& b);

// --feed-limit: the feed of a cutting block whose points need a share of it
// (the least Point::feed_share of its points) to keep their peak force under
// the limit and their torque and power within the spindle's S1 curve, rounded
// down to 0.1 mm/min. The share is exact for the model (the cutting forces
// grow with f_z, the edge forces do not; scaling F by limit / peak alone would
// leave the peak above the limit by up to the edge forces' part). A share is
// never taken below min_feed_share: where the edge forces alone exceed the
// limit no feed keeps it, and the plausibility checks say so (feed_limit).
inline constexpr double min_feed_share = 0.1;
inline double lowered_feed(double feed_mm_per_min, double share) {
  return std::max(std::floor(feed_mm_per_min * std::max(share, min_feed_share) * 10.0) / 10.0, 0.1);
}

// The stock and the tool's simulator along one run through the program.
class Run {
 public:
  // `own` (may be null): the map to cut, else a copy of the physics' stock.
  // `work`: the simulators' sample work (engage::Simulator::set_sample_work).
  Run(const Physics& ph, const Settings& s, engage::PointSink sink = {}, std::unique_ptr<stock::ZMap> own = nullptr,
      engage::SampleWork work = {})
      : ph_(ph), s_(s), sink_(std::move(sink)), work_(std::move(work)), z_(std::move(own)) {
    if (!ph.stock) throw Error(ErrorKind::settings, "no stock: give {stock} box:X0,Y0,Z0,X1,Y1,Z1 or a solid file");
    if (!z_) z_ = std::make_unique<stock::ZMap>(clone(*ph.stock));
    so_.path.cl_spacing_mm = s.cl_spacing_mm;
    so_.threads = s.threads;
    so_.evaluate = !s.geometry_only;
  }
  // Before motion m: false for a rapid before the first cut (not run); a cut
  // with another tool finishes the old simulator and starts the tool's own.
  bool prepare(const interp::Motion& m) {
    if (m.kind == interp::MotionKind::rapid && !sim_) return false;
    const std::string id = tool_id(m, s_);
    if (m.kind != interp::MotionKind::rapid && id != id_) {
      if (sim_) sim_->finish();
      if (m.tool == 0 && s_.tool_override.empty())
        throw Error(ErrorKind::input, "line " + std::to_string(m.line) + ": cutting with no tool (T.. M6) selected; give {tool}");
      tm_ = &model_for(models_, id, ph_, s_);
      engage::Process proc;
      proc.spindle_rpm = m.spindle_rpm > 0 ? m.spindle_rpm : 1.0;
      proc.fz_mm = m.feed_mm_per_min / (proc.spindle_rpm * tm_->slices.cutter.flutes);
      sim_ = std::make_unique<engage::Simulator>(*z_, tm_->slices, proc, so_, sink_);
      if (work_) sim_->set_sample_work(work_);
      id_ = id;
      ++tool_changes_;
    }
    return true;
  }
  engage::Simulator& sim() { return *sim_; }
  // Whether prepare(m) would keep the simulator (a rapid, or a cut with its tool).
  bool keeps(const interp::Motion& m) const {
    return sim_ && (m.kind == interp::MotionKind::rapid || tool_id(m, s_) == id_);
  }
  const engage::SimOptions& options() const { return so_; }  // every simulator's
  const stock::ZMap& zmap() const { return *z_; }
  const ToolModel& tool() const { return *tm_; }
  std::size_t tool_changes() const { return tool_changes_; }
  void finish() {
    if (sim_) sim_->finish();
  }

 private:
  const Physics& ph_;
  const Settings& s_;
  engage::PointSink sink_;
  engage::SampleWork work_;
  std::unique_ptr<stock::ZMap> z_;
  engage::SimOptions so_;
  std::map<std::string, ToolModel> models_;
  const ToolModel* tm_ = nullptr;
  std::string id_;
  std::unique_ptr<engage::Simulator> sim_;
  std::size_t tool_changes_ = 0;
};

}  // namespace deflex::compensate::detail
