// job::compliance() (stiffness.hpp).
#include "deflex/job/stiffness.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/job/setup.hpp"
#include "deflex/profile/search.hpp"
#include "deflex/stiffness/beam.hpp"
#include "deflex/stiffness/machine.hpp"

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

}  // namespace deflex::job
