// The probe program's targets, and the probe log joined with them: which point
// each logged position is, and how far the machined surface lies from the
// intended one there.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "deflex/measure/samples.hpp"

namespace deflex::measure {

// One probe point of deflex's probe program, from the comment the program
// carries just before the point's probing move, in exactly this form:
//   (DEFLEX PROBE 12 WX1 AT 10.000 5.000 -2.250 N 0.000 1.000 0.000 BALL 1.000)
// id (1, 2, 3 ... in program order), feature (letters, digits, '_'), the
// intended surface point (work frame, mm), the outward unit normal of the
// intended surface (from the material into the air: the stylus approaches
// along -N), the stylus ball radius (mm). Numbers carry a decimal point.
struct ProbeTarget {
  int id = 0;
  std::string feature;
  Eigen::Vector3d point_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit length
  double ball_radius_mm = 0;
  std::uint32_t line = 0;  // of the comment in the probe program
};

// The targets of a probe program's text. Lines without "(DEFLEX PROBE" are
// ignored; a malformed DEFLEX PROBE comment, ids not 1..n in order, a normal
// whose length is not 1 within 1e-3 (it is renormalised), a ball radius not
// > 0, a program without any target: located errors.
std::vector<ProbeTarget> read_probe_targets(const std::string& text, const std::string& file);

// A measured point on the machined surface.
struct MeasuredPoint {
  // The stylus ball's centre moved back by the ball radius along the intended
  // normal (contact taken along that normal), work frame, mm.
  Eigen::Vector3d surface_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d intended_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // outward, unit
  // (surface - intended) . normal, mm: deflex's sign, > 0 where material was left.
  double error_mm = 0;
  int id = 0;
  std::string feature;
  std::uint32_t line = 0;  // of the sample in the log
};

// Default of join_probe_log's limit: no machine deflects a finishing cut 2 mm.
inline constexpr double kMeasuredErrorLimitMm = 2.0;

// Joins a probe log's samples with the targets. The log's positions are the
// stylus ball's centre (the probe program's tool length offset is to the ball
// centre, as LinuxCNC's G38.x documentation asks of the controlled point). by_id false (LinuxCNC): the samples in probe order, one per target;
// a count that differs is a located error naming both counts (at the first
// extra line, or at the log's last line). by_id true (DPRNT): a sample whose id
// is no target's is a located error, targets never printed an error naming
// their ids. A point whose |error| exceeds limit_mm is a located error that
// names the likely cause (a unit slip, the wrong work offset, the wrong
// program). log_text: the log's text, for the source lines of the errors.
std::vector<MeasuredPoint> join_probe_log(const std::vector<ProbeTarget>& targets, const std::vector<Sample>& samples,
                                          bool by_id, const std::string& log_file, const std::string& log_text,
                                          double limit_mm = kMeasuredErrorLimitMm);

}  // namespace deflex::measure
