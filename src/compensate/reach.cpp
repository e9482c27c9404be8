#include "deflex/compensate/reach.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::compensate {

using V3 = Eigen::Vector3d;

namespace {
constexpr std::int64_t kSpan = std::int64_t{1} << 31;

std::int64_t cell(double v, double h) { return static_cast<std::int64_t>(std::floor(v / h)); }
// Whether a face of outward normal n at p turns against the tool's surface
// nearest it: their normals within 78 deg of opposite.
constexpr double kFacing = -0.2;
bool facing(const ToolReach::Tip& t, const V3& p, const V3& n, double margin_mm) {
  const V3 tip = t.tip_mm.cast<double>();
  if (t.ball) {
    const V3 c = tip + V3(0, 0, t.radius_mm);
    return (p - c).norm() < 1e-9 || n.dot((p - c).normalized()) <= kFacing;
  }
  const V3 radial(p.x() - tip.x(), p.y() - tip.y(), 0);
  const bool side = radial.norm() > 1e-9 && n.dot(radial.normalized()) <= kFacing;
  const bool bottom = p.z() <= tip.z() + 0.25 * margin_mm && n.z() >= -kFacing;  // a face turned up under the tip
  return side || bottom;
}

}  // namespace

ToolReach::ToolReach(double margin_mm) : margin_(margin_mm) {
  if (!(margin_mm > 0)) throw Error(ErrorKind::internal, "tool reach: the margin must be > 0 mm");
}

ToolReach::Key ToolReach::column(std::int64_t i, std::int64_t j) const { return (i + kSpan / 2) * kSpan + (j + kSpan / 2); }

// Cells within +-2^20 of the origin (at 0.5 mm, half a kilometre) pack into one key.
ToolReach::Key ToolReach::cell_key(std::int64_t i, std::int64_t j, std::int64_t k) {
  constexpr std::int64_t span = std::int64_t{1} << 21;
  return ((i + span / 2) * span + (j + span / 2)) * span + (k + span / 2);
}

void ToolReach::add(const std::vector<interp::Motion>& motions, const stiffness::ToolLibrary& tools,
                    const std::function<std::string(const interp::Motion&)>& tool_of, const engage::PathOptions& path) {
  const double q = 0.5 * margin_;
  for (const interp::Motion& m : motions) {
    if (m.kind == interp::MotionKind::rapid) continue;
    const std::string id = tool_of(m);
    const auto it = tools.tools.find(id);
    if (it == tools.tools.end()) continue;
    const stiffness::Tool& t = it->second;
    const auto r = static_cast<float>(0.5 * t.diameter_mm);
    const auto l = static_cast<float>(std::min(t.flute_length_mm, t.stickout_mm));
    reach_mm_ = std::max(reach_mm_, r + margin_);
    std::unordered_set<Key>& seen = seen_[id];
    for (const engage::Point3& v : engage::motion_vertices(m, path)) {
      const Key h = cell_key(cell(v[0], q), cell(v[1], q), cell(v[2], q));
      if (!seen.insert(h).second) continue;  // a tip of this tool this close is in already
      columns_[column(cell(v[0], kColumnMm), cell(v[1], kColumnMm))].push_back(
          {Eigen::Vector3f(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])), r, l,
           t.type == stock::EndShape::ball});
      ++tips_;
    }
  }
}

bool ToolReach::reaches(const V3& p, const V3& normal) const {
  const auto n = static_cast<std::int64_t>(std::ceil(reach_mm_ / kColumnMm));
  const std::int64_t i0 = cell(p.x(), kColumnMm), j0 = cell(p.y(), kColumnMm);
  for (std::int64_t i = i0 - n; i <= i0 + n; ++i)
    for (std::int64_t j = j0 - n; j <= j0 + n; ++j) {
      const auto it = columns_.find(column(i, j));
      if (it == columns_.end()) continue;
      for (const Tip& t : it->second) {
        const V3 tip = t.tip_mm.cast<double>();
        const double dz = p.z() - tip.z(), rho = std::hypot(p.x() - tip.x(), p.y() - tip.y());
        if (rho > t.radius_mm + margin_ || dz < -margin_ || dz > t.flutes_mm + margin_) continue;
        if (facing(t, p, normal, margin_)) return true;
      }
    }
  return false;
}

std::vector<FacetPoint> ToolReach::reached_points(const std::vector<stock::Triangle>& surface, double spacing_mm) const {
  std::vector<FacetPoint> out;
  // One point per cell of spacing_mm and face (normals within 30 deg): a
  // finely faceted surface gives every vertex once per facet round it.
  std::unordered_map<Key, std::vector<std::size_t>> kept;
  const double same_face = std::cos(30 * 3.14159265358979323846 / 180);
  auto keep = [&](const V3& p, const V3& n) {
    std::vector<std::size_t>& in = kept[cell_key(cell(p.x(), spacing_mm), cell(p.y(), spacing_mm), cell(p.z(), spacing_mm))];
    for (std::size_t i : in)
      if (out[i].normal.dot(n) >= same_face) return;
    if (!reaches(p, n)) return;
    in.push_back(out.size());
    out.push_back({p, n});
  };
  for (const stock::Triangle& tr : surface) {
    const V3 a(tr.p[0].data()), b(tr.p[1].data()), c(tr.p[2].data());
    const V3 normal = (b - a).cross(c - a);
    if (normal.norm() < 1e-12) continue;  // a sliver: no face to speak of
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, static_cast<int>(std::ceil(longest / spacing_mm)));
    // The barycentric grid of n steps a side: every point within spacing_mm of one.
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const V3 p = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        keep(p, normal.normalized());
      }
  }
  return out;
}

}  // namespace deflex::compensate
