// Measured points matched with the samples of a simulated surface: the
// measured error of each, and which sample predicts it.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deflex/fit/surface.hpp"
#include "deflex/part/part.hpp"

namespace deflex::fit {

// One measured point.
struct Observation {
  V3 at_mm = V3::Zero();  // a point of the machined surface (CSV, cloud), or the probed point's intended position
  V3 measured_mm = V3::Zero();  // the machined surface's point (= at_mm but for a probe log)
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

// The measured error of `o` against its sample `s` (see match()).
double measured_error(const Observation& o, const SurfaceSample& s, const part::PartModel* part);

// Each observation with its nearest sample within reach_mm. The measured error
// where not given: the signed distance from the intended surface along its
// normal, the intended surface being `part` when given (its closest point and
// normal), else the sample's point and normal (the rigid cutter's envelope).
Matching match(const Surface& surface, const std::vector<Observation>& obs, double reach_mm,
               const part::PartModel* part = nullptr);

// The same held against a simulation as it runs (simulate --measured): each
// observation keeps the nearest sample of the points seen so far, so memory
// is the observations' whatever the program's length. Points come in program
// order from one thread; the nearest sample of equal distance is the later's.
class Nearest {
 public:
  Nearest(const std::vector<Observation>& obs, double reach_mm,
          std::function<const stiffness::Tool*(int)> tool_of);
  Nearest(Nearest&&) noexcept;
  ~Nearest();
  // `offset_mm`: where the point runs off the design (simulate against a
  // reference: the compensation), so that the samples lie on the design
  // surface and their errors are measured from it (landing_error()).
  void add(const compensate::Point& p, const V3& offset_mm = V3::Zero());

  struct Found {
    bool found = false;
    SurfaceSample sample;
    double predicted_error_mm = 0;
    double distance_mm = 0;
  };
  const std::vector<Found>& found() const { return found_; }

 private:
  struct Index;
  std::unique_ptr<Index> index_;
  std::vector<Found> found_;
  double reach_mm_;
  std::function<const stiffness::Tool*(int)> tool_of_;
  std::uint32_t points_ = 0;
  std::vector<SurfaceSample> scratch_;
};

// Predicted against measured over the observations that have both.
struct Agreement {
  std::size_t points = 0;                  // with a prediction and a measurement
  double rms_difference_mm = 0, max_difference_mm = 0;  // predicted - measured
  double correlation = 0;                  // Pearson's, NaN below 3 points or without spread
  double within_tolerance_share = 0;       // |predicted - measured| <= tolerance
  double rms_measured_mm = 0, max_measured_mm = 0;  // |measured error|
};
Agreement agreement(const std::vector<double>& predicted_mm, const std::vector<double>& measured_mm, double tolerance_mm);

}  // namespace deflex::fit
