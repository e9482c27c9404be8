// The surface a simulation says the program leaves, as samples on the design
// surface (the envelope of the rigid cutter) with the error predicted there,
// and the matching of measured points with them.
//
// A flank cut (force/flank.hpp) gives one sample per engaged slice of its wall
// profile e(z); any other cutting point one at its contact (compensate/
// contact.hpp) with its error along the normal. A measured point takes the
// nearest sample: on a wall the nearest sample lies on the last pass that
// generated it, since an earlier pass's samples stand farther out in the air
// it removed. Farther than the reach from every sample, a point has no
// prediction: it is counted and said, never matched with a guess.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "deflex/compensate/compensate.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::fit {

using V3 = compensate::V3;

struct SurfaceSample {
  V3 at_mm = V3::Zero();   // on the design surface, work frame
  V3 normal = V3::UnitZ(); // outward (from the material into the air)
  std::uint32_t line = 0;  // the program line that generated it
  std::uint32_t point = 0; // index of its CL point in the simulation's points
  int slice = -1;          // its flank profile entry, -1: the point's contact
};

// The samples of one CL point (none in air or on a plunge); `index` is its
// index in the simulation's points.
void append_samples(const compensate::Point& p, std::uint32_t index, const stiffness::Tool& t,
                    std::vector<SurfaceSample>& out);
// The error the point predicts at one of its samples, mm.
double sample_error(const compensate::Point& p, const SurfaceSample& s);

class Surface {
 public:
  // The samples of a simulation's points (simulate() with
  // Settings::flank_profiles); `tool_of` gives the cutter of a T number.
  Surface(const std::vector<compensate::Point>& points,
          const std::function<const stiffness::Tool*(int)>& tool_of);
  Surface(Surface&&) noexcept;
  Surface& operator=(Surface&&) noexcept;
  ~Surface();

  const std::vector<SurfaceSample>& samples() const { return samples_; }
  // The errors another simulation of the same program (same engagement: only
  // the stiffness or the coefficients differ) predicts at each sample, mm.
  // Throws std::logic_error when its points are not those of this surface.
  std::vector<double> errors(const std::vector<compensate::Point>& points) const;

  // The nearest sample to p within reach_mm, or -1.
  long nearest(const V3& p_mm, double reach_mm) const;

 private:
  std::vector<SurfaceSample> samples_;
  std::vector<std::uint32_t> slices_of_point_;  // per point: its flank profile's length when sampled
  struct Index;
  std::unique_ptr<Index> index_;
};

}  // namespace deflex::fit
