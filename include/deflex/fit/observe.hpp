// Measured points matched with the samples of a simulated surface: the
// measured error of each, and which sample predicts it.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "deflex/fit/surface.hpp"
#include "deflex/part/part.hpp"

namespace deflex::fit {

// One measured point.
struct Observation {
  V3 at_mm = V3::Zero();  // a point of the machined surface (CSV, cloud), or the probed point's intended position
  // The measured error along the intended normal where the measurement gives
  // it (a probe log joined with its probe program); else it is measured here
  // against the intended surface (match()).
  std::optional<double> error_mm;
  std::string feature;    // the test cut's feature ("": none)
  std::string source;     // "file:line", for messages
};

struct Matched {
  std::size_t observation = 0;
  std::size_t sample = 0;
  double measured_error_mm = 0;  // e > 0: material left
};

struct Matching {
  std::vector<Matched> matched;
  std::vector<std::size_t> unmatched;  // observations farther than the reach from every sample
};

// Each observation with its nearest sample within reach_mm. The measured error
// where not given: the signed distance from the intended surface along its
// normal, the intended surface being `part` when given (its closest point and
// normal), else the sample's point and normal (the rigid cutter's envelope).
Matching match(const Surface& surface, const std::vector<Observation>& obs, double reach_mm,
               const part::PartModel* part = nullptr);

}  // namespace deflex::fit
