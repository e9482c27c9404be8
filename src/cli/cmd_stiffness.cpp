// deflex stiffness: the compliance C(h) of a tool in its holder on a machine,
// or (--part) the workpiece's own compliance at points of its surface.
#include <boost/program_options.hpp>
#include <cstdio>
#include <ostream>

#include "common.hpp"
#include "deflex/cli/command.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/job/physics.hpp"
#include "deflex/job/workpiece.hpp"
#include "deflex/report/compliance.hpp"
#include "deflex/report/workpiece.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::cli {
namespace {

namespace po = boost::program_options;
namespace st = deflex::stiffness;

const char* kUsage =
    "deflex stiffness --tool-file F --tool ID [--machine M] [--method beam|solid]\n"
    "                        [--at H ...] [--tool-only] [--format text|json]\n"
    "       deflex stiffness --part P --fixture box:X0,Y0,Z0,X1,Y1,Z1 [--fixture ...]\n"
    "                        --at X,Y,Z [--at ...] --material M [--material-file F]\n"
    "                        [--mesh-mm S] [--format text|json]";

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
    "JSON: {\"compliance\": [{\"height_mm\": H, \"matrix_mm_per_N\": [[..],[..],[..]]}]}\n"
    "\n"
    "With --part: the workpiece's own compliance, mm/N, at each --at X,Y,Z (mm,\n"
    "work frame, within 1 mm of the part's surface): the displacement of the\n"
    "surface there under a unit force in x, y and z spread over a small patch (a\n"
    "quarter of the thinnest wall, or of an element, in radius). The part (STEP,\n"
    "IGES or a closed STL, mm) is meshed with quadratic tetrahedra by gmsh\n"
    "(--mesh-mm, default half the thinnest wall) and solved as a linear-elastic\n"
    "body. --fixture is where the part is held: every mesh node on its surface\n"
    "inside the box is fixed, as by a rigid vice jaw or a bolted face (give a box\n"
    "around the faces the jaws grip or the face that sits on the table; repeat for\n"
    "several). --material names an entry of the material library with elastic:\n"
    "{E_MPa, poisson}. The text gives each matrix (rows: displacement; columns:\n"
    "force) and its principal compliances; a thin wall's bending is the largest.\n"
    "Add the tool's compliance to compare: along the surface normal the two add.\n"
    "\n"
    "JSON: {\"part\", \"material\", \"E_MPa\", \"poisson\", \"mesh\": {\"nodes\", \"elements\",\n"
    "\"dofs\", ...}, \"points\": [{\"point_mm\", \"surface_mm\", \"compliance_mm_per_N\":\n"
    "[[..],[..],[..]], \"principal\": [...]}]}\n";

std::string describe(const st::Tool& t) {
  char b[200];
  std::snprintf(b, sizeof b, "%s: %s end mill D %g mm, %d flutes, stick-out %g mm, E %g MPa, nu %g",
                t.id.c_str(), stock::to_string(t.type), t.diameter_mm, t.flutes, t.stickout_mm,
                t.material.E_MPa, t.material.poisson);
  return b;
}

// "X,Y,Z" of --at with --part.
Eigen::Vector3d parse_point(const std::string& text) {
  const std::vector<double> v = numbers_of(text, "--at");
  if (v.size() != 3)
    throw Error(ErrorKind::settings, "--at with --part takes a point X,Y,Z in mm, not '" + text + "'");
  return {v[0], v[1], v[2]};
}

double parse_height(const std::string& text) {
  const std::vector<double> v = numbers_of(text, "--at");
  if (v.size() != 1) throw Error(ErrorKind::settings, "--at takes heights above the tip in mm, not '" + text + "'");
  return v[0];
}

int part_compliance(const std::vector<std::string>& at, const std::vector<std::string>& fixtures,
                    const std::string& material, const std::string& material_file, double mesh_mm,
                    const std::string& part, const std::string& format, Io& io) {
  job::WorkpieceSettings ws;
  ws.part = part;
  ws.fixtures = fixtures;
  for (const auto& a : at) ws.points_mm.push_back(parse_point(a));
  ws.material = material;
  ws.material_file = material_file;
  ws.mesh_mm = mesh_mm;
  if (io.err_is_terminal) io.err << "deflex stiffness: meshing and solving the workpiece " << part << "...\n";
  const job::WorkpieceResult r = job::workpiece_compliance(ws);
  const report::WorkpieceTitle t{r.part, fixtures, r.material, r.elastic};
  io.out << (format == "json" ? report::workpiece_json(t, r.mesh, r.points) : report::workpiece_text(t, r.mesh, r.points));
  return 0;
}

}  // namespace

int cmd_stiffness(const std::vector<std::string>& args, Io& io) {
  std::string tool_file, tool_id, machine, method = "beam", format = "text";
  std::string part, material, material_file;
  std::vector<std::string> at, fixtures;
  double mesh_mm = 0;
  po::options_description d("options");
  d.add_options()
      ("tool-file", po::value(&tool_file)->value_name("F"), "tool library (YAML)")
      ("tool", po::value(&tool_id)->value_name("ID"), "tool in the library")
      ("machine", po::value(&machine)->value_name("M"), "machine profile file or name")
      ("method", po::value(&method)->value_name("beam|solid"), "model (default beam)")
      ("at", po::value(&at)->multitoken()->composing()->value_name("H"),
       "load heights above the tip, mm (default: 7 along the flutes); with --part, points X,Y,Z on the part, mm")
      ("tool-only", "clamp the tool rigidly at the holder face")
      ("format", po::value(&format)->value_name("text|json"), "output format (default text)")
      ("mesh-mm", po::value(&mesh_mm)->value_name("S"), "solid: element size, mm (default D_flute/5; --part: half the thinnest wall)")
      ("no-cache", "solid: neither read nor write the cache")
      ("part", po::value(&part)->value_name("P"), "the workpiece's compliance: its model (STEP, IGES or a closed STL)")
      ("fixture", po::value(&fixtures)->composing()->value_name("box:X0,Y0,Z0,X1,Y1,Z1"),
       "--part: where it is held (mm; surface inside is fixed); repeatable")
      ("material", po::value(&material)->value_name("M"), "--part: the work material (with elastic: in the library)")
      ("material-file", po::value(&material_file)->value_name("F"), "--part: material library (YAML)")
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
  if (format != "text" && format != "json")
    throw Error(ErrorKind::settings, "stiffness: --format must be text or json, not '" + format + "'");
  if (!part.empty()) {
    if (!tool_file.empty() || !tool_id.empty() || !machine.empty() || vm.count("method") || vm.count("tool-only"))
      throw Error(ErrorKind::settings, "stiffness: --part is the workpiece's compliance: no --tool-file, --tool, "
                                       "--machine, --method or --tool-only with it");
    return part_compliance(at, fixtures, material, material_file, mesh_mm, part, format, io);
  }
  if (!fixtures.empty() || !material.empty() || !material_file.empty())
    throw Error(ErrorKind::settings, "stiffness: --fixture, --material and --material-file need --part");
  if (tool_file.empty() || tool_id.empty())
    throw Error(ErrorKind::settings, "stiffness: --tool-file and --tool are required (or --part for the workpiece)");

  job::ComplianceSettings cs;
  cs.tool = tool_id;
  cs.tool_file = tool_file;
  cs.machine = vm.count("tool-only") ? "" : machine;
  for (const auto& a : at) cs.heights_mm.push_back(parse_height(a));
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
