#include "deflex/compensate/gouge.hpp"

#include <cmath>
#include <limits>

namespace deflex::compensate {

using V3 = Eigen::Vector3d;

namespace {

void note(GapSide& g, std::uint32_t line, double gap_mm, bool at_least = false) {
  ++g.points;
  if (g.lines.empty() || g.lines.back() != line) g.lines.push_back(line);
  if (std::fabs(gap_mm) > g.worst_mm) {
    g.worst_mm = std::fabs(gap_mm);
    g.worst_line = line;
    g.worst_at_least = at_least;
  }
}

// The contact with the smallest gap: from below, and for flat and bull-nose
// ends also from the four sides of the feed frame at mid-flank.
part::Contact nearest(const part::PartModel& part, const stiffness::Tool& t, const V3& tip, const V3& feed) {
  const part::CutterShape shape = part::cutter_shape(t);
  part::Contact best = part.contact(shape, tip, V3::Zero());
  if (t.type == stock::EndShape::ball) return best;
  const V3 side(-feed.y(), feed.x(), 0.0);
  const double r = 0.5 * t.diameter_mm, up = 0.5 * std::min(t.flute_length_mm, t.diameter_mm);
  for (const V3& d : {feed, V3(-feed), side, V3(-side)}) {
    const part::Contact c = part.contact(shape, tip, r * d + up * V3::UnitZ());
    if (c.gap_mm < best.gap_mm) best = c;
  }
  return best;
}

// Whether a move with this travel runs along the face of normal n (within
// 60 deg of it) rather than toward or away from it: the approach to a face,
// a plunge to a floor and the retract from them stand off the face on purpose
// until they arrive, and only a pass along the face that stands off it says
// the part and the program disagree.
bool along_face(const V3& travel, const V3& n) {
  const double len = travel.norm();
  return len < 1e-9 || std::fabs(travel.dot(n)) <= 0.5 * len;
}

}  // namespace

PartGaps part_gaps(const std::vector<interp::Motion>& motions, const part::PartModel& part,
                   const stiffness::ToolLibrary& tools, const std::function<std::string(const interp::Motion&)>& tool_of,
                   const engage::PathOptions& path, double gap_mm, double reach_mm) {
  PartGaps g;
  V3 feed = V3::UnitX();
  struct Sample {
    part::Contact c;
    V3 travel;
  };
  std::vector<Sample> at;  // one motion's, the storage kept from motion to motion
  for (const interp::Motion& m : motions) {
    if (m.kind == interp::MotionKind::rapid) continue;
    auto it = tools.tools.find(tool_of(m));
    if (it == tools.tools.end()) continue;  // the simulation reports a missing tool
    const std::vector<engage::Point3> v = engage::motion_vertices(m, path);
    at.clear();
    double gap_lo = std::numeric_limits<double>::infinity(), gap_hi = -gap_lo;
    for (std::size_t k = 1; k < v.size(); ++k) {
      const V3 tip(v[k][0], v[k][1], v[k][2]), prev(v[k - 1][0], v[k - 1][1], v[k - 1][2]);
      const V3 travel = tip - prev;
      V3 d = travel;
      d.z() = 0;
      if (d.norm() > 1e-9) feed = d.normalized();
      at.push_back({nearest(part, it->second, tip, feed), travel});
      gap_lo = std::min(gap_lo, at.back().c.gap_mm);
      gap_hi = std::max(gap_hi, at.back().c.gap_mm);
    }
    // A move whose gap closes or opens along it by more than half its
    // largest is a lead-in or lead-out (a tangential arc onto a face stands
    // off it on purpose until it arrives); a pass that stands off a face
    // keeps its gap.
    const bool approach = gap_hi - gap_lo > 0.5 * gap_hi;
    for (const Sample& sm : at) {
      const part::Contact& c = sm.c;
      ++g.points;
      if (c.gap_mm < -gap_mm) note(g.overcut, m.line, c.gap_mm, c.depth_at_least);
      else if (!approach && c.gap_mm > gap_mm && c.gap_mm <= reach_mm && c.on_face && along_face(sm.travel, c.normal))
        note(g.standoff, m.line, c.gap_mm);
    }
  }
  return g;
}

void merge(PartGaps& into, const PartGaps& piece) {
  into.points += piece.points;
  auto side = [](GapSide& a, const GapSide& b) {
    a.points += b.points;
    for (std::uint32_t l : b.lines)
      if (a.lines.empty() || a.lines.back() != l) a.lines.push_back(l);
    if (b.worst_mm > a.worst_mm) {  // the earlier on a tie, as note() keeps it
      a.worst_mm = b.worst_mm;
      a.worst_line = b.worst_line;
      a.worst_at_least = b.worst_at_least;
    }
  };
  side(into.overcut, piece.overcut);
  side(into.standoff, piece.standoff);
}

}  // namespace deflex::compensate
