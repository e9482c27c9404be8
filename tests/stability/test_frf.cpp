// The tool tip's FRF (stability/frf.hpp): from modes against the SDOF closed
// form, and the CSV reader's errors, optional cross terms and round trip.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "../support.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/stability/frf.hpp"

using namespace deflex;
using namespace deflex::stability;

namespace {
// The message of the input error `csv` raises, or "" if none.
std::string csv_error(const std::string& csv) {
  try {
    parse_frf_csv(csv, "tap.csv");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::input);
    return e.what();
  }
  return "";
}
const std::string kHeader = "frequency_Hz,re_xx_mm_per_N,im_xx_mm_per_N,re_yy_mm_per_N,im_yy_mm_per_N\n";
const std::string kRows = "100,1e-4,-1e-6,2e-4,-2e-6\n200,3e-4,-1e-4,4e-4,-1e-4\n300,-1e-4,-2e-5,-2e-4,-3e-5\n";
}  // namespace

TEST_SUITE("stability") {
  TEST_CASE("frf: an SDOF's peak from modes is 1 / (2 k zeta sqrt(1 - zeta^2)) within 1 %") {
    for (double zeta : {0.01, 0.03, 0.1}) {
      const stiffness::Mode m{700, zeta, 2e4};
      const Frf frf = frf_from_modes({m}, {m}, 3000);
      double peak = 0;
      for (const Frf2& h : frf.h_mm_per_N) peak = std::max(peak, std::abs(h(0, 0)));
      CAPTURE(zeta);
      CHECK(peak == doctest::Approx(1 / (2 * m.stiffness_N_per_mm * zeta * std::sqrt(1 - zeta * zeta))).epsilon(0.01));
      // Static end: 1/k; no cross terms; the samples ascend to f_max.
      CHECK(frf.h_mm_per_N.front()(0, 0).real() == deflex::test::within(1 / m.stiffness_N_per_mm, 1e-3));
      CHECK(frf.h_mm_per_N.front()(0, 1) == std::complex<double>(0, 0));
      CHECK(std::is_sorted(frf.frequency_Hz.begin(), frf.frequency_Hz.end()));
      CHECK(frf.frequency_Hz.back() == 3000);
    }
  }

  TEST_CASE("frf: at() interpolates linearly between samples and holds the ends") {
    const Frf frf = parse_frf_csv(kHeader + kRows, "tap.csv");
    CHECK(frf.at(150)(0, 0).real() == doctest::Approx(2e-4));
    CHECK(frf.at(150)(1, 1).imag() == doctest::Approx(-5.1e-5));
    CHECK(frf.at(50)(0, 0) == frf.h_mm_per_N.front()(0, 0));
    CHECK(frf.at(400)(1, 1) == frf.h_mm_per_N.back()(1, 1));
  }

  TEST_CASE("frf csv: columns by name, cross terms optional, comments, blank lines and CRLF") {
    const Frf direct = parse_frf_csv("# tap test\n\n" + kHeader + kRows, "tap.csv");
    REQUIRE(direct.frequency_Hz.size() == 3);
    CHECK(direct.source == "tap.csv");
    CHECK(direct.h_mm_per_N[1](0, 0) == std::complex<double>(3e-4, -1e-4));
    CHECK(direct.h_mm_per_N[1](1, 1) == std::complex<double>(4e-4, -1e-4));
    CHECK(direct.h_mm_per_N[1](0, 1) == std::complex<double>(0, 0));  // absent: 0
    const Frf cross = parse_frf_csv(
        "im_yy_mm_per_N,re_yx_mm_per_N,im_yx_mm_per_N,frequency_Hz,re_xx_mm_per_N,im_xx_mm_per_N,re_xy_mm_per_N,"
        "im_xy_mm_per_N,re_yy_mm_per_N\r\n"
        "-1,7,8,10,2,3,4,5,6\r\n# between\r\n1,1,1,20,1,1,1,1,1\r\n1,1,1,30,1,1,1,1,1\r\n",
        "cross.csv");
    CHECK(cross.frequency_Hz == std::vector<double>{10, 20, 30});
    CHECK(cross.h_mm_per_N[0](0, 0) == std::complex<double>(2, 3));
    CHECK(cross.h_mm_per_N[0](0, 1) == std::complex<double>(4, 5));
    CHECK(cross.h_mm_per_N[0](1, 0) == std::complex<double>(7, 8));
    CHECK(cross.h_mm_per_N[0](1, 1) == std::complex<double>(6, -1));
  }

  TEST_CASE("frf csv: every malformed input is an error at its line and column") {
    CHECK(csv_error("").find("tap.csv:1:1: error: the file is empty") == 0);
    CHECK(csv_error("# only a comment\n").find("tap.csv:1:1: error: no header") == 0);
    CHECK(csv_error("frequency_Hz,re_xx_mm_per_N,im_xx_mm_per_N,re_yy_mm_per_N\n" + kRows)
              .find("tap.csv:1:1: error: no column im_yy_mm_per_N") == 0);
    CHECK(csv_error("frequency_Hz,re_xx_mm_per_N,im_xx_mm_per_N,re_yy_mm_per_N,im_yy_mm_per_N,re_xy_mm_per_N\n" + kRows)
              .find("tap.csv:1:1: error: column im_xy_mm_per_N missing") == 0);
    CHECK(csv_error("frequency_Hz,re_xx_mm_per_N,im_xx_mm_per_N,re_yy_mm_per_N,im_yy_mm_per_N,phase\n")
              .find("tap.csv:1:74: error: unknown column 'phase'") == 0);
    CHECK(csv_error("frequency_Hz,re_xx_mm_per_N,im_xx_mm_per_N,re_yy_mm_per_N,re_yy_mm_per_N\n")
              .find("tap.csv:1:59: error: column 're_yy_mm_per_N' given twice") == 0);
    CHECK(csv_error(kRows).find("tap.csv:1:1: error: the first line is data, not a header") == 0);
    CHECK(csv_error(kHeader + "100,1e-4,x,2e-4,-2e-6\n").find("tap.csv:2:10: error: im_xx_mm_per_N: 'x' is not a number") == 0);
    CHECK(csv_error(kHeader + "100,1e-4,nan,2e-4,-2e-6\n").find("tap.csv:2:10: error: im_xx_mm_per_N: 'nan' is not a finite number") == 0);
    CHECK(csv_error(kHeader + "100,1e-4,-1e-6,2e-4\n").find("tap.csv:2:20: error: expected 5 fields") == 0);
    CHECK(csv_error(kHeader + "100,1e-4,-1e-6,2e-4,-2e-6\n\n100,1e-4,-1e-6,2e-4,-2e-6\n")
              .find("tap.csv:4:1: error: frequency_Hz must ascend strictly (the row before has 100 Hz)") == 0);
    CHECK(csv_error(kHeader + "0,1e-4,-1e-6,2e-4,-2e-6\n").find("tap.csv:2:1: error: frequency_Hz must be > 0") == 0);
    CHECK(csv_error("\n" + kHeader + "100,1e-4,-1e-6,2e-4,-2e-6\n200,1e-4,-1e-6,2e-4,-2e-6\n")
              .find("tap.csv:2:1: error: an FRF needs at least 3 rows, found 2") == 0);
    // The source line and a caret follow, as in every located error of deflex.
    const std::string e = csv_error(kHeader + "100,1e-4,x,2e-4,-2e-6\n");
    CHECK(e.find("100,1e-4,x,2e-4,-2e-6") != std::string::npos);
    CHECK(e.find("^") != std::string::npos);
    CHECK(csv_error(kHeader + kRows).empty());
  }

  TEST_CASE("frf csv: frf_from_modes written and read back is the same FRF") {
    const Frf frf = frf_from_modes({{500, 0.03, 1e4}, {1400, 0.02, 3e4}}, {{550, 0.04, 1.2e4}}, 2500);
    const Frf again = parse_frf_csv(frf_csv(frf), "again.csv");
    CHECK(again.frequency_Hz == frf.frequency_Hz);
    CHECK(again.h_mm_per_N == frf.h_mm_per_N);
  }
}
