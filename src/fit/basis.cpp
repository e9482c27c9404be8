// fit::simulate_basis() (basis.hpp).
#include "deflex/fit/basis.hpp"

#include <stdexcept>
#include <string>

namespace deflex::fit {

double Basis::predict(std::size_t i, const Scales& s) const {
  double inverse[kStiffnessParams];
  for (int k = 0; k < kStiffnessParams; ++k) inverse[k] = 1 / s[k];
  return scaled_error(errors_mm.row(static_cast<Eigen::Index>(i)).data(), inverse, s[int(Param::coefficients)]);
}

Basis simulate_basis(const std::vector<interp::Motion>& motions, const compensate::Physics& ph,
                     const compensate::Settings& settings, const std::function<const stiffness::Tool*(int)>& tool_of,
                     const compensate::Progress& progress) {
  if (ph.tool_only) throw std::logic_error("fit::simulate_basis: a tool-only run has no machine to fit");
  compensate::Settings s = settings;
  s.flank_profiles = true;
  const std::unique_ptr<compensate::DesignNormals> normals = compensate::design_normals(motions, ph, s);
  const auto machines = basis_machines(ph.machine);
  std::vector<std::vector<double>> cols;
  std::unique_ptr<Surface> surface;
  for (std::size_t b = 0; b < machines.size(); ++b) {
    compensate::Physics pb = ph;
    pb.machine = machines[b];
    pb.consumable_stock = nullptr;  // every basis run starts from the same stock
    const std::string stage = "basis " + std::to_string(b + 1) + "/" + std::to_string(machines.size());
    const std::vector<compensate::Point> pts = compensate::simulate(
        motions, {}, pb, s, [&](const std::string&, double f) { if (progress) progress(stage, f); }, normals.get());
    if (!surface) surface = std::make_unique<Surface>(pts, tool_of);
    cols.push_back(surface->errors(pts));
  }
  Basis r{std::move(*surface), BasisRows(static_cast<Eigen::Index>(cols[0].size()), kStiffnessParams + 1), {}};
  for (std::size_t i = 0; i < cols[0].size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    r.errors_mm(row, 0) = cols[0][i];
    for (int k = 0; k < kStiffnessParams; ++k) r.errors_mm(row, 1 + k) = cols[1 + k][i] - cols[0][i];
  }
  for (int p = 0; p < kParams; ++p) r.present[p] = present(ph.machine, Param(p));
  return r;
}

}  // namespace deflex::fit
