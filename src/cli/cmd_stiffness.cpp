// deflex stiffness: the compliance C(h) of a tool in its holder on a machine.
#include <boost/program_options.hpp>
#include <cstdio>
#include <ostream>

#include "common.hpp"
#include "deflex/cli/command.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/job/physics.hpp"
#include "deflex/report/compliance.hpp"
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
  if (format != "text" && format != "json")
    throw Error(ErrorKind::settings, "stiffness: --format must be text or json, not '" + format + "'");

  job::ComplianceSettings cs;
  cs.tool = tool_id;
  cs.tool_file = tool_file;
  cs.machine = vm.count("tool-only") ? "" : machine;
  cs.heights_mm = at;
  cs.method = method;
  cs.mesh_mm = mesh_mm;
  cs.cache = !vm.count("no-cache");
  if (method == "solid" && io.err_is_terminal) io.err << "deflex stiffness: solving the solid model of " << tool_id << "...\n";
  const job::ComplianceResult r = job::compliance(cs);
  std::string note;
  if (r.solid) {
    const st::SolidInfo& info = *r.solid;
    char b[200];
    if (info.from_cache)
      std::snprintf(b, sizeof b, "solid model: from cache %s\n", info.cache_file.c_str());
    else
      std::snprintf(b, sizeof b, "solid model: %zu nodes, %zu quadratic tets, %zu dofs, %.1f s\n",
                    info.nodes, info.elements, info.dofs, info.seconds);
    note = b;
  }
  if (format == "json") {
    io.out << report::compliance_json(r.rows);
    return 0;
  }
  std::string title = describe(r.tool) + "\nmethod: " + method + "; " +
                      (r.tool_only ? std::string("tool only, clamped rigidly at the holder face")
                                   : "tool in holder on machine " + r.machine_file) +
                      "\n" + note;
  io.out << report::compliance_text(r.rows, title);
  return 0;
}

}  // namespace deflex::cli
