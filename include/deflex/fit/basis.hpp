// The surface errors of a program on each basis machine (model.hpp): one
// simulation per term, after which any stiffness and coefficient scales give
// the prediction at every sample as a weighted sum, without simulating again.
#pragma once
#include <vector>

#include <Eigen/Core>

#include "deflex/compensate/compensate.hpp"
#include "deflex/fit/model.hpp"
#include "deflex/fit/surface.hpp"
#include "deflex/interp/motion.hpp"

namespace deflex::fit {

// One row per sample, its terms contiguous (scaled_error() reads a row).
using BasisRows = Eigen::Matrix<double, Eigen::Dynamic, kStiffnessParams + 1, Eigen::RowMajor>;

struct Basis {
  Surface surface;
  // samples x (kStiffnessParams + 1): column 0 the fixed part's error, column
  // 1 + k that of stiffness parameter k at the starting profile, mm.
  BasisRows errors_mm;
  std::array<bool, kParams> present{};  // the starting profile has the component

  // The error at sample i with the stiffness scales and coefficients' scale of `s`.
  double predict(std::size_t sample, const Scales& s) const;
};

// Simulates `motions` on each basis machine of ph.machine (ph.tool_only must
// be false: the machine is what is fitted). `progress` sees the stage
// "basis k/6" per simulation.
Basis simulate_basis(const std::vector<interp::Motion>& motions, const compensate::Physics& ph,
                     const compensate::Settings& s, const std::function<const stiffness::Tool*(int)>& tool_of,
                     const compensate::Progress& progress = {});

}  // namespace deflex::fit
