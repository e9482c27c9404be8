// deflex forces: cutting forces over one spindle revolution for one engagement
// condition; deflex calibrate: cutting/edge coefficients from slot tests
// (job::forces, job::calibrate); here the options and the printing.
#include <cmath>
#include <cstdio>
#include <ostream>
#include <set>
#include <sstream>

#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/job/physics.hpp"
#include "deflex/profile/spindle.hpp"
#include "deflex/report/json.hpp"

namespace deflex::cli {
namespace {

namespace fo = deflex::force;

const char* kForcesHelp =
    "Cutting forces on the tool over one spindle revolution, for a straight cut\n"
    "into a wall: mechanistic model with cutting and edge coefficients\n"
    "(Altintas 2012 ch. 2; Lee & Altintas 1996 for the ball end; Engin & Altintas\n"
    "2001 for the bull nose), the helical flutes cut into axial slices.\n"
    "\n"
    "Conventions:\n"
    "  feed along +X; spindle clockwise seen from above (M3); Z up the spindle.\n"
    "  Immersion angle measured clockwise from +Y (seen from above); the edge\n"
    "  point of radius r sits at r (sin a, cos a). Output angle_deg is the rotation\n"
    "  of tooth 1's tip; the other teeth follow at 360/flutes, each edge point\n"
    "  lagging z tan(helix) / R behind the tip (constant-lead flutes).\n"
    "  --up: up-milling, cutting on the +Y side, a_e measured from +Y (entry at 0).\n"
    "  --down: down-milling, cutting on the -Y side, a_e from -Y (exit at 180).\n"
    "  a_e >= D is a full slot. Forces act on the tool, in machine axes, N.\n"
    "  Units: lengths mm; cutting coefficients K_tc/K_rc/K_ac (--kt --kr --ka)\n"
    "  in N/mm^2, edge coefficients (--kte --kre --kae) in N/mm. A positive K_ac\n"
    "  pulls a right-hand helix cutter down (-Z).\n"
    "  Coefficients come from --material (samples/materials.yaml, or\n"
    "  --material-file, e.g. written by `deflex calibrate`) or from --kt/--kr/--ka.\n"
    "\n"
    "Output:\n"
    "  --format csv: one row per angular step, columns angle_deg,Fx_N,Fy_N,Fz_N;\n"
    "    each row is the mean over its angular step.\n"
    "  --format json: {\"mean_N\": [x,y,z], \"peak_abs_N\": [x,y,z], \"mean_torque_Nm\": M, \"shape_code\": ...}\n"
    "    mean_torque_Nm: the torque on the spindle, sum of r dF_t, mean over the revolution;\n"
    "    with --rpm N also \"power_kW\": the cutting power M 2 pi N / 60.\n"
    "    shape_code (flat end mills, --down only): the F_y force-shape code of\n"
    "    Morelli et al. 2021, e.g. IIML (type I/II/III of one flute, then the overlap\n"
    "    L/M/H/m/h of each following flute in the cut). Their classification is\n"
    "    for down-milling; it is left out for up-milling.\n"
    "\n"
    "Example: deflex forces --tool-file samples/tools.yaml --tool T1 \\\n"
    "           --material Al6082-T4 --ae 2.5 --ap 12 --fz 0.1 --down --format json\n";

const char* kCalibrateHelp =
    "Fits the six coefficients of the mechanistic force model, K_tc, K_rc, K_ac\n"
    "(N/mm^2) and K_te, K_re, K_ae (N/mm), to the mean forces of full-slot tests\n"
    "with a flat end mill at several feeds per tooth, by linear regression of\n"
    "F/(flutes a_p) against f_z (Altintas 2012 ch. 2). Prints the coefficients, the\n"
    "fit and the residual of every test, then a material entry (YAML) for\n"
    "--material-file, written to -o FILE when given.\n"
    "\n"
    "CSV: '#' lines are comments; '# key: value' lines before the header set\n"
    "defaults (diameter_mm, flutes, ap_mm, helix_deg, material, tool, forces_on:\n"
    "tool|workpiece). Header row with columns fz_mm,Fx_N,Fy_N,Fz_N and optionally\n"
    "ap_mm, flutes, diameter_mm; then one test per row. Forces: means over whole\n"
    "revolutions, machine axes (feed +X, spindle M3, Z up), acting on the tool\n"
    "(forces_on: workpiece negates them). See samples/calibration/README.md.\n";

std::string fixed(double v, int decimals) {
  if (std::abs(v) < 0.5 * std::pow(10.0, -decimals)) v = 0;  // no "-0.000"
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}


struct ForcesArgs {
  std::string tool_file, tool, format = "csv";
  MaterialOptions mat;
  double ae = 0, ap = 0, fz = 0, dz = 0.05;
  bool up = false, down = false, help = false;
  int steps = 360;
  double rpm = 0;
};

report::Json json_vec(const fo::Vec3& v) { return report::xyz(v.x(), v.y(), v.z(), 3); }

}  // namespace

int cmd_forces(const std::vector<std::string>& args, Io& io) {
  ForcesArgs a;
  po::options_description desc("options");
  desc.add_options()
      ("help,h", po::bool_switch(&a.help), "show this help")
      ("tool-file", po::value(&a.tool_file), "tool library (YAML, tools: {ID: {...}})")
      ("tool", po::value(&a.tool), "tool ID in the library")
      ;
  add_material_options(desc, a.mat);
  desc.add_options()
      ("ae", po::value(&a.ae), "radial depth of cut a_e, mm, from the cutting side (>= D: slot)")
      ("ap", po::value(&a.ap), "axial depth of cut a_p above the tool tip, mm")
      ("fz", po::value(&a.fz), "feed per tooth f_z, mm")
      ("up", po::bool_switch(&a.up), "up-milling (cuts on the +Y side)")
      ("down", po::bool_switch(&a.down), "down-milling (cuts on the -Y side)")
      ("steps", po::value(&a.steps), "angular steps per revolution (default 360)")
      ("dz", po::value(&a.dz), "axial slice height, mm (default 0.05; at least 20 slices)")
      ("rpm", po::value(&a.rpm), "spindle speed, rpm: the json gives the cutting power at it")
      ("format", po::value(&a.format), "csv (default) or json");
  const po::variables_map vm = parse(args, desc, po::positional_options_description());
  refuse_output_onto_input({a.tool_file, a.mat.material_file});
  if (a.help) {
    print_help(io.out,
               "deflex forces --tool-file F --tool ID (--material M [--material-file F] | --kt K --kr K "
               "--ka K [--kte K --kre K --kae K]) --ae A --ap P --fz F (--down | --up) [--steps N] "
               "[--format csv|json]",
               kForcesHelp, desc);
    return 0;
  }
  for (const char* req : {"tool-file", "tool", "ae", "ap", "fz"})
    if (!vm.count(req)) throw Error(ErrorKind::settings, std::string("forces: --") + req + " is required (see --help)");
  if (a.up == a.down) throw Error(ErrorKind::settings, "forces: give exactly one of --up and --down");
  if (!(a.rpm >= 0) || !std::isfinite(a.rpm)) throw Error(ErrorKind::settings, "forces: --rpm must be a speed >= 0");
  if (a.format != "csv" && a.format != "json")
    throw Error(ErrorKind::settings, "forces: --format must be csv or json");
  job::ForceSettings fs;
  fs.tool = a.tool;
  fs.tool_file = a.tool_file;
  fs.material = a.mat;
  fs.ae_mm = a.ae, fs.ap_mm = a.ap, fs.fz_mm = a.fz, fs.dz_mm = a.dz;
  fs.up_milling = a.up;
  fs.steps = a.steps;
  const job::ForceResult r = job::forces(fs);
  const std::vector<fo::Vec3>& F = r.force_N;
  if (a.format == "csv") {
    io.out << "angle_deg,Fx_N,Fy_N,Fz_N\n";
    for (int j = 0; j < a.steps; ++j)
      io.out << significant_digits(360.0 * j / a.steps) << "," << fixed(F[j].x(), 3) << "," << fixed(F[j].y(), 3)
             << "," << fixed(F[j].z(), 3) << "\n";
    return 0;
  }
  report::Json j{{"mean_N", json_vec(r.summary.mean_N)}, {"peak_abs_N", json_vec(r.summary.peak_abs_N)},
                 {"mean_torque_Nm", report::fixed(r.mean_torque_Nm, 4)}};
  if (a.rpm > 0) j["power_kW"] = report::fixed(profile::power_from_torque_kW(r.mean_torque_Nm, a.rpm), 4);
  if (r.shape_code) j["shape_code"] = *r.shape_code;
  io.out << report::line(j);
  return 0;
}

namespace {

std::string calibration_report(const fo::SlotTestData& d, const fo::SlotCalibration& c) {
  std::ostringstream o;
  std::set<double> depths;
  for (const auto& t : d.tests) depths.insert(t.ap_mm);
  o << "slot tests: " << d.file << " (" << d.tests.size() << " tests, " << depths.size()
    << (depths.size() == 1 ? " depth" : " depths") << ")\n\n"
    << "coefficients (Altintas 2012 ch. 2; forces on the tool, feed +X, M3):\n"
    << "  K_tc " << fixed(c.k.Ktc_N_per_mm2, 2) << " N/mm^2    K_te " << fixed(c.k.Kte_N_per_mm, 3) << " N/mm\n"
    << "  K_rc " << fixed(c.k.Krc_N_per_mm2, 2) << " N/mm^2    K_re " << fixed(c.k.Kre_N_per_mm, 3) << " N/mm\n"
    << "  K_ac " << fixed(c.k.Kac_N_per_mm2, 2) << " N/mm^2    K_ae " << fixed(c.k.Kae_N_per_mm, 3) << " N/mm\n\n"
    << "fit of F / (flutes a_p) = slope f_z + intercept:\n";
  const char* axis[] = {"Fx", "Fy", "Fz"};
  for (int a = 0; a < 3; ++a)
    o << "  " << axis[a] << ": slope " << fixed(c.fit[a].slope, 3) << " N/mm^2, intercept "
      << fixed(c.fit[a].intercept, 4) << " N/mm, R^2 " << fixed(c.fit[a].r2, 6) << "\n";
  o << "\nresiduals (measured - fitted), N:\n"
    << "  line    fz_mm   ap_mm      Fx_N      Fy_N      Fz_N     dFx_N     dFy_N     dFz_N\n";
  for (std::size_t i = 0; i < d.tests.size(); ++i) {
    const auto& t = d.tests[i];
    char b[256];
    std::snprintf(b, sizeof b, "  %4d %8.4f %7.3f %9.2f %9.2f %9.2f %9.3f %9.3f %9.3f\n", t.line, t.fz_mm,
                  t.ap_mm, t.mean_N.x(), t.mean_N.y(), t.mean_N.z(), c.residual_N[i].x(),
                  c.residual_N[i].y(), c.residual_N[i].z());
    o << b;
  }
  o << "  rms residual: Fx " << fixed(c.rms_residual_N.x(), 3) << ", Fy " << fixed(c.rms_residual_N.y(), 3)
    << ", Fz " << fixed(c.rms_residual_N.z(), 3) << " N\n";
  return o.str();
}

}  // namespace

int cmd_calibrate(const std::vector<std::string>& args, Io& io) {
  std::string file, name, output;
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")
      ("name", po::value(&name), "material name of the entry (default: '# material:' of the CSV, else the file name)")
      ("output,o", po::value(&output), "write the material entry (YAML) to this file");
  po::options_description hidden;
  hidden.add_options()("file", po::value(&file));
  po::options_description all;
  all.add(desc).add(hidden);
  po::positional_options_description pos;
  pos.add("file", 1);
  parse(args, all, pos);
  refuse_output_onto_input({file});
  if (help) {
    print_help(io.out, "deflex calibrate FILE.csv [--name NAME] [-o OUT.yaml]", kCalibrateHelp, desc);
    return 0;
  }
  if (file.empty()) throw Error(ErrorKind::settings, "calibrate: missing FILE.csv (see --help)");

  const job::CalibrationResult c = job::calibrate({file, name, output});
  io.out << calibration_report(c.tests, c.fit);
  if (output.empty()) io.out << "\nmaterial entry:\n" << c.yaml;
  else io.out << "\nmaterial entry '" << c.entry.name << "' written to " << output << "\n";
  return 0;
}

}  // namespace deflex::cli
