// One entry point for a measurement file of any of the four forms.
#pragma once
#include <string>
#include <vector>

#include "deflex/measure/probe.hpp"
#include "deflex/measure/samples.hpp"

namespace deflex::measure {

enum class MeasuredForm { points_csv, point_cloud, linuxcnc_log, dprnt };

struct Measured {
  MeasuredForm form = MeasuredForm::points_csv;
  // points_csv, point_cloud: raw points; the caller compares them with the
  // intended surface (the part model), for there is no probe program.
  std::vector<Sample> samples;
  // linuxcnc_log, dprnt: the log joined with the probe program.
  std::vector<MeasuredPoint> points;
};

// Reads `path` by its extension (any case): .csv a CMM's points, .ply/.stl a
// point cloud; anything else is a probe log, which needs the probe program
// that wrote it (`probe_program`, else Error(ErrorKind::settings)), and is
// read as DPRNT output when its first line that is not blank nor '%' starts
// with PT, else as LinuxCNC's log. Unreadable files: Error(ErrorKind::io).
Measured read_measured(const std::string& path, const std::string& probe_program = "",
                       double limit_mm = kMeasuredErrorLimitMm);

}  // namespace deflex::measure
