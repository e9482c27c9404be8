// The surface error profile of a flat or bull-nose end mill cutting with its
// flank, along the axial depth (Morelli et al. 2021, §2.3-2.4; docs/physics.md).
//
// The wall at height z is generated when the edge at z passes the generating
// immersion angle phi_n (the exit, pi, in down-milling; the entry, 0, in
// up-milling). Because of the helix every height is generated at its own instant,
// and the tool then carries the force distribution of that instant, not the
// revolution mean. The error of the wall at z is the tool's displacement at z
// along the wall's outward normal n:
//
//   e(z) = n . sum over engaged slices z' of C(z, z') dF_gen(z, z')
//
// dF_gen(z, z'): force slice z' carries when the edge at z is at phi_n
// (surface_generating_loads, mechanistic.hpp); C(z, z'): cross compliance, mm/N
// (stiffness/compliance.hpp CrossComplianceTable). Morelli's Table 2 key points
// are where the surface-generating force profile changes shape; with a
// height-independent compliance e(z) is that profile scaled, with a real one it
// is "twisted" (their §3.2), the kinks staying where they are.
//
// Frames and units: forces, the normal and the compliance must share one frame;
// the force model's is the feed frame (feed +X, spindle axis +Z, the immersion
// convention of engagement.hpp). An axisymmetric tool chain (diag(c, c, c_z))
// reads the same in machine axes; an anisotropic machine structure must be
// rotated into the feed frame first (R^T C R). Heights: mm above the tool tip.
// Errors: mm, positive where the tool is pushed away from the wall into the air,
// i.e. material is left (undercut).
#pragma once
#include <Eigen/Core>
#include <functional>
#include <span>
#include <vector>

#include "deflex/force/coefficients.hpp"
#include "deflex/force/cutter.hpp"
#include "deflex/force/engagement.hpp"
#include "deflex/force/mechanistic.hpp"

namespace deflex::force {

using Mat3 = Eigen::Matrix3d;

// C(z_i, z_m) between the slices of one CutterSlices, mm/N: build once per tool
// (the slicing is fixed per tool), read per CL point.
struct SliceCompliance {
  std::size_t n = 0;                  // = cs.slices.size()
  std::vector<Mat3> c_mm_per_N;       // n x n, row-major: [i * n + m]
  const Mat3& at(std::size_t i, std::size_t m) const { return c_mm_per_N[i * n + m]; }
};
// c(z_mm, zp_mm): displacement at z under a unit force at zp (e.g. a
// stiffness::CrossComplianceTable's at()).
SliceCompliance slice_compliance(const CutterSlices& cs,
                                 const std::function<Mat3(double z_mm, double zp_mm)>& c);

// Generating immersion angle: the exit pi in down-milling, the entry 0 in
// up-milling (Morelli 2021 §2; the cut is on phi in (0, pi), engagement.hpp).
double generating_phi(MillingMode mode);
// The wall's outward unit normal (from the material towards the tool axis) where
// the edge at immersion phi_n generates it: -(sin phi_n, cos phi_n, 0), feed frame.
Vec3 wall_normal(double phi_n);

struct FlankPoint {
  double z_mm = 0;      // engaged slice mid height above the tip
  double error_mm = 0;  // e(z), see above
};

struct FlankProfile {
  std::vector<FlankPoint> points;  // one per engaged slice, ascending z
  double min_mm = 0, max_mm = 0;   // extremes of e(z) (0 with no engaged slice)
  double z_of_min_mm = 0, z_of_max_mm = 0;
  // (max + min) / 2: the one offset s minimising max |e(z) - s| over the flank.
  double mid_offset_mm = 0;
  // mid_offset_mm * n: shifting the programmed path by minus this vector (mm,
  // same frame) centres the error band on the nominal wall.
  Vec3 mid_offset_vec_mm = Vec3::Zero();
};

// Inputs of one CL point. Engagement slices index cs.slices.
struct FlankInput {
  const CutterSlices& cs;
  const Coefficients& k;
  double fz_mm;
  const Engagement& eng;
  double phi_n;      // generating immersion angle, rad (generating_phi)
  Vec3 normal;       // wall's outward unit normal (wall_normal(phi_n) for a wall along the feed)
};

FlankProfile flank_error_profile(const FlankInput& in, const SliceCompliance& c);
// The same reusing `loads` and `out` (warm calls do not allocate).
void flank_error_profile(const FlankInput& in, const SliceCompliance& c, GeneratingLoads& loads,
                         FlankProfile& out);

// Fills min/max, where they lie and the mid-range offset from out.points.
void summarize_profile(const Vec3& normal, FlankProfile& out);

// Where the shape of a sampled profile changes (the key points of Morelli 2021
// Table 2). A slope break is a segment end of the generating force distribution
// with a finite load density (a flute's entry edge crossing the tip or the top of
// the cut: z_3, z_L, z_2m, z_H); a curvature break one at zero density (an exit
// edge, no chip: z_M, z_m). Found by fitting a quadratic to the 6 samples on
// each side of every sample and comparing slopes and curvatures; extrema are
// strict over +-5 samples. Breaks within 11 samples of either end go unseen.
// The slicing quantises breaks to the samples: expect them within half a slice.
enum class FeatureKind { slope_break, curvature_break, minimum, maximum };
const char* to_string(FeatureKind k);
struct ProfileFeature {
  FeatureKind kind = FeatureKind::slope_break;
  double z_mm = 0;
  double strength = 0;  // jump over the robust background of the measure (0 for extrema)
};
// Points must be equally spaced in z. `min_strength`: how many times the robust
// background (median) a jump must exceed.
std::vector<ProfileFeature> profile_features(std::span<const FlankPoint> points,
                                             double min_strength = 8);

}  // namespace deflex::force
