// Cutter-radius compensation (G41/G42) in the G17 plane: the programmed
// contour in, the tool-centre path out, as the control computes it.
//
// The control reads one block ahead: where a move ends depends on the move
// after it. Each contour element (a G0/G1 line or a G2/G3 arc with XY travel)
// is held until the next one comes; the corner between them then fixes the
// end of the first:
//   - inside corner (the tool on the inner side of the turn): the intersection
//     of the two offset elements (a line shifted by r, an arc of radius rho +- r);
//   - outside corner: per dialect (profile::Dialect::cutter_comp_corner),
//       arc: an arc of radius r round the programmed corner, from the first
//            element's perpendicular end to the second's perpendicular start
//            (LinuxCNC; at a turn of at most 0.05 rad, inside or outside, the
//            first element ends perpendicular and the second starts there);
//       intersection: the intersection of the offset elements, extended along
//            their tangents, for a turn up to 90 deg; a sharper turn goes
//            round by two points, r beyond the corner along each tangent
//            (Fanuc Series 0i/30i cutter compensation C; deflex draws the
//            line at 95 deg, see kObtuseMaxTurnRad).
// Start-up (the first move with XY travel after G41/G42, a G0/G1 from where
// the tool stands): LinuxCNC offsets the start-up line itself and meets the
// next element at a corner as above; Fanuc's type A start-up (parameter
// 5003#0 SUP = 0, the default) ends it perpendicular to the next element's
// start. Cancel (G40): the last element ends perpendicular to its end and the
// next move goes from there to its programmed point. Moves without XY travel
// (Z only) under compensation keep the XY where the element before them ends.
//
// LinuxCNC's behaviour was read off its rs274 (tests/cli/test_cutter_comp.cpp
// compares every case); Fanuc's follows the Series 0i-MF operator's manual.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "deflex/interp/motion.hpp"

namespace deflex::interp::detail {

class CutterComp {
 public:
  enum class Corner { arc, intersection };
  enum class Startup { offset_line, perpendicular_next };
  CutterComp(MotionSink& out, Corner corner, Startup startup) : out_(out), corner_(corner), startup_(startup) {}

  // G41 (side +1) or G42 (-1) with radius r: takes effect with the next move
  // with XY travel. Errors come back as a message (empty: fine).
  std::string start(int side, double radius_mm);
  // G40: the held element ends perpendicular to its end; moves go to their
  // programmed points again (the first from where the offset left the tool).
  std::string stop();
  bool on() const { return state_ != State::off; }
  bool starting() const { return state_ == State::starting; }  // the next move with XY travel starts it
  // One programmed motion (the control's contour, tip coordinates).
  std::string add(const Motion& m);
  // End of the program: the held element ends perpendicular to its end.
  std::string flush() { return stop(); }

 private:
  enum class State { off, starting, on };
  struct Element {
    Motion m;            // as programmed
    Vec3 centre_start;   // where the tool centre starts it
    bool entry = false;  // the start-up move (its start is not offset)
  };
  // Tangent (unit, XY) at the start or end of a programmed element, and the
  // unit normal towards the tool there.
  std::array<double, 2> tangent(const Motion& m, bool at_end) const;
  std::array<double, 2> normal(const Motion& m, bool at_end) const;
  // Offset radius of an arc element (rho + r outside, rho - r inside).
  double offset_radius(const Motion& m) const;
  std::string corner(Element& a, const Motion& b, Vec3& b_start, std::vector<Motion>& pieces);
  bool intersect(const Element& a, const Motion& b, const Vec3& near, Vec3& x) const;
  std::string emit_held(const Vec3& end, const std::vector<Motion>& pieces);

  MotionSink& out_;
  Corner corner_;
  Startup startup_;
  State state_ = State::off;
  int side_ = 1;
  double r_ = 0;
  Vec3 centre_{0, 0, 0};
  bool have_held_ = false;
  bool displaced_ = false;  // after G40: the tool stands offset from the programmed point
  Element held_;
  std::vector<Motion> held_z_;  // Z-only moves after the held element
};

}  // namespace deflex::interp::detail
