// What a report says about each CL point, in one table that every report
// file reads (points.csv, the maps, report.html, summary.json's statistics).
//
// Sign convention, everywhere in deflex: the surface error e is measured along
// the outward normal n of the design surface, e = (landing point - intended
// point) . n; e > 0 the tool stood off the surface (material left, undercut),
// e < 0 it dug in (overcut). Offsets are along n likewise.
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "deflex/compensate/compensate.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/process/cusp.hpp"

namespace deflex::report {

using V3 = Eigen::Vector3d;
constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

// The offset commanded at a CL sample: between the offsets of the motion's
// start (the motion before) and its end, by the sample's position along it.
V3 offset_at(const compensate::Point& p, const std::vector<V3>& offsets);

// The landing error of each point in material (NaN in air and on plunges),
// the points displaced by `offsets` (per motion; empty: none).
std::vector<double> landing_errors(const std::vector<compensate::Point>& pts, const std::vector<V3>& offsets);

struct PointTable {
  std::vector<compensate::Point> points;  // the points reported: compensated, or simulated
  std::vector<double> offset_n_mm;        // offset along n at each (0: none)
  std::vector<double> error_mm;           // landing error against the design (NaN in air)
  std::vector<double> error_as_written_mm;// the program as written at the same place (NaN: not known)
  std::vector<double> path_mm;            // cutting path length from the program start
  std::vector<process::CuspResult> cusp;  // of the program as written at the same place
  bool has_as_written = false;            // compensate: both columns; simulate: one
  bool cutting(std::size_t i) const { return !points[i].air && !points[i].plunge; }
};

// Cusp samples of the points (ball ends: D_e = D; others: none), with the
// direction of travel from the neighbouring samples of the same move chain.
std::vector<process::CuspSample> cusp_samples(const std::vector<compensate::Point>& pts,
                                              const std::vector<interp::Motion>& motions,
                                              const compensate::Physics& ph, const compensate::Settings& s);

// The table of a simulation against the design: `intent` the offsets of the
// simulated program from the design (simulate --reference; empty: none).
PointTable table_of_simulation(std::vector<compensate::Point> pts, const std::vector<V3>& intent,
                               const std::vector<interp::Motion>& motions, const compensate::Physics& ph,
                               const compensate::Settings& s);

// The table of a compensation: its final points (`final`, moved in by the
// caller: a million points are not copied), each beside the point of the
// program as written (`nominal`) nearest to it on the same original move (the
// result's motions hold inserted blocks the program as written does not have),
// whose cusp it takes.
PointTable table_of_compensation(std::vector<compensate::Point> final, const std::vector<compensate::Point>& nominal,
                                 const compensate::Result& r, const std::vector<interp::Motion>& original,
                                 const compensate::Physics& ph, const compensate::Settings& s);

// points.csv, one row per CL point in material or air (air rows have no error).
void write_points_csv(const std::string& path, const PointTable& t);
// flank_profile.csv: e(z) of each flank point of `as_written` (simulated with
// Settings::flank_profiles); false (nothing written) when there is none.
bool write_flank_profile_csv(const std::string& path, const std::vector<compensate::Point>& as_written);

}  // namespace deflex::report
