#include "contour.hpp"

#include <algorithm>
#include <cmath>

#include "deflex/interp/arc.hpp"

namespace deflex::compensate::detail {

// Under G41/G42: where each programmed point goes so that the control's
// centre path runs through the compensated centre points (per motion of
// `motions`; meaningful where m.comp and not m.corner). The control offsets
// the contour: at a corner where it meets the offset lines (an inside
// corner; on Fanuc also an outside one up to 90 deg, and every small kink of
// a split line), the centre point is V = Q + r (nA + nB) / (1 + nA.nB), nA and
// nB the unit normals towards the tool of the lines on both sides, parallel
// to their centre lines; where it ends the line perpendicular (LinuxCNC at a
// small kink; before G40), V = Q + r nA. Both are inverted on the
// compensated centre lines. Elsewhere (next to an arc, or to the pieces
// round an outside corner, which deflex moves with the corner) the point
// moves by the offset, the first order of the same.
std::vector<interp::Vec3> contour_targets(const std::vector<interp::Motion>& ms, const std::vector<V3>& offsets,
                                          const profile::Dialect& d) {
  const std::size_t n = ms.size();
  if (std::none_of(ms.begin(), ms.end(), [](const interp::Motion& m) { return m.comp != 0; })) return {};
  std::vector<interp::Vec3> t(n);
  auto off = [&](std::size_t i) { return offsets.empty() ? V3(V3::Zero()) : offsets[i]; };
  auto centre = [&](std::size_t i, bool end) {  // compensated centre point, XY
    const interp::Vec3& p = end ? ms[i].end_mm : ms[i].start_mm;
    const V3 o = end ? off(i) : i > 0 ? off(i - 1) : V3(V3::Zero());
    return Eigen::Vector2d(p[0] + o[0], p[1] + o[1]);
  };
  auto line_xy = [&](std::size_t i) {
    const interp::Motion& m = ms[i];
    return m.comp && !m.corner && !interp::is_arc(m) && m.moves_xy();
  };
  for (std::size_t i = 0; i < n; ++i) {
    const interp::Motion& m = ms[i];
    const V3 o = off(i);
    for (int a = 0; a < 3; ++a) t[i][a] = m.contour_end_mm[a] + o[a];
    // A Z move at a corner: its block has only Z; the XY is where the block
    // before it put the corner.
    if (m.comp && !m.corner && i > 0 && ms[i - 1].comp && !m.moves_xy()) {
      t[i][0] = t[i - 1][0];
      t[i][1] = t[i - 1][1];
      continue;
    }
    if (!line_xy(i) || !m.compensable()) continue;
    const Eigen::Vector2d va = centre(i, true), da = (va - centre(i, false)).normalized();
    const Eigen::Vector2d na = m.comp * Eigen::Vector2d(-da.y(), da.x());
    const double r = m.comp_radius_mm;
    std::size_t j = i + 1;  // the next motion with XY travel (Z moves at the corner stand between)
    while (j < n && ms[j].comp && !ms[j].corner && !ms[j].moves_xy()) ++j;
    Eigen::Vector2d q = va - r * na;  // perpendicular end
    if (j < n && line_xy(j) && !ms[j].corner) {
      const Eigen::Vector2d db = (centre(j, true) - centre(j, false)).normalized();
      const Eigen::Vector2d nb = m.comp * Eigen::Vector2d(-db.y(), db.x());
      // The corner as the interpreter classed it on the program as written
      // (the path deflex simulated): a corner piece follows where it went round.
      auto dir = [&](std::size_t k) {
        return Eigen::Vector2d(ms[k].end_mm[0] - ms[k].start_mm[0], ms[k].end_mm[1] - ms[k].start_mm[1]).normalized();
      };
      const Eigen::Vector2d oa = dir(i), ob = dir(j);
      const double cross = oa.x() * ob.y() - oa.y() * ob.x(), turn = std::atan2(cross, oa.dot(ob));
      const bool meet = d.comp_corner == profile::Dialect::CompCorner::arc ? m.comp * cross > 0 && std::fabs(turn) > 0.05
                                                                           : true;
      if (meet) q = va - r * (na + nb) / (1 + na.dot(nb));
    } else if (j < n && ms[j].comp && ms[j].corner && d.comp_corner == profile::Dialect::CompCorner::intersection) {
      // Fanuc's points round an outside corner next: this line ends `ext`
      // past the corner along itself (r past an acute one, where the pieces
      // start), so the control's end of the compensated line is where deflex
      // simulated it; the pieces (in the air) follow within r times the turn.
      const Eigen::Vector2d oa = Eigen::Vector2d(m.end_mm[0] - m.start_mm[0], m.end_mm[1] - m.start_mm[1]).normalized();
      const double ext_mm = (m.end_mm[0] - m.contour_end_mm[0]) * oa.x() + (m.end_mm[1] - m.contour_end_mm[1]) * oa.y();
      q = va - r * na - ext_mm * da;
    } else if (j < n && ms[j].comp && (ms[j].corner || !line_xy(j))) {
      // LinuxCNC's arc round the corner next: it moves with this motion's
      // offset, centred on the corner point moved by it (this line's end
      // slides along it by r times its turn); or an arc next: first order.
      continue;
    }
    t[i][0] = q.x();
    t[i][1] = q.y();
  }
  return t;
}


}  // namespace deflex::compensate::detail
