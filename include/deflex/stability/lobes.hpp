// Milling stability lobes by the zero-order (average tooth-passing) method of
// Altintas & Budak 1995 (Annals of the CIRP 44/1, 357-362; Altintas,
// Manufacturing Automation, 2nd ed. 2012, ch. 4): the critical axial depth of
// cut against spindle speed for a tool-tip FRF (frf.hpp) and a cut.
//
// The dynamic milling forces are averaged over a tooth period: the directional
// coefficients alpha (2x2, dimensionless) of the immersion [phi_st, phi_ex]
// turn the regenerative displacement into force, and the chatter
// limit at a chatter frequency omega_c is the eigenvalue problem
//   det[I + Lambda alpha Phi(i omega_c)] = 0,  Lambda = -N a K_t (1 - e^{-i omega_c T}) / (4 pi)
// with Phi the 2x2 FRF. Then, with kappa = Lambda_I / Lambda_R,
//   a_lim = -2 pi Lambda_R (1 + kappa^2) / (N K_t),
//   psi = atan kappa, eps = pi - 2 psi, n = 60 omega_c / (N (eps + 2 k pi))
// for each lobe k = 0, 1, 2, ...
//
// Known limit: the zero-order method keeps only the mean of the periodic
// directional matrix. At low radial immersion (a_e / D below about 0.1-0.2) the
// forces are strongly intermittent; the period-doubling (flip) lobes and the
// extra lobes of the multi-frequency solution (Merdol & Altintas 2004;
// Insperger & Stepan's semi-discretization) are missed there, so the lobes of
// a light finishing cut may be optimistic near the flip speeds.
#pragma once
#include <array>
#include <limits>
#include <vector>

#include "deflex/force/coefficients.hpp"
#include "deflex/force/engagement.hpp"
#include "deflex/stability/frf.hpp"

namespace deflex::stability {

// The cut: teeth, the tangential cutting coefficient, K_r = K_rc / K_tc, and the
// immersion in deflex's phi convention (force/engagement.hpp, Altintas's).
struct Cut {
  int flutes = 2;
  double Kt_N_per_mm2 = 0;
  double Kr_ratio = 0;
  double phi_start_rad = 0, phi_exit_rad = 0;
};

// K_t = K_tc and K_r = K_rc / K_tc of a coefficient set (the edge terms do not
// regenerate), over one engaged interval.
Cut cut_of(const force::Coefficients& k, int flutes, force::AngleInterval immersion);

// The average directional coefficients alpha, [[xx, xy], [yx, yy]].
Eigen::Matrix2d directional_coefficients(const Cut& c);

// One root of the characteristic equation at one chatter frequency, on one
// eigenvalue branch: a_lim and eps, the phase between the inner and the outer
// modulation, in (0, 2 pi).
struct ChatterRoot {
  double ap_mm = 0;    // a_lim; valid only when ok
  double eps_rad = 0;
  bool ok = false;     // a_lim > 0 and finite
};

struct ChatterSample {
  double f_Hz = 0;
  std::array<ChatterRoot, 2> root;  // per eigenvalue branch, each followed continuously
};

// Every chatter frequency of a cut with its roots, refined as
// zero_order_lobes() says: what its lobes are, before they are mapped onto
// speeds.
struct ChatterSweep {
  int flutes = 0;
  std::vector<ChatterSample> samples;
  double ap_min_mm = std::numeric_limits<double>::infinity();  // the absolute minimum
  double ap_min_chatter_Hz = 0;
};

struct LobePoint {
  double rpm = 0;
  double ap_limit_mm = 0;
  double chatter_Hz = 0;
};

// One lobe's curve as it is traced: lobe number k, one eigenvalue branch of
// the 2x2 problem, and points in the order of ascending chatter frequency (the
// speed usually falls as it rises); a gap (no positive root) starts a new
// curve, and so does leaving the speed range (a curve keeps the one point past
// either end of the range, for interpolation at the edges).
struct Lobe {
  int k = 0;
  std::vector<LobePoint> points;
};

struct Lobes {
  std::vector<Lobe> lobes;     // the curves' pieces inside [rpm_min, rpm_max]
  double ap_min_mm = 0;        // the absolute, speed-independent minimum over every chatter
                               // frequency; +infinity when no frequency has a chatter root
  double ap_min_chatter_Hz = 0;
};

// The lobes over [rpm_min, rpm_max], of lobe numbers 0 .. max_lobes - 1, or
// with max_lobes = 0 as many as reach rpm_min at every chatter frequency whose
// a_lim is within 10 times ap_min_mm (at most 2000): the lower envelope is then
// complete wherever it is below 10 ap_min_mm (a missing lobe would leave it too
// high, on the unsafe side). Chatter
// frequencies are the FRF's samples, each interval subdivided (FRF linearly
// interpolated) until a_lim changes by under 1 % between neighbours; roots
// with a_lim <= 0 or not finite are no chatter. Throws Error(ErrorKind::settings)
// for a cut without teeth, K_t or immersion, or a speed range that is empty.
Lobes zero_order_lobes(const Frf& frf, const Cut& cut, double rpm_min, double rpm_max, int max_lobes = 0);
// The same for a directional matrix given whole (real for a cut, complex where
// it stands for one eigenvalue of a cut's: stability/model.hpp), N teeth and K_t.
Lobes zero_order_lobes(const Frf& frf, const Eigen::Matrix2cd& alpha, int flutes, double Kt_N_per_mm2, double rpm_min,
                       double rpm_max, int max_lobes = 0);

// The sweep of a directional matrix (as the second zero_order_lobes()).
ChatterSweep chatter_sweep(const Frf& frf, const Eigen::Matrix2cd& alpha, int flutes, double Kt_N_per_mm2);
// The limit at one speed straight from the sweep: the lowest lobe that
// crosses it (each lobe interpolated between the sweep's frequencies, as its
// curve is), ap_min_mm where none does. What StabilityLimit tabulates, for
// one speed without tracing every lobe: a program's few S values.
double ap_limit_at(const ChatterSweep& sweep, double rpm);

// The stability limit against speed for fast repeated look-ups: the lower
// envelope of every lobe, tabulated at `steps` + 1 speeds over [rpm_min,
// rpm_max] and interpolated linearly between them. A speed no lobe reaches
// (outside the lobes' range) gets the absolute minimum ap_min_mm, on the safe
// side, as does a speed outside [rpm_min, rpm_max]. The table resolves what is
// wider than its step: at low speeds, where the lobes of high k crowd
// together, a step wider than a lobe cuts the cusps between them.
class StabilityLimit {
 public:
  StabilityLimit(const Lobes& lobes, double rpm_min, double rpm_max, int steps = 4000);
  double ap_limit_mm(double rpm) const;
  double rpm_min() const { return rpm_min_; }
  double rpm_max() const { return rpm_max_; }

 private:
  double rpm_min_, rpm_max_, ap_min_mm_, step_rpm_ = 0;
  std::vector<double> ap_mm_;  // steps + 1
};

}  // namespace deflex::stability
