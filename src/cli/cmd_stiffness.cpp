// deflex stiffness: the compliance C(h) of a tool in its holder on a machine.
#include <boost/program_options.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ostream>

#include "common.hpp"
#include "deflex/cli/command.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/profile/search.hpp"
#include "deflex/report/compliance.hpp"
#include "deflex/stiffness/beam.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/solid.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::cli {
namespace {

namespace po = boost::program_options;
namespace st = deflex::stiffness;

const char* kUsage =
    "deflex stiffness --tool-file F --tool ID [--machine M] [--method beam|solid]\n"
    "                        [--at H ...] [--tool-only] [--format text|json]";

const char* kHelp =
    "The compliance C(h) of a tool, mm/N: the 3x3 matrix (rows displacement x, y,\n"
    "z; columns force Fx, Fy, Fz; machine axes) for a load on the tool axis at\n"
    "height h above the tip, along the flutes.\n"
    "\n"
    "  beam   Timoshenko beam elements of the stepped tool (fluted part as a\n"
    "         cylinder of flute_diameter_ratio x D), the holder and the joints.\n"
    "  solid  the tool as an OpenCASCADE solid (or its step_file), quadratic\n"
    "         tetrahedra by gmsh, linear-elastic FEM; the load spread over a patch\n"
    "         of a quarter of the fluted radius. Cached by geometry in\n"
    "         $DEFLEX_CACHE_DIR, $XDG_CACHE_HOME/deflex or ~/.cache/deflex.\n"
    "\n"
    "--machine takes a profile file or a name in samples/machines/ (its holder:\n"
    "and stiffness: sections: holder body, tool_clamp and spindle springs,\n"
    "measured structure compliance, all in series). Without it, or with\n"
    "--tool-only, the tool is clamped rigidly at the holder face.\n"
    "\n"
    "JSON: {\"compliance\": [{\"height_mm\": H, \"matrix_mm_per_N\": [[..],[..],[..]]}]}\n";

std::string resolve_machine(const std::string& m) {
  if (m.find('/') != std::string::npos || m.ends_with(".yaml") || std::filesystem::exists(m)) return m;
  const std::string f = profile::find_machine(m);
  return f.empty() ? m : f;
}

// Heights to print: the user's, checked against the flutes, or seven evenly spaced.
std::vector<double> heights(const std::vector<double>& at, const st::Tool& t) {
  const double top = std::min(t.flute_length_mm, t.stickout_mm);
  for (double h : at)
    if (!(h >= 0 && h <= top + 1e-9)) {
      char b[160];
      std::snprintf(b, sizeof b, "--at %g: the load height must lie along the flutes of %s (0 to %g mm)",
                    h, t.id.c_str(), top);
      throw Error(ErrorKind::settings, b);
    }
  if (!at.empty()) return at;
  std::vector<double> h;
  for (int i = 0; i <= 6; ++i) h.push_back(std::round(top * i / 6 * 1000) / 1000);
  return h;
}

std::string describe(const st::Tool& t) {
  char b[200];
  std::snprintf(b, sizeof b, "%s: %s end mill D %g mm, %d flutes, stick-out %g mm, E %g MPa, nu %g",
                t.id.c_str(), stock::to_string(t.type), t.diameter_mm, t.flutes, t.stickout_mm,
                t.material.E_MPa, t.material.poisson);
  return b;
}

}  // namespace

int cmd_stiffness(const std::vector<std::string>& args, Io& io) {
  std::string tool_file, tool_id, machine, method = "beam", format = "text";
  std::vector<double> at;
  double mesh_mm = 0;
  po::options_description d("options");
  d.add_options()
      ("tool-file", po::value(&tool_file)->value_name("F"), "tool library (YAML)")
      ("tool", po::value(&tool_id)->value_name("ID"), "tool in the library")
      ("machine", po::value(&machine)->value_name("M"), "machine profile file or name")
      ("method", po::value(&method)->value_name("beam|solid"), "model (default beam)")
      ("at", po::value(&at)->multitoken()->composing()->value_name("H"),
       "load heights above the tip, mm (default: 7 along the flutes)")
      ("tool-only", "clamp the tool rigidly at the holder face")
      ("format", po::value(&format)->value_name("text|json"), "output format (default text)")
      ("mesh-mm", po::value(&mesh_mm)->value_name("S"), "solid: element size, mm (default D_flute/5)")
      ("no-cache", "solid: neither read nor write the cache")
      ("help,h", "this help");
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(d).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw Error(ErrorKind::settings, std::string("stiffness: ") + e.what());
  }
  refuse_output_onto_input({tool_file});
  if (vm.count("help")) {
    print_help(io.out, kUsage, kHelp, d);
    return 0;
  }
  if (tool_file.empty() || tool_id.empty())
    throw Error(ErrorKind::settings, "stiffness: --tool-file and --tool are required");
  if (method != "beam" && method != "solid")
    throw Error(ErrorKind::settings, "stiffness: --method must be beam or solid, not '" + method + "'");
  if (format != "text" && format != "json")
    throw Error(ErrorKind::settings, "stiffness: --format must be text or json, not '" + format + "'");
  if (mesh_mm < 0) throw Error(ErrorKind::settings, "stiffness: --mesh-mm must be > 0");

  const st::ToolLibrary lib = st::load_tool_library(tool_file);
  const st::Tool& tool = st::find_tool(lib, tool_id);
  const bool tool_only = vm.count("tool-only") || machine.empty();
  st::MachineStiffness m;
  if (!tool_only) m = st::load_machine_stiffness(resolve_machine(machine));
  const std::vector<double> hs = heights(at, tool);

  st::ComplianceTable table;
  std::string note;
  if (method == "beam") {
    table = st::beam_compliance(tool, m, tool_only);
  } else {
    st::SolidOptions o;
    o.mesh_size_mm = mesh_mm;
    if (vm.count("no-cache")) o.cache_dir = "";
    if (io.err_is_terminal) io.err << "deflex stiffness: solving the solid model of " << tool.id << "...\n";
    st::SolidInfo info;
    table = st::solid_compliance(tool, m, tool_only, o, &info);
    char b[200];
    if (info.from_cache)
      std::snprintf(b, sizeof b, "solid model: from cache %s\n", info.cache_file.c_str());
    else
      std::snprintf(b, sizeof b, "solid model: %zu nodes, %zu quadratic tets, %zu dofs, %.1f s\n",
                    info.nodes, info.elements, info.dofs, info.seconds);
    note = b;
  }
  const auto rows = st::sample(table, hs);
  if (format == "json") {
    io.out << report::compliance_json(rows);
    return 0;
  }
  std::string title = describe(tool) + "\nmethod: " + method + "; " +
                      (tool_only ? std::string("tool only, clamped rigidly at the holder face")
                                 : "tool in holder on machine " + resolve_machine(machine)) +
                      "\n" + note;
  io.out << report::compliance_text(rows, title);
  return 0;
}

}  // namespace deflex::cli
