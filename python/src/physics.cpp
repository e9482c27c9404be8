// The physics as plain calls, the library functions behind `deflex stiffness`
// (src/cli/cmd_stiffness.cpp), `deflex forces` (src/cli/cmd_forces.cpp),
// `deflex stability` (src/cli/cmd_stability.cpp) and the cusp height (process/cusp.hpp): numbers and NumPy arrays, units in the
// names. Libraries default as a job's do (job/setup.hpp: config.yaml, else
// the installed samples).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include "bindings.hpp"
#include "deflex/force/mechanistic.hpp"
#include "deflex/force/tool.hpp"
#include "deflex/job/setup.hpp"
#include "deflex/job/physics.hpp"
#include "deflex/job/stability.hpp"
#include "deflex/process/cusp.hpp"
#include "deflex/profile/profile.hpp"
#include "deflex/stiffness/compliance.hpp"
#include "settings.hpp"

namespace deflex::python {
namespace {

namespace st = deflex::stiffness;
namespace fo = deflex::force;

std::string opt_path(const char* what, const py::object& v) { return v.is_none() ? "" : path_text(what, v); }

py::dict compliance(const std::string& tool, const py::object& tool_file, const py::object& machine,
                    const std::optional<std::vector<double>>& heights_mm, bool tool_only, const std::string& method,
                    double mesh_mm) {
  job::ComplianceSettings cs;
  cs.tool = tool;
  cs.tool_file = opt_path("tool_file", tool_file);
  // No machine: the tool clamped rigidly at the holder face, as `deflex stiffness` without --machine.
  cs.machine = tool_only ? "" : opt_path("machine", machine);
  cs.heights_mm = heights_mm.value_or(std::vector<double>());
  if (heights_mm && heights_mm->empty()) throw Error(ErrorKind::settings, "heights_mm: give at least one height");
  cs.method = method;
  cs.mesh_mm = mesh_mm;
  std::vector<st::ComplianceRow> rows;
  {
    py::gil_scoped_release nogil;  // the solid model meshes and solves for seconds
    rows = job::compliance(cs).rows;
  }
  py::array_t<double> h(py::ssize_t(rows.size())), c({py::ssize_t(rows.size()), py::ssize_t(3), py::ssize_t(3)});
  auto hw = h.mutable_unchecked<1>();
  auto cw = c.mutable_unchecked<3>();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    hw(py::ssize_t(i)) = rows[i].height_mm;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) cw(py::ssize_t(i), r, k) = rows[i].matrix_mm_per_N(r, k);
  }
  py::dict d;
  d["heights_mm"] = h;
  d["matrix_mm_per_N"] = c;
  return d;
}

py::dict forces(const std::string& tool, const py::object& tool_file, const job::MaterialSettings& mat, double ae_mm,
                double ap_mm, double fz_mm, const std::string& milling, int steps, double dz_mm) {
  if (milling != "up" && milling != "down")
    throw Error(ErrorKind::settings, "milling must be 'up' or 'down', not '" + milling + "'");
  job::ForceSettings fs;
  fs.tool = tool;
  fs.tool_file = opt_path("tool_file", tool_file);
  fs.material = mat;
  fs.ae_mm = ae_mm, fs.ap_mm = ap_mm, fs.fz_mm = fz_mm, fs.dz_mm = dz_mm;
  fs.up_milling = milling == "up";
  fs.steps = steps;
  const job::ForceResult r = job::forces(fs);
  py::array_t<double> angle(static_cast<py::ssize_t>(steps)), force({py::ssize_t(steps), py::ssize_t(3)});
  auto aw = angle.mutable_unchecked<1>();
  auto fw = force.mutable_unchecked<2>();
  for (int j = 0; j < steps; ++j) {
    aw(j) = 360.0 * j / steps;
    for (int c = 0; c < 3; ++c) fw(j, c) = r.force_N[std::size_t(j)][c];
  }
  auto vec = [](const fo::Vec3& v) { return py::array_t<double>(3, v.data()); };
  py::dict d;
  d["angle_deg"] = angle;
  d["force_N"] = force;
  d["mean_N"] = vec(r.summary.mean_N);
  d["peak_abs_N"] = vec(r.summary.peak_abs_N);
  if (r.shape_code) d["shape_code"] = *r.shape_code;
  return d;
}

py::array_t<double> pairs_array(const std::vector<std::pair<double, double>>& v) {
  py::array_t<double> a({py::ssize_t(v.size()), py::ssize_t(2)});
  auto w = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < v.size(); ++i) w(py::ssize_t(i), 0) = v[i].first, w(py::ssize_t(i), 1) = v[i].second;
  return a;
}

py::dict stability(job::StabilitySettings s, const std::string& milling, const std::optional<std::pair<double, double>>& rpm) {
  if (milling != "up" && milling != "down")
    throw Error(ErrorKind::settings, "milling must be 'up' or 'down', not '" + milling + "'");
  s.up_milling = milling == "up";
  if (rpm) s.rpm_min = rpm->first, s.rpm_max = rpm->second;
  const job::StabilityResult r = job::stability(s);
  py::list modes;
  for (const auto& m : r.modes) {
    py::dict d;
    d["frequency_Hz"] = m.frequency_Hz, d["damping_ratio"] = m.damping_ratio, d["stiffness_N_per_mm"] = m.stiffness_N_per_mm;
    modes.append(d);
  }
  py::dict d;
  d["limit"] = pairs_array(r.limit);
  d["pockets"] = pairs_array(r.pockets);
  d["ap_min_mm"] = r.lobes.ap_min_mm;
  d["ap_min_chatter_Hz"] = r.lobes.ap_min_chatter_Hz;
  d["modes"] = modes;
  d["frf_source"] = r.frf_source;
  return d;
}

// Mikó et al. Eq. 4 and 7 (process/cusp.hpp), angles in degrees.
double cusp_height_mm(double diameter_mm, double stepover_mm, double inclination_deg, double direction_deg) {
  constexpr double rad = std::numbers::pi / 180;
  return process::cusp_height_mm(diameter_mm, stepover_mm,
                                 process::cusp_alpha3_rad(direction_deg * rad, inclination_deg * rad));
}

}  // namespace

void bind_physics(py::module_& m) {
  m.def("compliance", &compliance, py::arg("tool"), py::arg("tool_file") = py::none(), py::arg("machine") = py::none(),
        py::arg("heights_mm") = py::none(), py::arg("tool_only") = false, py::arg("method") = "beam",
        py::arg("mesh_mm") = 0.0);
  m.def(
      "forces",
      [](const std::string& tool, const py::object& tool_file, const py::object& material,
         const py::object& material_file, std::optional<double> kt, std::optional<double> kr, std::optional<double> ka,
         std::optional<double> kte, std::optional<double> kre, std::optional<double> kae, double ae_mm, double ap_mm,
         double fz_mm, const std::string& milling, int steps, double dz_mm) {
        job::MaterialSettings mat{
            opt_path("material", material), opt_path("material_file", material_file), kt, kr, ka, kte, kre, kae};
        return forces(tool, tool_file, mat, ae_mm, ap_mm, fz_mm, milling, steps, dz_mm);
      },
      py::kw_only(), py::arg("tool"), py::arg("tool_file") = py::none(), py::arg("material") = py::none(),
      py::arg("material_file") = py::none(), py::arg("kt_N_per_mm2") = py::none(), py::arg("kr_N_per_mm2") = py::none(),
      py::arg("ka_N_per_mm2") = py::none(), py::arg("kte_N_per_mm") = py::none(), py::arg("kre_N_per_mm") = py::none(),
      py::arg("kae_N_per_mm") = py::none(), py::arg("ae_mm"), py::arg("ap_mm"), py::arg("fz_mm"),
      py::arg("milling") = "down", py::arg("steps") = 360, py::arg("dz_mm") = 0.05);
  m.def(
      "stability",
      [](const std::string& tool, const py::object& tool_file, const py::object& material, const py::object& material_file,
         const py::object& machine, const py::object& frf, bool tool_only, double ae_mm, std::optional<double> ap_mm,
         const std::string& milling, std::optional<std::pair<double, double>> rpm, int points) {
        job::StabilitySettings s;
        s.tool = tool;
        s.tool_file = opt_path("tool_file", tool_file);
        s.material = {opt_path("material", material), opt_path("material_file", material_file), {}, {}, {}, {}, {}, {}};
        s.machine = opt_path("machine", machine);
        s.frf = opt_path("frf", frf);
        s.tool_only = tool_only;
        s.ae_mm = ae_mm;
        s.ap_mm = ap_mm;
        s.points = points;
        return stability(s, milling, rpm);
      },
      py::kw_only(), py::arg("tool"), py::arg("tool_file") = py::none(), py::arg("material") = py::none(),
      py::arg("material_file") = py::none(), py::arg("machine") = py::none(), py::arg("frf") = py::none(),
      py::arg("tool_only") = false, py::arg("ae_mm"), py::arg("ap_mm") = py::none(), py::arg("milling") = "down",
      py::arg("rpm") = py::none(), py::arg("points") = 1000);
  m.def("cusp_height_mm", py::vectorize(&cusp_height_mm), py::arg("diameter_mm"), py::arg("stepover_mm"),
        py::arg("inclination_deg") = 0.0, py::arg("direction_deg") = 0.0);
}

}  // namespace deflex::python
