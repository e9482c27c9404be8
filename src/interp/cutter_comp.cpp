#include "cutter_comp.hpp"

#include <cmath>
#include <cstdio>

#include "deflex/interp/arc.hpp"

namespace deflex::interp::detail {
namespace {

using P2 = std::array<double, 2>;

P2 xy(const Vec3& v) { return {v[0], v[1]}; }
P2 plus(const P2& a, const P2& b, double s = 1.0) { return {a[0] + s * b[0], a[1] + s * b[1]}; }
P2 sub(const P2& a, const P2& b) { return {a[0] - b[0], a[1] - b[1]}; }
double dot(const P2& a, const P2& b) { return a[0] * b[0] + a[1] * b[1]; }
double cross(const P2& a, const P2& b) { return a[0] * b[1] - a[1] * b[0]; }
double norm(const P2& a) { return std::hypot(a[0], a[1]); }
Vec3 at(const P2& p, double z) { return {p[0], p[1], z}; }

// LinuxCNC neither goes round an arc nor meets the offsets at a corner that
// turns by at most this (rs274ngc's TOLERANCE_CONCAVE_CORNER; checked with
// rs274: 2.86 deg gives no arc, 2.87 deg one).
constexpr double kArcMinTurnRad = 0.05;

// Fanuc meets the offsets at an outside corner turning up to 90 deg and goes
// round by two points beyond; at 90 deg both give the same point. deflex
// takes turns up to 95 deg as the first: a CAM program's right angles stay
// one point when the compensation turns a side by a few hundredths of a
// degree (the two differ by at most 0.07 r, in the air round the corner).
// Turns below this are tangents: the perpendicular points are within
// 6e-7 mm for r = 6 mm, where the offsets of two nearly concentric arcs cross
// far from the corner (or not at all).
constexpr double kTangentRad = 1e-7;

constexpr double kObtuseMaxTurnRad = 95.0 * M_PI / 180.0;

std::string fmt(const char* f, double a, double b = 0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, f, a, b);
  return buf;
}

// An offset element as a primitive: a line (point, unit direction) or a
// circle (centre, radius).
struct Prim {
  bool circle;
  P2 p, d;
  double r;
};

// Intersections of two primitives (0, 1 or 2 points).
std::vector<P2> meet(const Prim& a, const Prim& b) {
  std::vector<P2> out;
  if (!a.circle && !b.circle) {
    const double c = cross(a.d, b.d);
    if (std::fabs(c) < 1e-12) return out;
    out.push_back(plus(a.p, a.d, cross(sub(b.p, a.p), b.d) / c));
  } else if (a.circle != b.circle) {
    const Prim& l = a.circle ? b : a;
    const Prim& c = a.circle ? a : b;
    const P2 w = sub(l.p, c.p);
    const double hb = dot(l.d, w), cc = dot(w, w) - c.r * c.r, disc = hb * hb - cc;
    if (disc < 0) return out;
    const double s = std::sqrt(disc);
    out.push_back(plus(l.p, l.d, -hb - s));
    out.push_back(plus(l.p, l.d, -hb + s));
  } else {
    const P2 w = sub(b.p, a.p);
    const double dd = norm(w);
    if (dd < 1e-12) return out;
    const double x = (dd * dd + a.r * a.r - b.r * b.r) / (2 * dd), h2 = a.r * a.r - x * x;
    if (h2 < 0) return out;
    const P2 u{w[0] / dd, w[1] / dd}, m = plus(a.p, u, x);
    const double h = std::sqrt(h2);
    out.push_back({m[0] - h * u[1], m[1] + h * u[0]});
    out.push_back({m[0] + h * u[1], m[1] - h * u[0]});
  }
  return out;
}

}  // namespace

std::array<double, 2> CutterComp::tangent(const Motion& m, bool at_end) const {
  if (!is_arc(m)) {
    const P2 d = sub(xy(m.end_mm), xy(m.start_mm));
    const double n = norm(d);
    return {d[0] / n, d[1] / n};
  }
  const P2 v = sub(xy(at_end ? m.end_mm : m.start_mm), xy(m.center_mm));
  const double n = norm(v);
  return m.kind == MotionKind::arc_ccw ? P2{-v[1] / n, v[0] / n} : P2{v[1] / n, -v[0] / n};
}

std::array<double, 2> CutterComp::normal(const Motion& m, bool at_end) const {
  const P2 t = tangent(m, at_end);
  return {-side_ * t[1], side_ * t[0]};  // left of the travel for G41, right for G42
}

double CutterComp::offset_radius(const Motion& m) const {
  const P2 s = xy(m.start_mm), c = xy(m.center_mm);
  const double rho = norm(sub(s, c));
  return dot(normal(m, false), sub(c, s)) > 0 ? rho - r_ : rho + r_;
}

std::string CutterComp::start(int side, double radius_mm) {
  if (state_ != State::off) {
    if (side == side_ && radius_mm == r_) return {};
    return "a change of side or radius (G41/G42, D) while cutter compensation is on is not interpreted: "
           "cancel it with G40 first";
  }
  side_ = side;
  r_ = radius_mm;
  if (radius_mm > 0) state_ = State::starting;  // radius 0: the centre path is the contour
  return {};
}

// The offset element of `a` (at its end) or `b` (at its start) as a primitive.
bool CutterComp::intersect(const Element& a, const Motion& b, const Vec3& near, Vec3& x) const {
  auto prim = [&](const Motion& m, bool at_end) {
    const P2 p = xy(at_end ? m.end_mm : m.start_mm);
    if (is_arc(m)) return Prim{true, xy(m.center_mm), {0, 0}, offset_radius(m)};
    return Prim{false, plus(p, normal(m, at_end), r_), tangent(m, at_end), 0};
  };
  const std::vector<P2> pts = meet(prim(a.m, true), prim(b, false));
  if (pts.empty()) return false;
  // The crossing that trims both elements (behind the corner along the
  // first, ahead of it along the second), the nearest such: where an arc
  // meets a line it turns back on, both crossings are as near.
  const P2 n = xy(near), c = xy(a.m.end_mm), ta = tangent(a.m, true), tb = tangent(b, false);
  auto score = [&](const P2& x) {
    const bool trims = dot(sub(x, c), ta) <= 1e-9 && dot(sub(x, c), tb) >= -1e-9;
    return norm(sub(x, n)) + (trims ? 0.0 : 1e6);
  };
  P2 best = pts[0];
  for (const P2& p : pts)
    if (score(p) < score(best)) best = p;
  // An intersection far from the corner is another crossing of the offset
  // curves, not the one the control meets here.
  if (norm(sub(best, n)) > 4 * r_ + 1e-6) return false;
  x = at(best, near[2]);
  return true;
}

// The corner between the held element `a` and the next element `b`: where
// `a`'s centre path ends (a_end), where `b`'s starts, and the pieces between.
std::string CutterComp::corner(Element& a, const Motion& b, Vec3& b_start, std::vector<Motion>& pieces) {
  const P2 p = xy(a.m.end_mm);
  const P2 ta = tangent(a.m, true), tb = tangent(b, false);
  const P2 na = normal(a.m, true), nb = normal(b, false);
  const P2 pa = plus(p, na, r_), pb = plus(p, nb, r_);
  const double c = cross(ta, tb), d = dot(ta, tb), turn = std::atan2(c, d);
  const double za = a.m.end_mm[2], zb = b.start_mm[2];
  Vec3 a_end = at(pa, za);
  b_start = at(pb, zb);
  auto piece = [&](MotionKind k, const P2& s, const P2& e) {
    Motion m = b;
    m.kind = k;
    m.start_mm = at(s, zb);
    m.end_mm = at(e, zb);
    m.center_mm = at(p, zb);
    m.corner = true;
    // The line of the block that ends at the corner: the block after it may
    // be split by blocks deflex inserts before it, this one always ends there.
    m.line = a.m.line;
    pieces.push_back(m);
  };
  const MotionKind line = b.kind == MotionKind::rapid ? MotionKind::rapid : MotionKind::linear;
  if (a.entry && startup_ == Startup::perpendicular_next) {
    a_end = at(pb, za);  // Fanuc type A: perpendicular to the next move's start
  } else if (std::fabs(turn) < kTangentRad) {
    // Tangent: the perpendicular points coincide (to r kTangentRad).
  } else if (std::fabs(c) < 1e-12) {
    // The contour turns back on itself: where an arc curls away the offsets
    // still meet (rs274 takes that point too); two lines never do.
    Vec3 x;
    if (!intersect(a, b, at(p, za), x)) return "the contour turns back on itself: cutter compensation cannot follow it";
    a_end = x;
    b_start = at(xy(x), zb);
  } else if (corner_ == Corner::arc && std::fabs(turn) <= kArcMinTurnRad) {
    // LinuxCNC, a small turn either way: the first element ends at its
    // perpendicular point and the next starts there (rs274: G1 X20 Y0.01
    // after G1 X0 Y0 ends at X19.997 Y6.01 with r 6).
    b_start = at(pa, zb);
  } else if (corner_ == Corner::intersection && side_ * c < 0 && (is_arc(a.m) || is_arc(b)) &&
             std::fabs(turn) <= kArcMinTurnRad) {
    // Fanuc, a small outside turn at an arc: the perpendicular points, as
    // LinuxCNC (no connecting lines; they would be at most r 0.025 long). A
    // tangent arc stays so when the compensation turns its neighbour a little.
    b_start = at(pa, zb);
  } else if (side_ * c > 0) {
    // Inside corner: the offsets meet.
    Vec3 x;
    const Vec3 near = at(P2{(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2}, za);
    if (!intersect(a, b, near, x)) {
      // Small outside turns of arcs may not cross: their tangents do.
      x = at(plus(p, plus(na, nb), r_ / (1 + dot(na, nb))), za);
    }
    a_end = x;
    b_start = at(xy(x), zb);
  } else if (corner_ == Corner::arc) {
    piece(side_ > 0 ? MotionKind::arc_cw : MotionKind::arc_ccw, pa, pb);
  } else if (std::fabs(turn) <= kObtuseMaxTurnRad) {
    // Fanuc, obtuse outside corner: the offset elements extended along their
    // tangents meet at v; an arc element ends at its perpendicular point and
    // a line joins it to v.
    const P2 v = plus(p, plus(na, nb), r_ / (1 + dot(na, nb)));
    if (is_arc(a.m)) piece(line, pa, v); else a_end = at(v, za);
    if (is_arc(b)) piece(line, v, pb); else b_start = at(v, zb);
  } else {
    // Fanuc, acute outside corner: round by two points r beyond the corner
    // along each tangent.
    const P2 p1 = plus(pa, ta, r_), p2 = plus(pb, tb, -r_);
    if (is_arc(a.m)) piece(line, pa, p1); else a_end = at(p1, za);
    piece(line, p1, p2);
    if (is_arc(b)) piece(line, p2, pb); else b_start = at(p2, zb);
  }
  return emit_held(a_end, pieces);
}

// Emits the held element ending at `end` (after checking its centre path
// still runs forwards), the Z moves held after it, then `pieces`.
std::string CutterComp::emit_held(const Vec3& end, const std::vector<Motion>& pieces) {
  Motion c = held_.m;
  c.start_mm = held_.centre_start;
  c.end_mm = end;
  c.contour_start_mm = held_.m.start_mm;
  c.contour_end_mm = held_.m.end_mm;
  c.comp = static_cast<std::int8_t>(side_);
  c.comp_radius_mm = r_;
  if (!is_arc(c)) {
    const P2 t = tangent(held_.m, true);
    if (dot(sub(xy(end), xy(c.start_mm)), t) <= 1e-9)
      return "cutter compensation gouge: the tool centre path of the move at line " + std::to_string(c.line) +
             " runs backwards: the move is too short for the tool radius " + fmt("%.4f mm", r_) +
             " at an inside corner (the control alarms)";
  } else {
    const P2 cc = xy(c.center_mm);
    const P2 s = sub(xy(c.start_mm), cc), e = sub(xy(end), cc), s0 = sub(xy(held_.m.start_mm), cc),
             e0 = sub(xy(held_.m.end_mm), cc);
    const double dir = c.kind == MotionKind::arc_ccw ? 1.0 : -1.0;
    auto sweep = [&](const P2& u, const P2& v) {
      double a = dir * std::atan2(cross(u, v), dot(u, v));
      return a < 0 ? a + 2 * M_PI : a;
    };
    const double prog = sweep(s0, e0), now = sweep(s, e);
    const bool full = norm(sub(s0, e0)) < 1e-9;
    if (!full && prog > 1e-9 && now > prog + 0.5 * (2 * M_PI - prog))
      return "cutter compensation gouge: the tool centre path of the arc at line " + std::to_string(c.line) +
             " runs backwards: the arc is too short for the tool radius " + fmt("%.4f mm", r_) +
             " at an inside corner (the control alarms)";
  }
  out_.motion(c);
  centre_ = end;
  for (Motion z : held_z_) {
    z.start_mm = centre_;
    z.end_mm = {end[0], end[1], z.end_mm[2]};
    // The program's point is the corner's (the block has only Z), the tool's
    // the centre's.
    z.contour_start_mm = {held_.m.end_mm[0], held_.m.end_mm[1], z.start_mm[2]};
    z.contour_end_mm = {held_.m.end_mm[0], held_.m.end_mm[1], z.end_mm[2]};
    z.comp = static_cast<std::int8_t>(side_);
    z.comp_radius_mm = r_;
    out_.motion(z);
    centre_ = z.end_mm;
  }
  held_z_.clear();
  for (Motion m : pieces) {
    m.start_mm = centre_;
    m.comp = static_cast<std::int8_t>(side_);
    m.comp_radius_mm = r_;
    m.contour_start_mm = m.contour_end_mm = held_.m.end_mm;
    out_.motion(m);
    centre_ = m.end_mm;
  }
  have_held_ = false;
  return {};
}

std::string CutterComp::stop() {
  std::string err;
  if (state_ == State::on && have_held_) {
    const P2 pa = plus(xy(held_.m.end_mm), normal(held_.m, true), r_);
    err = emit_held(at(pa, held_.m.end_mm[2]), {});
    displaced_ = true;
  }
  state_ = State::off;
  return err;
}

std::string CutterComp::add(const Motion& m) {
  if (state_ == State::off && !displaced_) {  // every motion of a program without G41/G42: no copy
    out_.motion(m);
    centre_ = m.end_mm;
    return {};
  }
  const bool arc = is_arc(m);
  const bool travel = arc || std::hypot(m.end_mm[0] - m.start_mm[0], m.end_mm[1] - m.start_mm[1]) > 1e-9;
  if (state_ == State::off || (state_ == State::starting && !travel)) {
    Motion c = m;
    if (displaced_) {
      // The first move after G40 goes from where the offset left the tool.
      if (arc && std::hypot(centre_[0] - m.start_mm[0], centre_[1] - m.start_mm[1]) > 1e-9)
        return "an arc right after G40 starts where the tool is not (still offset by the radius): "
               "cancel cutter compensation on a straight move";
      c.start_mm = centre_;
      displaced_ = false;
    }
    out_.motion(c);
    centre_ = m.end_mm;
    return {};
  }
  if (state_ == State::starting) {
    if (arc) return "cutter compensation starts on an arc: the start-up move must be G0 or G1";
    const double len = std::hypot(m.end_mm[0] - m.start_mm[0], m.end_mm[1] - m.start_mm[1]);
    if (len <= r_)
      return fmt("the cutter compensation start-up move (%.4f mm) is not longer than the tool radius %.4f mm", len,
                 r_);
    held_ = {m, centre_, true};
    have_held_ = true;
    state_ = State::on;
    return {};
  }
  if (!travel) {
    held_z_.push_back(m);
    return {};
  }
  if (arc && offset_radius(m) <= 1e-9)
    return fmt("the tool radius %.4f mm is not less than the arc radius %.4f mm: the tool cannot follow the "
               "inside of this arc",
               r_, std::hypot(m.start_mm[0] - m.center_mm[0], m.start_mm[1] - m.center_mm[1]));
  Vec3 b_start;
  std::vector<Motion> pieces;
  const std::string err = corner(held_, m, b_start, pieces);
  if (!err.empty()) return err;
  held_ = {m, b_start, false};
  have_held_ = true;
  return {};
}

}  // namespace deflex::interp::detail
