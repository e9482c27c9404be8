// Slot-test calibration (Altintas 2012 ch. 2): recovers known coefficients from
// the simulated model and from the sample CSV.
#include <doctest/doctest.h>

#include <cmath>

#include "../support.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/force/calibration.hpp"
#include "deflex/force/mechanistic.hpp"

using namespace deflex::force;

namespace {

Coefficients truth() {
  Coefficients k;
  k.Ktc_N_per_mm2 = 850;
  k.Krc_N_per_mm2 = 290;
  k.Kac_N_per_mm2 = 120;
  k.Kte_N_per_mm = 24;
  k.Kre_N_per_mm = 31;
  k.Kae_N_per_mm = 1.8;
  return k;
}

void check_coefficients(const Coefficients& got, const Coefficients& want, double rel) {
  CHECK(got.Ktc_N_per_mm2 == deflex::test::within(want.Ktc_N_per_mm2, rel));
  CHECK(got.Krc_N_per_mm2 == deflex::test::within(want.Krc_N_per_mm2, rel));
  CHECK(got.Kac_N_per_mm2 == deflex::test::within(want.Kac_N_per_mm2, rel));
  CHECK(got.Kte_N_per_mm == deflex::test::within(want.Kte_N_per_mm, rel));
  CHECK(got.Kre_N_per_mm == deflex::test::within(want.Kre_N_per_mm, rel));
  CHECK(got.Kae_N_per_mm == deflex::test::within(want.Kae_N_per_mm, rel));
}

}  // namespace

TEST_SUITE("force") {

TEST_CASE("calibration recovers the coefficients of simulated helical slot tests") {
  // Mean forces from the full time-domain model (helix 30, 4 flutes), not from the
  // closed form the calibration inverts.
  const Coefficients k = truth();
  Cutter c;
  c.type = deflex::stock::EndShape::flat;
  c.diameter_mm = 12;
  c.flutes = 4;
  c.helix_deg = 30;
  SlotTestData data;
  data.file = "simulated";
  for (double ap : {2.0, 4.0})
    for (double fz : {0.03, 0.06, 0.09, 0.12}) {
      const CutterSlices sl = make_slices(c, 0.05, ap);
      Engagement e;
      simple_engagement(sl, 12, ap, MillingMode::down, e);
      SlotTest t;
      t.fz_mm = fz;
      t.ap_mm = ap;
      t.flutes = 4;
      t.mean_N = summarize(revolution_forces(sl, k, fz, e, 720)).mean_N;
      data.tests.push_back(t);
    }
  const SlotCalibration cal = calibrate_slot_tests(data);
  check_coefficients(cal.k, k, 0.005);
  for (int a = 0; a < 3; ++a) CHECK(cal.fit[a].r2 > 0.9999);
}

TEST_CASE("calibration of samples/calibration/slot_tests_al7075.csv (0.5% noise)") {
  const SlotTestData d =
      load_slot_tests(std::string(DEFLEX_SOURCE_DIR) + "/samples/calibration/slot_tests_al7075.csv");
  REQUIRE(d.tests.size() == 12);
  CHECK(d.tests[0].flutes == 4);  // from the "# flutes:" line
  CHECK(d.tests[0].ap_mm == 3);
  CHECK(d.helix_deg == 30);
  const SlotCalibration cal = calibrate_slot_tests(d);
  check_coefficients(cal.k, truth(), 0.03);
  // Residuals of the order of the noise (0.5% of forces up to ~800 N).
  CHECK(cal.rms_residual_N.maxCoeff() < 3.0);
  CHECK(cal.rms_residual_N.minCoeff() > 0.0);
}

TEST_CASE("slot-test CSV: workpiece forces are negated, errors have file:line:col") {
  const std::string csv =
      "# forces_on: workpiece\n# ap_mm: 2\n# flutes: 2\nfz_mm, Fx_N, Fy_N, Fz_N\r\n0.1,1,-2,3\r\n0.2,2,-4,6";
  const SlotTestData d = parse_slot_tests(csv, "t.csv");
  REQUIRE(d.tests.size() == 2);
  CHECK(d.tests[1].mean_N.y() == 4);
  CHECK(d.tests[1].line == 6);

  auto msg = [](const std::string& text) {
    try {
      parse_slot_tests(text, "t.csv");
    } catch (const deflex::Error& e) {
      CHECK(e.kind() == deflex::ErrorKind::input);
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(msg("fz_mm,Fx_N,Fy_N,Fz_N,ap_mm,flutes\n0.1,1,2,3,4,oops\n") ==
        "t.csv:2:13: error: flutes must be a number, not 'oops'");
  CHECK(msg("fz_mm,Fx_N,Fy_N\n").find("t.csv:1:1: error: missing column 'Fz_N'") == 0);
  CHECK(msg("fz_mm,Fx_N,Fy_N,Fz_N\n").find("'ap_mm' must be a column") != std::string::npos);
  CHECK(msg("fz_mm,Fx_N,Fy_N,Fz_N,a_p\n").find("t.csv:1:22: error: unknown column 'a_p'") == 0);
  // One feed only: the regression is undetermined.
  const SlotTestData one = parse_slot_tests("# ap_mm: 1\n# flutes: 2\nfz_mm,Fx_N,Fy_N,Fz_N\n0.1,1,2,3\n0.1,1,2,3\n", "t.csv");
  CHECK_THROWS_AS(calibrate_slot_tests(one), deflex::Error);
}

}  // TEST_SUITE
