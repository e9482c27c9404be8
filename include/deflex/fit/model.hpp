// The machine as the few numbers a test cut can tell apart: a scale of each
// stiffness a machine profile gives (tool clamp, spindle, structure per axis)
// and a scale of the material's force coefficients.
//
// Why a scale per section, not per spring: a clamp's radial, rotational and
// axial springs are one joint (a collet or shrink fit that is stiffer or
// softer as a whole); fitting them apart would ask a wall's error profile,
// nearly straight over a few millimetres, for more shapes than it has.
//
// The surface error is linear in each compliance and in the force: the chain
// of tool, clamp, holder and spindle is a cantilever (statically determinate),
// so its flexibility is the sum of each element's, each proportional to that
// element's compliance (stiffness/beam.hpp); the structure adds in series;
// the mechanistic forces scale with the coefficients (force/mechanistic.hpp).
// So with the engagement fixed by the programmed path,
//
//   e(point) = s * ( e_fixed + sum_k e_k / lambda_k ),
//
// e_fixed from the tool and holder alone (and a structure's off-diagonal
// terms), e_k from component k of the starting profile alone, lambda_k its
// stiffness scale, s the coefficients' scale. One simulation per basis term
// gives every e_k; the fit then never simulates again.
#pragma once
#include <array>
#include <string>

#include "deflex/stiffness/machine.hpp"

namespace deflex::fit {

enum class Param { clamp, spindle, structure_x, structure_y, structure_z, coefficients };
constexpr int kParams = 6;
// The stiffness terms of the basis (every parameter but the coefficients' scale).
constexpr int kStiffnessParams = 5;

// "tool clamp", "spindle", "structure X", ..., "force coefficients".
const char* name(Param p);
// The profile key the parameter scales, for messages: "stiffness.tool_clamp", ...
const char* profile_key(Param p);

using Scales = std::array<double, kParams>;  // indexed by Param; 1 = the starting profile
inline Scales unit_scales() { return {1, 1, 1, 1, 1, 1}; }

// The starting machine with each stiffness multiplied by its scale (the
// structure's diagonal compliance divided by it; off-diagonal terms kept).
stiffness::MachineStiffness scaled(const stiffness::MachineStiffness& start, const Scales& s);

// The basis machines: [0] the fixed part (holder, no clamp or spindle spring,
// the structure's off-diagonal terms), then one per stiffness parameter: the
// fixed part plus that component of `start` alone. A component `start` does
// not have (rigid) gives a basis machine equal to the fixed part.
std::array<stiffness::MachineStiffness, kStiffnessParams + 1> basis_machines(const stiffness::MachineStiffness& start);

// The error at one sample from its basis row (row[0] the fixed part's error,
// row[1 + k] stiffness term k's, mm), the reciprocal of each stiffness scale
// and the coefficients' scale: s * (e_fixed + sum_k e_k / lambda_k). The one
// place the formula is written: the fit's residuals (with Ceres' automatic
// derivatives, T a Jet) and Basis::predict() both call it.
template <class T>
T scaled_error(const double* row, const T* inverse_stiffness_scales, const T& coefficients_scale) {
  T e = T(row[0]);
  for (int k = 0; k < kStiffnessParams; ++k) e += row[1 + k] * inverse_stiffness_scales[k];
  return coefficients_scale * e;
}

// Whether `start` has the component at all (a rigid one cannot be scaled).
bool present(const stiffness::MachineStiffness& start, Param p);

}  // namespace deflex::fit
