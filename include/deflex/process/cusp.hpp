// Cusp height of ball-end finishing: Mikó, Beňo, Maňková,
// "Experimental verification of cusp heights when 3D milling rounded surfaces"
// (Mikó et al., Eq. 1-7; docs/physics.md).
//
// The cusp left between two neighbouring passes of a ball end of effective
// diameter D_e with a horizontal step-over a_e on a surface inclined by alpha_1:
//   alpha_3 = atan(sin A tan alpha_1)                                   (Eq. 4)
//   Ch = D_e/2 - sqrt((D_e/2)^2 - (a_e / (2 cos alpha_3))^2)            (Eq. 7)
// (Eq. 1 is alpha_3 = 0, Eq. 2 alpha_3 = alpha_1.) a_e / cos alpha_3 is the
// step-over measured on the surface, alpha_3 the slope of the surface along the
// step-over (horizontal, across the feed).
//
// The milling direction A. The paper's text calls A = 90 deg "ramping" and says
// the cusp then does not depend on the slope, which Eq. 4 (alpha_3 = alpha_1 at
// A = 90) contradicts. We keep Eq. 4 as printed and define A so that it gives
// the slope along the step-over, the quantity Eq. 7 needs: A is the angle in the
// horizontal plane between the feed direction and the fall line (the steepest
// descent of the surface). A = 0: the tool runs up or down the slope, the
// step-over follows a level line, alpha_3 = 0; A = 90 deg: the tool runs along a
// level line (contouring a slope), the step-over climbs it, alpha_3 = alpha_1.
//
// D_e is the diameter of the cutter's profile that forms the cusp: for a ball
// end its diameter D, whatever the depth of cut (the section of the swept ball
// across the feed is a circle of radius D/2). Other tools are outside the
// paper's model and get no cusp height.
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <vector>

namespace deflex::process {

// Eq. 4: the surface slope along the step-over, radians.
double cusp_alpha3_rad(double milling_direction_rad, double inclination_rad);

// Eq. 7: the cusp height, mm. A step-over on the surface wider than D_e leaves
// the whole radius standing: D_e / 2.
double cusp_height_mm(double effective_diameter_mm, double stepover_mm, double alpha3_rad);

// One CL point of a program for the per-point analysis.
struct CuspSample {
  Eigen::Vector3d tip_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d feed_dir = Eigen::Vector3d::Zero();  // direction of travel (any length; zero: none)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();   // outward unit normal of the design surface
  double profile_diameter_mm = 0; // D_e; 0: not a ball end, no cusp
  bool cutting = false;           // in material: gets a cusp (a neighbour may be in air)
  // The normal is the design surface's (false: a guess, compensate's
  // NormalSource::undetermined): the cusp's angles, and so the cusp, are not
  // known there (a steep guess across the feed would give the ball's radius).
  bool normal_known = true;
};

struct CuspResult {
  static constexpr double none = std::numeric_limits<double>::quiet_NaN();
  double stepover_mm = none;       // horizontal, across the feed, to the nearest neighbouring pass
  double inclination_deg = none;   // alpha_1: the normal's angle from +Z
  double direction_deg = none;     // A, 0..90 (see above)
  double alpha3_deg = none;
  double height_mm = none;         // Ch (NaN: no neighbouring pass, or not a ball end)
};

// Per sample: the step-over to the nearest neighbouring pass on either side
// (the larger of the two cusps where there are two), the angles and Ch.
// A neighbouring pass is another stretch of cutting path within D_e across the
// feed, running within 30 deg of parallel (either way: zig-zag reverses), and
// farther across than the point's own path could be if it ran there bent no
// tighter than the ball's radius: across > 1 um + along^2 / D_e. So the own
// pass, curved or closed on itself (a contour meeting its start), is never
// its neighbour, while the next pass of a zig-zag is, right up to the turn
// where the two passes are a short link apart along the path. The distance across is
// measured from the point to the line of travel of the neighbour's sample
// nearest to it, so on straight passes it does not depend on where the samples
// fall. Of equally near samples the one earlier in the program counts (so the
// result does not depend on how a search orders them). Neighbours are found
// through CGAL's kd-tree; O(n log n).
//
// The neighbours of a sample are searched in a window of the program, not all
// of it, so that a program of any length is read in constant memory: its
// block of `block` samples and the blocks before and after (a pass is its
// neighbour's neighbour in program order in every strategy but one returning
// to a region much later). Programs of up to 2 blocks are searched whole.
// Each block's kd-tree is built once, when the block is whole, and searched
// for its own samples and those of the blocks beside it.
constexpr std::size_t kCuspBlock = 32768;
std::vector<CuspResult> cusp_heights(const std::vector<CuspSample>& samples, std::size_t block = kCuspBlock);

namespace detail {
struct CuspBlock;  // the samples of a block and their kd-tree (cusp.cpp)
}

// The same over samples given one at a time, in program order: the results of
// a block are known once the block after it is whole (or after finish()).
class CuspStream {
 public:
  explicit CuspStream(std::size_t block = kCuspBlock);
  ~CuspStream();
  CuspStream(CuspStream&&) noexcept;
  void add(const CuspSample& s);  // sample number size()
  void finish();
  std::size_t size() const { return size_; }
  std::size_t ready() const { return ready_; }  // the results of samples [0, ready()) are known
  const CuspResult& result(std::size_t i) const;  // not forgotten, below ready()
  void forget_before(std::size_t i);             // results below i are not asked for again

 private:
  void solve(std::size_t b);
  std::size_t block_, size_ = 0, ready_ = 0, blocks_base_ = 0, results_base_ = 0;
  std::deque<std::unique_ptr<detail::CuspBlock>> blocks_;  // from block blocks_base_ on
  std::deque<CuspResult> results_;
};

}  // namespace deflex::process
