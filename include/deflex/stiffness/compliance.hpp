// C(h): the compliance of the tool on its machine for a load on the tool axis at
// height h above the tip.
#pragma once
#include <vector>

#include <Eigen/Dense>

namespace deflex::stiffness {

// 3x3 compliance, machine axes, mm/N: rows = displacement x, y, z of the load
// point; columns = force x, y, z.
using Compliance = Eigen::Matrix3d;

struct ComplianceRow {
  double height_mm = 0;  // above the tip, on the tool axis
  Compliance matrix_mm_per_N = Compliance::Zero();
};

// Compliance at stations along the tool, interpolated between them.
class ComplianceTable {
 public:
  ComplianceTable() = default;
  // Rows in any order; sorted by height. Heights must be distinct.
  explicit ComplianceTable(std::vector<ComplianceRow> rows);

  // Piecewise-cubic Hermite interpolation (slopes by finite differences), so a
  // cubic-in-h bending compliance is followed closely; h outside the stations is
  // clamped to the nearest end (loads only act along the flutes).
  Compliance at(double height_mm) const;

  const std::vector<ComplianceRow>& rows() const { return rows_; }
  bool empty() const { return rows_.empty(); }
  double min_height_mm() const { return rows_.front().height_mm; }
  double max_height_mm() const { return rows_.back().height_mm; }

 private:
  std::vector<ComplianceRow> rows_;
};

// C(z, z'): the displacement of the tool axis at height z under a unit force at
// height z' (both above the tip, mm; machine axes, mm/N; rows displacement x, y,
// z at z, columns force x, y, z at z'). On the diagonal it is C(h) of
// ComplianceTable; Maxwell-Betti reciprocity gives C(z, z') = C(z', z)^T. Needed
// where the load is spread along the flutes and the deflection is wanted at
// another height (the flank surface error profile, force/flank.hpp).
//
// Stored per station pair as a lateral (x and y alike, axisymmetric chain) and an
// axial influence coefficient plus a constant 3x3 (the machine structure in
// series, which translates the whole tool whatever the load height).
class CrossComplianceTable {
 public:
  CrossComplianceTable() = default;
  // heights_mm ascending and distinct; lateral/axial: n x n, (i, j) = displacement
  // at station i under a unit load at station j.
  CrossComplianceTable(std::vector<double> heights_mm, Eigen::MatrixXd lateral_mm_per_N,
                       Eigen::MatrixXd axial_mm_per_N,
                       const Compliance& structure_mm_per_N = Compliance::Zero());

  // Tensor-product cubic Hermite in z and z' with the slopes ComplianceTable uses
  // (exact at station pairs; the same weights in both variables, so a reciprocal
  // table stays reciprocal between stations). Heights outside are clamped.
  Compliance at(double z_mm, double zp_mm) const;

  const std::vector<double>& heights_mm() const { return h_; }
  const Eigen::MatrixXd& lateral_mm_per_N() const { return lateral_; }
  const Eigen::MatrixXd& axial_mm_per_N() const { return axial_; }
  bool empty() const { return h_.empty(); }

 private:
  std::vector<double> h_;
  Eigen::MatrixXd lateral_, axial_;
  Compliance structure_ = Compliance::Zero();
};

// Deflection of the load point, mm, machine axes, under force_N at height h:
// delta = C(h) F.
Eigen::Vector3d deflection_mm(const ComplianceTable& c, double height_mm,
                              const Eigen::Vector3d& force_N);

// C(h) at each height.
std::vector<ComplianceRow> sample(const ComplianceTable& c, const std::vector<double>& heights_mm);

// Heights of the table stations: n equal steps from 0 to top_mm (n >= 1).
std::vector<double> station_heights_mm(double top_mm, int steps);

}  // namespace deflex::stiffness
