// The stability limit of a library tool on its machine: the tool tip's FRF
// from the beam model's modes (stiffness/modes.hpp), and, along a program,
// the limit of each cut's own engagement at its speed (LimitCache).
#pragma once
#include <array>
#include <map>
#include <memory>
#include <shared_mutex>
#include <utility>
#include <vector>

#include "deflex/force/coefficients.hpp"
#include "deflex/force/engagement.hpp"
#include "deflex/stability/frf.hpp"
#include "deflex/stability/lobes.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::stability {

// The lowest lateral modes the tip FRF is built from. The chatter of a
// tool-holder-spindle chain is set by its first two or three bending modes;
// each higher one is several times stiffer at the tip (the cantilever's k_r
// grows as f_r^2), so four keep every mode that can bound the limit.
inline constexpr int kModelModes = 4;

struct TipModel {
  std::vector<stiffness::Mode> modes;  // x and y alike (the chain is axisymmetric)
  Frf frf;
};

// The FRF of modes in x and y alike (no cross terms), up to 1.5 times the
// highest (modes: not empty, frequency ascending).
TipModel tip_model_of(std::vector<stiffness::Mode> modes);

// The tool's lowest modes on the machine (tool_only: clamped rigidly at the
// holder face) and their FRF. Throws what stiffness::tip_modes throws (a
// material without density).
TipModel tip_model(const stiffness::Tool& t, const stiffness::MachineStiffness& m, bool tool_only,
                   int modes = kModelModes);

// The speed range a limit is tabulated over for a spindle that turns up to
// max_rpm: from a 50th of it (below, the lobes crowd together and the limit
// is near the absolute minimum, which StabilityLimit gives outside its range).
std::pair<double, double> rpm_range(double max_rpm);

// The directional matrix of a cut as the engagement gives it, mm: over every
// slice the averaged directional coefficients of its engaged intervals on the
// cutting side (directional_coefficients), with the slice's in-plane radial
// coefficient K_r = (K_rc sin kappa + K_ac cos kappa) / K_tc, weighted by the
// slice's height dz. A flat end in a straight cut gives a_p times the
// coefficients of its immersion; a ball or a bull nose the sum over its
// slices, each at its own immersion and kappa (Altintas, Shamoto, Lee & Budak
// 1999, J. Manuf. Sci. Eng. 121: the ball end's zero-order limit).
Eigen::Matrix2d directional_matrix_mm(const force::CutterSlices& cs, const force::Engagement& e,
                                      const force::Coefficients& k);

// The limit at many cuts of one tool. The modal model's FRF is the same in x
// and y with no cross terms, Phi = G I, so the eigenvalues of B Phi (B a
// cut's directional matrix) are mu G, mu an eigenvalue of B: each of the two
// is a lobe problem of its own, whose limit scales as 1 / |mu| and whose
// lobes depend on the phase of mu alone. One chatter sweep per phase (rounded
// to a whole degree) and its limit at each speed a program runs (ap_limit_at),
// each made on first use, serve every cut. Thread-safe: the simulator's
// threads share one.
class LimitCache {
 public:
  // The tip's modes, in x and y alike, and their FRF (tip_model).
  LimitCache(const TipModel& tip, const force::Coefficients& k, int flutes, double max_rpm);
  // A measured FRF, x and y apart, cross terms and all: there the cut's own
  // matrix decides, not one eigenvalue's phase. One sweep per direction of
  // the directional matrix (B / |B|, each entry rounded to 1/64: a limit
  // within about 2 %), its limit scaled by 1 / |B|.
  LimitCache(Frf measured, const force::Coefficients& k, int flutes, double max_rpm);
  // The depth at which a cut with directional matrix B_mm (directional_matrix_mm)
  // and axial depth ap_mm, its engagement scaled along the axis, chatters at
  // `rpm`: ap_mm times the scale at which the first branch goes unstable.
  // +infinity for a cut with no directional matrix (nothing engaged).
  double ap_limit_mm(const Eigen::Matrix2d& B_mm, double ap_mm, double rpm) const;
  const Frf& frf() const { return frf_; }

 private:
  // The limit at `rpm` of the directional matrix kept under `key` (a phase
  // in degrees, or a unit matrix in 64ths), its sweep and the limit made on
  // first use (alpha(): the matrix).
  template <class Key, class Alpha>
  double cached_limit(std::map<Key, std::unique_ptr<ChatterSweep>>& sweeps,
                      std::map<std::pair<Key, double>, double>& limits, const Key& key, double rpm,
                      const Alpha& alpha) const;
  Frf frf_;
  double Kt_N_per_mm2_;
  int flutes_;
  bool symmetric_ = true;  // the modal model's Phi = G I (else a measured FRF)
  double rpm_min_, rpm_max_;
  mutable std::shared_mutex mutex_;
  mutable std::map<int, std::unique_ptr<ChatterSweep>> sweeps_;
  mutable std::map<std::pair<int, double>, double> limits_;  // (phase, rpm) -> mm
  mutable std::map<std::array<int, 4>, std::unique_ptr<ChatterSweep>> matrix_sweeps_;
  mutable std::map<std::pair<std::array<int, 4>, double>, double> matrix_limits_;
};

}  // namespace deflex::stability
