// A simulation of the four walls (tests/data/fit/walls_xy.nc) held against
// synthetic measurements, its report written: what the tests of the page's
// "Predicted against measured" section look at.
#pragma once
#include <cmath>
#include <fstream>
#include <string>

#include "../fit/support.hpp"

namespace deflex::test {

// Writes `csv`: probe-like points on the four walls (as tests/fit's measure()
// places them, every 2.5 mm along and 0.25 mm up each wall), each moved off
// the design face along its normal by an error of the size the prediction
// has there (20 to 38 um, largest mid-height), plus `far` points 5 mm above the block, out of reach of any
// prediction. Returns the number of points written.
inline std::size_t write_walls_measured(const std::string& csv, int far) {
  struct Wall { double nx, ny, ae, ap; };
  const Wall walls[] = {{0, 1, 4, 12}, {-1, 0, 6, 12}, {0, -1, 3, 10}, {1, 0, 2, 12}};
  std::ofstream o(csv);
  o << "x_mm,y_mm,z_mm\n";
  o.precision(9);
  std::size_t n = 0;
  for (const Wall& w : walls)
    for (double u = -20; u <= 20; u += 2.5)
      for (double z_mm = -w.ap + 0.5; z_mm < -0.2; z_mm += 0.25) {
        const double e_mm = 0.020 + 0.015 * std::sin(M_PI * -z_mm / w.ap) + 0.003 * std::sin(u / 6);
        const double fx = 50 + 50 * w.nx - w.ae * w.nx - u * w.ny, fy = 50 + 50 * w.ny - w.ae * w.ny + u * w.nx;
        o << fx + e_mm * w.nx << "," << fy + e_mm * w.ny << "," << z_mm << "\n";
        ++n;
      }
  for (int k = 0; k < far; ++k, ++n) o << 40 + k << ",50,5\n";
  return n;
}

// The walls simulated on mill3 against `csv`, the report into `report_dir`.
inline job::Settings walls_measured_settings(const std::string& csv, const std::string& report_dir) {
  job::Settings s = walls(kSrc + "/samples/machines/mill3.yaml");
  s.measured = csv;
  s.report_dir = report_dir;
  return s;
}

}  // namespace deflex::test
