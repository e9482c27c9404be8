// The tool tip's frequency response function (FRF) in the machine's X and Y:
// what the stability lobes (lobes.hpp) read. From the modal model of the tool
// chain (stiffness/modes.hpp) or from a tap test's CSV.
#pragma once
#include <complex>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "deflex/stiffness/modes.hpp"

namespace deflex::stability {

// 2x2 complex receptance at one frequency, mm/N, machine axes: (0,0) = xx,
// (0,1) = xy (displacement x under a force in y), (1,0) = yx, (1,1) = yy.
using Frf2 = Eigen::Matrix2cd;

// An FRF sampled at ascending frequencies (> 0 Hz).
struct Frf {
  std::vector<double> frequency_Hz;
  std::vector<Frf2> h_mm_per_N;  // one per frequency
  std::string source;            // where it came from, for messages: a file, or "modal model"
  // Linear interpolation inside [front, back]; the end sample outside it.
  Frf2 at(double f_Hz) const;
};

// The receptance of a sum of modes at f (stiffness::Mode):
// sum_r 1 / (k_r (1 - (f/f_r)^2 + 2 i zeta_r f/f_r)), mm/N.
std::complex<double> modal_receptance(const std::vector<stiffness::Mode>& modes, double f_Hz);

// The FRF of x modes in x and y modes in y (no cross terms) from f_max /
// 1000 to f_max, sampled where it changes: the step at f is a tenth of
// min over modes of max(zeta_r f_r, |f - f_r|), so the half-power band
// (width 2 zeta_r f_r) of every mode gets at least 20 samples and the step
// grows away from the peaks; never coarser than f_max / 400. Linear
// interpolation between such samples errs by well under 1 % near a peak,
// inside the 2 % the lobes are meant to hold.
Frf frf_from_modes(const std::vector<stiffness::Mode>& x, const std::vector<stiffness::Mode>& y, double f_max_Hz);

// A measured FRF as CSV. A header line (the first line that is neither blank
// nor a '#' comment) names the columns, in any order:
//   frequency_Hz, re_xx_mm_per_N, im_xx_mm_per_N, re_yy_mm_per_N, im_yy_mm_per_N
// and optionally the cross terms re_xy_mm_per_N, im_xy_mm_per_N,
// re_yx_mm_per_N, im_yx_mm_per_N (absent: 0). Then one row per frequency:
// finite numbers, frequencies > 0 and strictly ascending, at least 3 rows.
// Blank lines and '#' comments anywhere; CRLF line ends read alike. Every
// malformed input is an Error(ErrorKind::input) `file:line:col: error: ...`
// with the source line and a caret, like deflex's other text readers.
Frf parse_frf_csv(std::string_view text, const std::string& file);
// The same from a file (Error(ErrorKind::io) when it cannot be read).
Frf load_frf_csv(const std::string& path);
// The CSV parse_frf_csv reads, every column, numbers with 17 significant
// digits (read back bit for bit).
std::string frf_csv(const Frf& frf);

}  // namespace deflex::stability
