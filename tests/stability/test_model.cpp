// The limit along a program (stability/model.hpp): a cut's directional matrix
// from its engagement against the textbook immersion, and LimitCache's
// per-phase tables against the lobes of the cut itself.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "../support.hpp"
#include "deflex/force/cutter.hpp"
#include "deflex/force/engagement.hpp"
#include "deflex/stability/model.hpp"

using namespace deflex;
using namespace deflex::stability;

namespace {

force::Cutter cutter(stock::EndShape type, double D, int flutes) {
  force::Cutter c;
  c.type = type;
  c.diameter_mm = D;
  c.flutes = flutes;
  c.helix_deg = 30;
  c.flute_length_mm = 30;
  return c;
}

force::Coefficients steel() {
  force::Coefficients k;
  k.Ktc_N_per_mm2 = 2000;
  k.Krc_N_per_mm2 = 700;
  k.Kac_N_per_mm2 = 300;
  return k;
}

// Two modes, as a slender tool on a spindle has them.
std::vector<stiffness::Mode> modes() { return {{900, 0.03, 4000}, {2400, 0.04, 25000}}; }

// The limit of a cut with directional matrix alpha (mean over its depth), by
// the lobes of that matrix itself: what LimitCache must agree with.
double direct_limit_mm(const Eigen::Matrix2d& alpha, int flutes, double Kt, double rpm) {
  const Frf frf = tip_model_of(modes()).frf;
  const auto [lo, hi] = rpm_range(20000);
  const StabilityLimit lim(zero_order_lobes(frf, alpha.cast<std::complex<double>>(), flutes, Kt, lo, hi), lo, hi);
  return lim.ap_limit_mm(rpm);
}

}  // namespace

TEST_SUITE("stability") {

TEST_CASE("a flat end's directional matrix is a_p times the coefficients of its immersion") {
  const force::CutterSlices cs = force::make_slices(cutter(stock::EndShape::flat, 12, 3), 0.5, 20);
  const force::Coefficients k = steel();
  force::Engagement e;
  for (const force::MillingMode mode : {force::MillingMode::up, force::MillingMode::down})
    for (const double ae : {1.0, 6.0, 12.0}) {
      CAPTURE(ae);
      force::simple_engagement(cs, ae, 8, mode, e);
      const Eigen::Matrix2d B = directional_matrix_mm(cs, e, k);
      const Eigen::Matrix2d want =
          8 * directional_coefficients(cut_of(k, 3, force::immersion_interval(6, 6, ae, mode)));
      CHECK((B - want).norm() <= 1e-9 * want.norm());
    }
}

TEST_CASE("the limit at one speed from the sweep is the lobes' envelope (StabilityLimit) within 0.5 %") {
  const Frf frf = tip_model_of(modes()).frf;
  const force::Coefficients k = steel();
  for (const force::AngleInterval imm : {force::AngleInterval{0, std::numbers::pi}, force::AngleInterval{2.2, std::numbers::pi},
                                         force::AngleInterval{0, 0.9}}) {
    const Cut cut = cut_of(k, 3, imm);
    const Eigen::Matrix2cd alpha = directional_coefficients(cut).cast<std::complex<double>>();
    const ChatterSweep sw = chatter_sweep(frf, alpha, 3, k.Ktc_N_per_mm2);
    const StabilityLimit table(zero_order_lobes(frf, cut, 1000, 20000), 1000, 20000, 20000);
    for (double rpm = 1500; rpm <= 19500; rpm += 250) {
      CAPTURE(rpm);
      CHECK(ap_limit_at(sw, rpm) == deflex::test::within(table.ap_limit_mm(rpm), 0.005));
    }
  }
}

TEST_CASE("LimitCache: the per-phase sweeps give the limit of the cut's own lobes within 2 %") {
  const force::Coefficients k = steel();
  const LimitCache cache(tip_model_of(modes()), k, 3, 20000);
  force::Engagement e;
  // A flat end at several immersions and a ball end whose slices each have
  // their own immersion and kappa: the mean directional matrix B / a_p.
  struct Case {
    stock::EndShape type;
    double ae_mm, ap_mm;
    force::MillingMode mode;
  };
  for (const Case c : {Case{stock::EndShape::flat, 2, 5, force::MillingMode::down},
                       Case{stock::EndShape::flat, 6, 5, force::MillingMode::up},
                       Case{stock::EndShape::flat, 12, 3, force::MillingMode::down},
                       Case{stock::EndShape::ball, 3, 2.5, force::MillingMode::down},
                       Case{stock::EndShape::ball, 1, 4, force::MillingMode::up}}) {
    CAPTURE(c.ae_mm);
    CAPTURE(c.ap_mm);
    const force::CutterSlices cs = force::make_slices(cutter(c.type, 12, 3), 0.1, 20);
    force::simple_engagement(cs, c.ae_mm, c.ap_mm, c.mode, e);
    const Eigen::Matrix2d B = directional_matrix_mm(cs, e, k);
    const double ap = c.ap_mm;
    for (const double rpm : {3000.0, 7500.0, 12000.0, 17000.0}) {
      CAPTURE(rpm);
      const double want = direct_limit_mm(B / ap, 3, k.Ktc_N_per_mm2, rpm);
      CHECK(cache.ap_limit_mm(B, ap, rpm) == deflex::test::within(want, 0.02));
    }
  }
  // Nothing engaged: no limit.
  CHECK(std::isinf(cache.ap_limit_mm(Eigen::Matrix2d::Zero(), 1, 5000)));
}

}  // TEST_SUITE
