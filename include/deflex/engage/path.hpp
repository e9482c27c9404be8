// CL points along the interpreter's motions: every motion end point plus samples
// along long moves and arcs, and the polyline each motion is swept along.
//
// A motion from v_0 (its start) to v_n (its end) is split into n pieces: lines
// into ceil(length / cl_spacing_mm), arcs and helices into the larger of that and
// the chord count that keeps the sagitta within chord_tol_mm. The CL samples of
// the motion are v_1 .. v_n (v_0 is the previous motion's last sample), so each
// motion end point is a CL point and consecutive samples are at most cl_spacing_mm
// apart. Arc samples lie on the exact arc with its exact tangent.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "deflex/engage/engagement.hpp"
#include "deflex/interp/motion.hpp"

namespace deflex::engage {

struct PathOptions {
  double cl_spacing_mm = 0.5;   // longest distance between CL samples along a move
  double chord_tol_mm = 0.001;  // sagitta of the chords an arc is swept along
};

struct CLSample {
  CLPoint point;             // tip, direction of travel, feed frame
  std::size_t motion = 0;    // index of the motion in the sequence given
  std::uint32_t line = 0;    // its source line
  int index = 0, count = 0;  // sample index in the motion, 1..count (count: the end point)
  bool rapid = false;
};

// Vertices v_0 .. v_n of a motion (see above); v_0 = start, v_n = end exactly.
std::vector<Point3> motion_vertices(const interp::Motion& m, const PathOptions& o);

// Unit direction of travel at vertex k of those vertices (exact arc tangent).
Point3 motion_direction(const interp::Motion& m, std::span<const Point3> verts, std::size_t k);

// CL sample k (1..count) of motion m, whose vertices are v; `feed` carries the
// XY feed direction across plunges (in: at the sample before; out: at this one).
// CLSample::motion is left 0 for the caller.
CLSample cl_sample(const interp::Motion& m, std::span<const Point3> v, std::size_t k, std::array<double, 2>& feed);

// CL samples of a motion sequence, without a stock. `last_feed` carries the XY
// feed direction across plunges (in: the one before the sequence; out: updated).
std::vector<CLSample> cl_samples(std::span<const interp::Motion> motions, const PathOptions& o,
                                 std::array<double, 2>* last_feed = nullptr);

}  // namespace deflex::engage
