// Mechanistic milling forces over one spindle revolution.
//
// Forces act on the tool, in machine axes (feed +X, spindle axis +Z up), N.
// Per edge element at immersion phi (see engagement.hpp) and axial immersion kappa
// (Engin & Altintas 2001; Smaoui 2011 Eq. 5 with beta = phi, eta = kappa):
//   dFx = -dFr sin(k) sin(phi) - dFt cos(phi) - dFa cos(k) sin(phi)
//   dFy = -dFr sin(k) cos(phi) + dFt sin(phi) - dFa cos(k) cos(phi)
//   dFz =  dFr cos(k)                         - dFa sin(k)
// with dF_q = K_qc h db + K_qe dS and h = f_z sin(phi) sin(k) (no force where h <= 0).
// Tooth j's edge at height z has phi = theta + j * pitch - psi(z), theta the
// spindle rotation angle (tooth 0's tip immersion).
#pragma once
#include <Eigen/Core>
#include <span>
#include <vector>

#include "deflex/force/coefficients.hpp"
#include "deflex/force/cutter.hpp"
#include "deflex/force/engagement.hpp"

namespace deflex::force {

using Vec3 = Eigen::Vector3d;  // machine axes X, Y, Z

// Rotation angles theta_j = j * 2 pi / steps, j = 0..steps-1, with their sines and
// cosines; build once per step count and share (read-only) between threads.
struct AngleGrid {
  int steps = 0;
  std::vector<double> sin_t, cos_t;
};
AngleGrid make_angle_grid(int steps);

// Force on the tool at rotation theta (exact point evaluation, all teeth, all slices).
Vec3 force_at_angle(const CutterSlices& cs, const Coefficients& k, double fz_mm,
                    const Engagement& eng, double theta);

// Forces at theta_j of `grid` into out_N (size grid.steps). Each sample is the mean
// over the angular cell [theta_j - dtheta/2, theta_j + dtheta/2], so the mean of
// the samples is the revolution mean up to O(dtheta^2) even for slot entries and
// exits. Does not allocate. When steps is a multiple of the flute count it
// evaluates one tooth pitch and repeats it (forces are periodic in the pitch).
void revolution_forces(const CutterSlices& cs, const AngleGrid& grid, const Coefficients& k,
                       double fz_mm, const Engagement& eng, std::span<Vec3> out_N);

struct ForceSummary {
  Vec3 mean_N = Vec3::Zero();
  Vec3 peak_abs_N = Vec3::Zero();  // per axis, max |F| over the revolution
};
ForceSummary summarize(std::span<const Vec3> forces_N);

// Convenience: allocates the result.
std::vector<Vec3> revolution_forces(const CutterSlices& cs, const Coefficients& k, double fz_mm,
                                    const Engagement& eng, int steps);

// The mean torque on the spindle over a revolution, N m: the tangential element
// forces at their radius, sum r dF_t, averaged over the rotation. Each tooth
// passes every immersion once per revolution, so the mean is the integral over
// the engaged angles in closed form (per slice and tooth, with h > 0 where
// sin(phi) > 0): (flutes / 2 pi) r [K_tc f_z sin(k) db (cos a - cos b) + K_te dS (b - a)].
// Split into what grows with the chip (f_z) and the edge's part, which does
// not: the feed that keeps the torque under a limit follows from it.
struct MeanTorque {
  double cutting_Nm = 0, edge_Nm = 0;
  double total_Nm() const { return cutting_Nm + edge_Nm; }
};
MeanTorque mean_torque(const CutterSlices& cs, const Coefficients& k, double fz_mm, const Engagement& eng);

// The largest s in [0, 1] with max over the revolution |edge + s (total - edge)|
// <= limit_N: the share of the feed per tooth at which the peak force meets the
// limit. total_N the forces at f_z (revolution_forces), edge_N at f_z = 0 (the
// edge forces alone), on the same grid; the cutting part is linear in f_z, so
// at every angle this is a quadratic in s. 0 when the edge forces alone exceed
// the limit somewhere (no feed keeps it), 1 when the peak is within it.
double peak_feed_share(std::span<const Vec3> total_N, std::span<const Vec3> edge_N, double limit_N);

// Surface-generating force (Morelli 2021 §2.3): the machined surface at height z is
// generated when an edge at z passes the surface-normal immersion angle phi_n (pi
// for down-milling on a -Y wall, 0 for up-milling on a +Y wall). For each engaged
// slice, the total force on the tool at that instant.
struct SurfaceForce {
  double z_mm = 0;
  Vec3 force_N = Vec3::Zero();
};
std::vector<SurfaceForce> surface_generating_forces(const CutterSlices& cs, const Coefficients& k,
                                                    double fz_mm, const Engagement& eng,
                                                    double normal_phi);
// The same into `out` (cleared first; reuse it so that warm calls do not allocate).
void surface_generating_forces(const CutterSlices& cs, const Coefficients& k, double fz_mm,
                               const Engagement& eng, double normal_phi,
                               std::vector<SurfaceForce>& out);

// The distribution behind surface_generating_forces, for the surface error
// profile (flank.hpp): at the instant the edge at engaged slice i passes
// normal_phi, the force engaged slice m carries (all its teeth in the cut), N,
// same frame as above. Summed over m it is surface_generating_forces()[i]
// (up to rounding). Same element force law (one code path).
struct GeneratingLoads {
  std::vector<std::size_t> slice;  // engaged slice indices into cs.slices, ascending
  std::vector<double> z_mm;        // their mid heights above the tip
  std::vector<Vec3> force_N;       // size() x size(), row-major: [i * size() + m]
  std::size_t size() const { return slice.size(); }
  const Vec3& at(std::size_t i, std::size_t m) const { return force_N[i * size() + m]; }
};
void surface_generating_loads(const CutterSlices& cs, const Coefficients& k, double fz_mm,
                              const Engagement& eng, double normal_phi, GeneratingLoads& out);

// The component along the in-plane unit normal (sin phi_n, cos phi_n, 0) with the
// largest magnitude among those slices (0 when nothing is engaged).
struct SurfaceForcePeak {
  double normal_N = 0;
  double z_mm = 0;
};
SurfaceForcePeak peak_normal(std::span<const SurfaceForce> sf, double normal_phi);

}  // namespace deflex::force
