#include "deflex/compensate/normals.hpp"

#include <algorithm>
#include <mutex>

#include "deflex/diag/diagnostics.hpp"
#include <cmath>

namespace deflex::compensate {

using V3 = Eigen::Vector3d;

const char* to_string(NormalSource s) {
  switch (s) {
    case NormalSource::part: return "part";
    case NormalSource::path: return "path";
    case NormalSource::undetermined: return "undetermined";
    case NormalSource::travel: break;
  }
  return "travel";
}

bool flank_cut(const engage::Metrics& mt, const stiffness::Tool& t) {
  return t.type != stock::EndShape::ball && mt.ap_mm > std::max(0.5 * t.corner_radius_mm, 0.2) &&
         mt.ae_mm < 0.95 * t.diameter_mm;
}

namespace {

// The travel rule at a sample with direction dir and XY feed direction (fx, fy).
V3 rule_normal(const V3& dir, double fx, double fy, const engage::Metrics& mt, const stiffness::Tool& t) {
  const V3 yf(-fy, fx, 0.0);  // Y' of the feed frame
  // Morelli 2021: down-milling leaves the wall on the -Y' side.
  if (flank_cut(mt, t)) return mt.up_share > 0.5 ? V3(-yf) : yf;
  V3 n = V3::UnitZ() - dir.dot(V3::UnitZ()) * dir;
  const double len = n.norm();
  return len > 1e-9 ? V3(n / len) : V3::UnitZ();
}

}  // namespace

// The direction is the design's, not the displaced trial motion's: on a 0.4 mm
// move a 20 um change of offset tilts it by 3 degrees, which is 10 um of error
// where the tool deflects 0.2 mm along the feed.
V3 travel_normal(const engage::CLSample& cl, const engage::Metrics& mt, const stiffness::Tool& t,
                 const interp::Motion& design) {
  const auto& p = cl.point;
  V3 dir(p.dir[0], p.dir[1], p.dir[2]);
  double fx = p.feed_x, fy = p.feed_y;
  if (design.kind == interp::MotionKind::linear || design.kind == interp::MotionKind::rapid) {
    const V3 d(design.end_mm[0] - design.start_mm[0], design.end_mm[1] - design.start_mm[1],
               design.end_mm[2] - design.start_mm[2]);
    if (d.norm() > 0) {
      dir = d.normalized();
      const double h = std::hypot(dir.x(), dir.y());
      if (h > 1e-6) fx = dir.x() / h, fy = dir.y() / h;
    }
  }  // arcs move whole: the same tangent
  return rule_normal(dir, fx, fy, mt, t);
}

DesignNormals::DesignNormals(const std::vector<interp::Motion>& design, const part::PartModel* part,
                             const stiffness::ToolLibrary& tools, const engage::PathOptions& path,
                             double part_reach_mm, std::function<std::string(const interp::Motion&)> tool_of)
    : part_(part), reach_mm_(part_reach_mm), tools_(&tools), path_options_(path), tool_of_(std::move(tool_of)),
      design_(&design) {}

DesignNormals::DesignNormals(MotionSource source, const part::PartModel* part, const stiffness::ToolLibrary& tools,
                             const engage::PathOptions& path, double part_reach_mm,
                             std::function<std::string(const interp::Motion&)> tool_of)
    : part_(part), reach_mm_(part_reach_mm), tools_(&tools), path_options_(path), tool_of_(std::move(tool_of)),
      source_(std::move(source)) {}

DesignNormals::~DesignNormals() = default;

namespace {
// Sorted, each point once: the same cloud whatever order the points came in
// (a point a program passes twice adds nothing to the surface).
void compact(std::vector<V3>& v) {
  std::sort(v.begin(), v.end(), [](const V3& a, const V3& b) {
    return a.x() != b.x() ? a.x() < b.x() : a.y() != b.y() ? a.y() < b.y() : a.z() < b.z();
  });
  v.erase(std::unique(v.begin(), v.end()), v.end());
}
}  // namespace

// The tip points of a ball-end tool's cutting move. Plunges and moves steeper
// than 80 degrees are left out: they stack points over one XY and the tip
// surface is a height field.
void DesignNormals::add_points(const interp::Motion& m, Clouds& into) const {
  if (m.kind == interp::MotionKind::rapid) return;
  const std::string id = tool_of_(m);
  auto t = tools_->tools.find(id);
  if (t == tools_->tools.end() || t->second.type != stock::EndShape::ball) return;
  const double dxy = std::hypot(m.end_mm[0] - m.start_mm[0], m.end_mm[1] - m.start_mm[1]);
  const double dz = std::fabs(m.end_mm[2] - m.start_mm[2]);
  if (m.kind == interp::MotionKind::linear && dz > 5.67 * dxy) return;
  std::vector<V3>& c = into[id];
  const std::vector<engage::Point3> v = engage::motion_vertices(m, path_options_);
  for (std::size_t k = 1; k < v.size(); ++k) c.emplace_back(v[k][0], v[k][1], v[k][2]);
}

const DesignNormals::Clouds& DesignNormals::block(std::size_t b) const {
  auto it = blocks_.find(b);
  if (it != blocks_.end()) return it->second;
  if (design_) {
    Clouds& c = blocks_[b];
    const std::size_t end = std::min(design_->size(), (b + 1) * kBlockMotions);
    for (std::size_t i = b * kBlockMotions; i < end; ++i) add_points((*design_)[i], c);
    return c;
  }
  // From the source, in order: every block up to b.
  std::vector<interp::Motion> more;
  while (!source_done_ && read_ < (b + 1) * kBlockMotions) {
    more.clear();
    if (!source_(more)) source_done_ = true;
    for (const interp::Motion& m : more) add_points(m, blocks_[read_++ / kBlockMotions]);
  }
  if (b < forgotten_)
    throw Error(ErrorKind::internal, "design normals: block " + std::to_string(b) + " asked for after it was dropped");
  return blocks_[b];
}

std::shared_ptr<const DesignNormals::Trees> DesignNormals::window(std::size_t b) const {
  auto it = windows_.find(b);
  if (it != windows_.end()) {
    it->second.used = ++clock_;
    return it->second.trees;
  }
  Clouds all;
  for (std::size_t k = b ? b - 1 : 0; k <= b + 1; ++k)
    for (const auto& [id, pts] : block(k)) all[id].insert(all[id].end(), pts.begin(), pts.end());
  auto trees = std::make_shared<Trees>();
  for (auto& [id, pts] : all) {
    compact(pts);
    (*trees)[id] = std::make_unique<part::PathNormals>(std::move(pts));
  }
  windows_[b] = {trees, ++clock_};
  // A whole program: the simulation beside the mirror pass may run far ahead
  // of it; the least recently used window goes (made again if asked for).
  // In pieces the caller says what is done with (forget_before).
  if (design_) {
    while (windows_.size() > 4)
      windows_.erase(std::min_element(windows_.begin(), windows_.end(), [](const auto& x, const auto& y) {
        return x.second.used < y.second.used;
      }));
    while (blocks_.size() > 8) blocks_.erase(blocks_.begin());
  }
  return trees;
}

void DesignNormals::forget_before(std::size_t motion) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::size_t b = motion / kBlockMotions;
  // Window b - 1 holds blocks b - 2 .. b: the earliest any later point asks for.
  while (!windows_.empty() && windows_.begin()->first + 1 < b) windows_.erase(windows_.begin());
  if (b >= 2) forgotten_ = std::max(forgotten_, b - 2);
  while (!blocks_.empty() && blocks_.begin()->first < forgotten_) blocks_.erase(blocks_.begin());
}

SurfaceNormal DesignNormals::at(const engage::CLSample& cl, const engage::Metrics& mt, const stiffness::Tool& t,
                                const interp::Motion& design, const V3& design_tip_mm, std::size_t motion) const {
  SurfaceNormal s;
  s.n = travel_normal(cl, mt, t, design);
  if (part_) {
    // Flank cuts: search from the wall side at mid-flank (the wall lies
    // against the travel rule's normal, which points from it to the tool:
    // where the flat end also stands on a floor, the last level of a pocket
    // wall, the floor is as near as the wall and only the side decides);
    // else from below.
    V3 hint = V3::Zero();
    if (flank_cut(mt, t)) hint = -0.5 * t.diameter_mm * s.n + 0.5 * mt.ap_mm * V3::UnitZ();
    const part::Contact c = part_->contact(part::cutter_shape(t), design_tip_mm, hint);
    if (c.found && std::fabs(c.gap_mm) <= reach_mm_) {
      s.n = c.normal;
      s.source = NormalSource::part;
      s.part_gap_mm = c.gap_mm;
    }
    return s;
  }
  if (t.type == stock::EndShape::ball) {
    s.source = NormalSource::undetermined;  // unless the neighbouring points give it
    std::shared_ptr<const Trees> w;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      w = window(motion / kBlockMotions);
    }
    auto it = w->find(t.id);
    if (it != w->end())
      if (auto n = it->second->normal_at(design_tip_mm)) {
        s.n = *n;
        s.source = NormalSource::path;
      }
  }
  return s;
}

}  // namespace deflex::compensate
