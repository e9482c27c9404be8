// The probe program the probe-log fuzz targets join their logs with: three
// points of different normals and ball radii.
#pragma once
#include <vector>

#include "deflex/measure/probe.hpp"

namespace deflex::fuzz {

inline const std::vector<measure::ProbeTarget>& probe_targets() {
  static const std::vector<measure::ProbeTarget> t = measure::read_probe_targets(
      "(DEFLEX PROBE 1 TOP AT 0.000 0.000 0.000 N 0.000 0.000 1.000 BALL 1.000)\n"
      "(DEFLEX PROBE 2 WX1 AT 10.000 5.000 -2.250 N 1.000 0.000 0.000 BALL 1.000)\n"
      "(DEFLEX PROBE 3 WY1 AT 5.000 10.000 -2.250 N 0.600 0.800 0.000 BALL 0.500)\n",
      "probe.nc");
  return t;
}

}  // namespace deflex::fuzz
