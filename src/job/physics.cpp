// job::compliance(), job::forces() and job::calibrate() (physics.hpp).
#include "deflex/job/physics.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/force/morelli.hpp"
#include "deflex/force/tool.hpp"
#include "deflex/job/setup.hpp"
#include "deflex/profile/search.hpp"
#include "deflex/stiffness/beam.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::job {
namespace {

namespace st = deflex::stiffness;

// A profile by file, or by name in the machine search path.
std::string machine_file(const std::string& m) {
  if (m.find('/') != std::string::npos || m.ends_with(".yaml") || std::filesystem::exists(m)) return m;
  const std::string f = profile::find_machine(m);
  return f.empty() ? m : f;
}

// The heights given, each along the flutes, or seven evenly spaced from the tip.
std::vector<double> heights(const std::vector<double>& at, const st::Tool& t) {
  const double top = std::min(t.flute_length_mm, t.stickout_mm);
  for (double h : at)
    if (!(h >= 0 && h <= top + 1e-9)) {
      char b[160];
      std::snprintf(b, sizeof b, "the load height %g mm is not along the flutes of %s (0 to %g mm)", h, t.id.c_str(), top);
      throw Error(ErrorKind::settings, b);
    }
  if (!at.empty()) return at;
  std::vector<double> h;
  for (int i = 0; i <= 6; ++i) h.push_back(std::round(top * i / 6 * 1000) / 1000);
  return h;
}

void require_positive(const char* what, double v, bool allow_zero = false) {
  if (!std::isfinite(v) || v < 0 || (!allow_zero && v == 0))
    throw Error(ErrorKind::settings, std::string(what) + " must be " + (allow_zero ? ">= 0" : "> 0"));
}

std::optional<std::string> shape_code(const force::Cutter& c, const force::Coefficients& k, double ae,
                                      double ap, bool down) {
  if (c.type != stock::EndShape::flat || !down) return std::nullopt;
  force::MorelliInput in;
  in.diameter_mm = c.diameter_mm;
  in.helix_deg = c.helix_deg;
  in.flutes = c.flutes;
  in.ar_mm = std::min(ae, c.diameter_mm);
  in.ap_mm = ap;
  in.Ktc_N_per_mm2 = k.Ktc_N_per_mm2;
  in.Krc_N_per_mm2 = k.Krc_N_per_mm2;
  try {
    return force::morelli_shape_code(in);
  } catch (const Error&) {
    return std::nullopt;  // outside the classification (straight flutes, K_rc <= 0)
  }
}

}  // namespace

ComplianceResult compliance(const ComplianceSettings& s) {
  if (s.method != "beam" && s.method != "solid")
    throw Error(ErrorKind::settings, "the stiffness method must be beam or solid, not '" + s.method + "'");
  if (!(s.mesh_mm >= 0)) throw Error(ErrorKind::settings, "the solid model's mesh size must be >= 0 mm (0: a fifth of the fluted diameter)");
  const std::string lib_file =
      !s.tool_file.empty() ? s.tool_file : tool_library_path("", profile::load_config());
  const st::ToolLibrary lib = st::load_tool_library(lib_file);
  ComplianceResult r;
  r.tool = st::find_tool(lib, s.tool);
  r.tool_only = s.tool_only || s.machine.empty();
  st::MachineStiffness m;
  if (!r.tool_only) {
    r.machine_file = machine_file(s.machine);
    m = st::load_machine_stiffness(r.machine_file);
  }
  const std::vector<double> hs = heights(s.heights_mm, r.tool);
  st::ComplianceTable table;
  if (s.method == "beam") {
    table = st::beam_compliance(r.tool, m, r.tool_only);
  } else {
    st::SolidOptions o;
    o.mesh_size_mm = s.mesh_mm;
    if (!s.cache) o.cache_dir = "";
    r.solid.emplace();
    table = st::solid_compliance(r.tool, m, r.tool_only, o, &*r.solid);
  }
  r.rows = st::sample(table, hs);
  return r;
}

ForceResult forces(const ForceSettings& s) {
  require_positive("the radial depth of cut a_e", s.ae_mm);
  require_positive("the axial depth of cut a_p", s.ap_mm);
  require_positive("the feed per tooth f_z", s.fz_mm, true);
  require_positive("the slice height", s.dz_mm);
  if (s.steps < 4 || s.steps > 1000000) throw Error(ErrorKind::settings, "the steps per revolution must be 4 to 1000000");
  const profile::Config cfg = profile::load_config();
  MaterialSettings mat = s.material;
  // A material by name (given, or the config's): its library, as a job's (open.cpp).
  if (!mat.material.empty() || !mat.kt) mat.material_file = material_library_path(mat.material_file, cfg);
  const force::Coefficients k = coefficients_of(mat, config_string(cfg, "material"));
  const std::string lib = !s.tool_file.empty() ? s.tool_file : tool_library_path("", cfg);
  const force::Cutter cutter = force::cutter_of(st::find_tool(st::load_tool_library(lib), s.tool));
  if (s.ap_mm > cutter.flute_length_mm) {
    char b[200];
    std::snprintf(b, sizeof b, "the axial depth of cut a_p %.10g mm exceeds the flute length of tool %s (%.10g mm)",
                  s.ap_mm, s.tool.c_str(), cutter.flute_length_mm);
    throw Error(ErrorKind::settings, b);
  }
  // At least 20 axial slices over a_p.
  const force::CutterSlices slices = force::make_slices(cutter, std::min(s.dz_mm, s.ap_mm / 20), s.ap_mm);
  force::Engagement eng;
  force::simple_engagement(slices, s.ae_mm, s.ap_mm, s.up_milling ? force::MillingMode::up : force::MillingMode::down,
                           eng);
  ForceResult r;
  r.force_N = force::revolution_forces(slices, k, s.fz_mm, eng, s.steps);
  r.summary = force::summarize(r.force_N);
  r.mean_torque_Nm = force::mean_torque(slices, k, s.fz_mm, eng).total_Nm();
  r.shape_code = shape_code(cutter, k, s.ae_mm, s.ap_mm, !s.up_milling);
  return r;
}

CalibrationResult calibrate(const CalibrationSettings& s) {
  if (!s.output.empty()) writer::check_output_path(s.output, s.file);
  CalibrationResult r;
  r.tests = force::load_slot_tests(s.file);
  r.fit = force::calibrate_slot_tests(r.tests);
  force::MaterialEntry& m = r.entry;
  const std::filesystem::path file(s.file);
  m.name = !s.name.empty() ? s.name : !r.tests.material.empty() ? r.tests.material : file.stem().string();
  m.form = force::ModelForm::mechanistic;
  m.k = r.fit.k;
  m.source = "deflex calibrate " + file.filename().string() + ": " + std::to_string(r.tests.tests.size()) +
             " slot tests, linear regression (Altintas 2012 ch. 2)";
  double fmin_mm = r.tests.tests.front().fz_mm, fmax_mm = fmin_mm;
  for (const auto& t : r.tests.tests) fmin_mm = std::min(fmin_mm, t.fz_mm), fmax_mm = std::max(fmax_mm, t.fz_mm);
  m.conditions = (r.tests.tool.empty() ? std::string("flat end mill") : r.tests.tool) + "; full slots, f_z " +
                 significant_digits(fmin_mm) + " to " + significant_digits(fmax_mm) + " mm";
  r.yaml = force::to_yaml(m);
  if (!s.output.empty()) writer::write_file_atomically(s.output, s.file, [&](std::ostream& o) { o << r.yaml; });
  return r;
}

}  // namespace deflex::job
