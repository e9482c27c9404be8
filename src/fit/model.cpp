// fit::scaled() and fit::basis_machines() (model.hpp).
#include "deflex/fit/model.hpp"

namespace deflex::fit {

const char* name(Param p) {
  switch (p) {
    case Param::clamp: return "tool clamp";
    case Param::spindle: return "spindle";
    case Param::structure_x: return "structure X";
    case Param::structure_y: return "structure Y";
    case Param::structure_z: return "structure Z";
    case Param::coefficients: return "force coefficients";
  }
  return "";
}

const char* profile_key(Param p) {
  switch (p) {
    case Param::clamp: return "stiffness.tool_clamp";
    case Param::spindle: return "stiffness.spindle";
    case Param::structure_x: return "stiffness.structure x";
    case Param::structure_y: return "stiffness.structure y";
    case Param::structure_z: return "stiffness.structure z";
    case Param::coefficients: return "the material's coefficients";
  }
  return "";
}

namespace {

stiffness::Springs times(const stiffness::Springs& s, double k) {
  stiffness::Springs r = s;
  if (r.radial_N_per_mm) *r.radial_N_per_mm *= k;
  if (r.rotational_Nmm_per_rad) *r.rotational_Nmm_per_rad *= k;
  if (r.axial_N_per_mm) *r.axial_N_per_mm *= k;
  return r;
}

Eigen::Matrix3d off_diagonal(const Eigen::Matrix3d& c) {
  Eigen::Matrix3d o = c;
  o.diagonal().setZero();
  return o;
}

}  // namespace

bool present(const stiffness::MachineStiffness& m, Param p) {
  switch (p) {
    case Param::clamp: return m.tool_clamp && m.tool_clamp->any();
    case Param::spindle: return m.spindle && m.spindle->any();
    case Param::structure_x: return m.structure_mm_per_N(0, 0) > 0;
    case Param::structure_y: return m.structure_mm_per_N(1, 1) > 0;
    case Param::structure_z: return m.structure_mm_per_N(2, 2) > 0;
    case Param::coefficients: return true;
  }
  return false;
}

stiffness::MachineStiffness scaled(const stiffness::MachineStiffness& start, const Scales& s) {
  stiffness::MachineStiffness m = start;
  if (m.tool_clamp) m.tool_clamp = times(*m.tool_clamp, s[int(Param::clamp)]);
  if (m.spindle) m.spindle = times(*m.spindle, s[int(Param::spindle)]);
  for (int a = 0; a < 3; ++a) m.structure_mm_per_N(a, a) /= s[int(Param::structure_x) + a];
  return m;
}

std::array<stiffness::MachineStiffness, kStiffnessParams + 1> basis_machines(const stiffness::MachineStiffness& start) {
  stiffness::MachineStiffness fixed = start;
  fixed.tool_clamp.reset();
  fixed.spindle.reset();
  fixed.structure_mm_per_N = off_diagonal(start.structure_mm_per_N);
  std::array<stiffness::MachineStiffness, kStiffnessParams + 1> b;
  b.fill(fixed);
  b[1 + int(Param::clamp)].tool_clamp = start.tool_clamp;
  b[1 + int(Param::spindle)].spindle = start.spindle;
  for (int a = 0; a < 3; ++a)
    b[1 + int(Param::structure_x) + a].structure_mm_per_N(a, a) = start.structure_mm_per_N(a, a);
  return b;
}

}  // namespace deflex::fit
