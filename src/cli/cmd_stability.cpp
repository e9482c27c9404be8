// deflex stability: the stability lobes (chatter) of a tool for one radial
// immersion (job::stability); here the options and the printing.
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <ostream>
#include <sstream>

#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/job/stability.hpp"
#include "deflex/report/json.hpp"
#include "deflex/report/lobes.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::cli {
namespace {

const char* kUsage =
    "deflex stability --tool-file F --tool T --material M (--machine M | --frf FRF.csv | --tool-only)\n"
    "                        --ae MM [--ap MM] [--up|--down] [--rpm MIN:MAX] [--points N]\n"
    "                        [--format text|csv|json] [--report DIR]";

const char* kHelp =
    "The milling stability limit (chatter): the largest axial depth of cut a_p\n"
    "that stays stable at each spindle speed, for one radial immersion - the\n"
    "zero-order (average tooth-passing) method of Altintas & Budak 1995, from\n"
    "the tool tip's frequency response in X and Y.\n"
    "\n"
    "The frequency response comes from:\n"
    "  --machine M  the beam model of tool + holder + joints + spindle springs\n"
    "               (the profile's holder: and stiffness:), its lowest four\n"
    "               bending modes, each with the profile's dynamics:\n"
    "               damping_ratio (default 0.03, the middle of the 0.02-0.05\n"
    "               tap tests give); the materials need density_kg_per_m3\n"
    "               (the presets have it). Default: the config's machine.\n"
    "  --tool-only  the same model with the tool clamped rigidly at the holder\n"
    "               face (no holder, no spindle).\n"
    "  --frf F.csv  a measured tool-tip FRF, as tap-test software exports it:\n"
    "               columns frequency_Hz, re_xx_mm_per_N, im_xx_mm_per_N,\n"
    "               re_yy_mm_per_N, im_yy_mm_per_N, optionally the cross terms\n"
    "               re_xy/im_xy/re_yx/im_yx_mm_per_N (docs/stability.md).\n"
    "               The machine structure's own modes are only in a measured FRF.\n"
    "\n"
    "The cut: --ae from the cutting side (>= D: a slot), --down (default) or\n"
    "--up; K_t = K_tc and K_r = K_rc / K_tc of the material (times the machine's\n"
    "force_scale). Without --ap the immersion is the straight wall's (the\n"
    "textbook cut); with --ap the engagement of that depth on the tool's own\n"
    "shape (a ball or a corner radius engages less near the tip), each slice at\n"
    "its own immersion and kappa - as `simulate` and `compensate` check every\n"
    "point of a program.\n"
    "\n"
    "Speeds: --rpm MIN:MAX, default the machine spindle's max_rpm / 50 to\n"
    "max_rpm (30000 without a spindle: section). Below the limit the cut is\n"
    "stable; the stable pockets are its local maxima.\n"
    "\n"
    "Output:\n"
    "  text (default): the modes, the cut, the absolute limit (stable at every\n"
    "    speed) and the best stable pockets.\n"
    "  csv: columns rpm,ap_limit_mm at --points + 1 speeds (default 1000 + 1).\n"
    "  json: {\"tool\", \"frf_source\", \"modes\": [{\"frequency_Hz\", \"damping_ratio\",\n"
    "    \"stiffness_N_per_mm\"}], \"cut\": {...}, \"ap_min_mm\", \"ap_min_chatter_Hz\",\n"
    "    \"pockets\": [[rpm, ap_limit_mm]], \"limit\": [[rpm, ap_limit_mm]]}.\n"
    "  --report DIR: stability.html (the lobes, opens offline), stability.csv and\n"
    "    stability.json.\n"
    "\n"
    "Known limit: the zero-order method misses the flip (period-doubling) lobes\n"
    "of very low radial immersion (a_e / D below about 0.1); there its limit may\n"
    "be optimistic near those speeds.\n"
    "\n"
    "Example: deflex stability --tool-file samples/tools.yaml --tool T1 \\\n"
    "           --material Al7075-T6 --machine mill3 --ae 3 --down\n";

struct Args {
  job::StabilitySettings s;
  std::string rpm, format = "text", report_dir;
  bool up = false, down = false, help = false;
};

constexpr double kDegPerRad = 180 / std::numbers::pi;

// "MIN:MAX" in rpm.
void parse_rpm(const std::string& text, job::StabilitySettings& s) {
  const auto colon = text.find(':');
  try {
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    std::size_t a = 0, b = 0;
    s.rpm_min = std::stod(text.substr(0, colon), &a);
    s.rpm_max = std::stod(text.substr(colon + 1), &b);
    if (a != colon || b != text.size() - colon - 1) throw std::invalid_argument("trailing text");
  } catch (const std::exception&) {
    throw Error(ErrorKind::settings, "stability: --rpm takes MIN:MAX in rpm, e.g. 2000:12000, not '" + text + "'");
  }
}

report::Json to_json(const job::StabilityResult& r) {
  report::Json modes = report::Json::array();
  for (const auto& m : r.modes)
    modes.push_back({{"frequency_Hz", report::fixed(m.frequency_Hz, 2)}, {"damping_ratio", m.damping_ratio},
                     {"stiffness_N_per_mm", report::significant(m.stiffness_N_per_mm, 6)}});
  auto pairs = [](const std::vector<std::pair<double, double>>& v) {
    report::Json a = report::Json::array();
    for (const auto& [rpm, ap] : v) a.push_back({report::fixed(rpm, 1), report::fixed(ap, 4)});
    return a;
  };
  return {{"tool", r.tool.id},
          {"frf_source", r.frf_source},
          {"modes", std::move(modes)},
          {"cut",
           {{"flutes", r.tool.flutes},
            {"Kt_N_per_mm2", report::fixed(r.Kt_N_per_mm2, 2)},
            {"Kr_ratio", report::fixed(r.Kr_ratio, 4)},
            {"immersion_deg", {report::fixed(r.immersion.start * kDegPerRad, 2), report::fixed(r.immersion.end * kDegPerRad, 2)}}}},
          {"rpm_range", {r.rpm_min, r.rpm_max}},
          {"ap_min_mm", report::fixed(r.lobes.ap_min_mm, 4)},
          {"ap_min_chatter_Hz", report::fixed(r.lobes.ap_min_chatter_Hz, 1)},
          {"pockets", pairs(r.pockets)},
          {"limit", pairs(r.limit)}};
}

std::string to_csv(const job::StabilityResult& r) {
  std::string o = "rpm,ap_limit_mm\n";
  for (const auto& [rpm, ap] : r.limit) o += fixed_decimals(rpm, 1) + "," + fixed_decimals(ap, 4) + "\n";
  return o;
}

std::string what_from(const job::StabilityResult& r, const job::StabilitySettings& s) {
  if (!s.frf.empty()) return "measured FRF " + r.frf_source;
  return r.frf_source + (r.machine_file.empty() ? "" : " (" + r.machine_file + ")");
}

std::string to_text(const job::StabilityResult& r, const job::StabilitySettings& s) {
  std::ostringstream o;
  o << "stability of " << r.tool.id << " (" << stock::to_string(r.tool.type) << " D " << r.tool.diameter_mm << " mm, "
    << r.tool.flutes << " flutes, stick-out " << r.tool.stickout_mm << " mm)\n"
    << "  tip response: " << what_from(r, s) << "\n";
  for (const auto& m : r.modes)
    o << "    mode " << fixed_decimals(m.frequency_Hz, 1) << " Hz, damping " << fixed_decimals(m.damping_ratio, 3)
      << (r.damping_given ? "" : " (default)") << ", stiffness at the tip " << fixed_decimals(m.stiffness_N_per_mm, 0) << " N/mm\n";
  o << "  cut: a_e " << s.ae_mm << " mm " << (s.up_milling ? "up" : "down") << "-milling, immersion "
    << fixed_decimals(r.immersion.start * kDegPerRad, 1) << "-" << fixed_decimals(r.immersion.end * kDegPerRad, 1) << " deg"
    << (s.ap_mm ? ", engagement of a_p " + fixed_decimals(*s.ap_mm, 3) + " mm on the tool's shape" : "") << "; K_t "
    << fixed_decimals(r.Kt_N_per_mm2, 0) << " N/mm^2, K_r " << fixed_decimals(r.Kr_ratio, 3) << " (" << r.material << ")\n"
    << "  absolute limit (stable at every speed): a_p " << fixed_decimals(r.lobes.ap_min_mm, 3) << " mm (chatter near "
    << fixed_decimals(r.lobes.ap_min_chatter_Hz, 0) << " Hz)\n"
    << "  stable pockets in " << fixed_decimals(r.rpm_min, 0) << "-" << fixed_decimals(r.rpm_max, 0) << " rpm (the limit's highest peaks):\n"
    << "       rpm   ap_limit_mm\n";
  for (std::size_t i = 0; i < r.pockets.size() && i < 8; ++i) {
    char b[80];
    std::snprintf(b, sizeof b, "    %6.0f   %11.3f\n", r.pockets[i].first, r.pockets[i].second);
    o << b;
  }
  if (r.pockets.empty()) o << "    none: the limit does not peak in this range\n";
  return o.str();
}

void write_report(const job::StabilityResult& r, const job::StabilitySettings& s, const std::string& dir,
                  const std::vector<std::string>& args) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error(ErrorKind::io, dir + ": error: cannot create the report folder: " + ec.message());
  const std::filesystem::path d(dir);
  report::LobesPage p;
  p.title = "deflex stability: " + r.tool.id + ", a_e " + fixed_decimals(s.ae_mm, 2) + " mm " + (s.up_milling ? "up" : "down") + "-milling";
  p.provenance = {{"tool", r.tool.id + " (" + stock::to_string(r.tool.type) + " D " + fixed_decimals(r.tool.diameter_mm, 2) + " mm, " +
                               std::to_string(r.tool.flutes) + " flutes)"},
                  {"tip response", what_from(r, s)},
                  {"material", r.material + ": K_t " + fixed_decimals(r.Kt_N_per_mm2, 0) + " N/mm², K_r " + fixed_decimals(r.Kr_ratio, 3)},
                  {"absolute limit", fixed_decimals(r.lobes.ap_min_mm, 3) + " mm"}};
  for (const auto& m : r.modes)
    p.provenance.emplace_back("mode", fixed_decimals(m.frequency_Hz, 1) + " Hz, ζ " + fixed_decimals(m.damping_ratio, 3) + ", k " +
                                          fixed_decimals(m.stiffness_N_per_mm, 0) + " N/mm");
  std::string command = "deflex stability";
  for (const auto& a : args) command += " " + a;
  p.provenance.emplace_back("command", command);
  p.limit = r.limit;
  p.pockets = r.pockets;
  p.ap_min_mm = r.lobes.ap_min_mm;
  writer::write_file_atomically((d / "stability.csv").string(), "", [&](std::ostream& o) { o << to_csv(r); });
  writer::write_file_atomically((d / "stability.json").string(), "",
                                [&](std::ostream& o) { o << report::document(to_json(r)); });
  writer::write_file_atomically((d / "stability.html").string(), "",
                                [&](std::ostream& o) { o << report::lobes_html(p); });
}

}  // namespace

int cmd_stability(const std::vector<std::string>& args, Io& io) {
  Args a;
  double ap = 0;
  po::options_description desc("options");
  desc.add_options()
      ("help,h", po::bool_switch(&a.help), "show this help")
      ("tool-file", po::value(&a.s.tool_file)->value_name("F"), "tool library (YAML; default: the config's)")
      ("tool", po::value(&a.s.tool)->value_name("ID"), "tool ID in the library");
  add_material_options(desc, a.s.material);
  desc.add_options()
      ("machine", po::value(&a.s.machine)->value_name("M"), "machine profile file or name (default: the config's)")
      ("frf", po::value(&a.s.frf)->value_name("F.csv"), "a measured tool-tip FRF instead of the model")
      ("tool-only", po::bool_switch(&a.s.tool_only), "the model of the tool clamped rigidly at the holder face")
      ("ae", po::value(&a.s.ae_mm)->value_name("MM"), "radial depth of cut a_e, mm, from the cutting side (>= D: slot)")
      ("ap", po::value(&ap)->value_name("MM"), "the depth whose engagement on the tool's shape is taken, mm")
      ("up", po::bool_switch(&a.up), "up-milling (cuts on the +Y side)")
      ("down", po::bool_switch(&a.down), "down-milling (cuts on the -Y side; the default)")
      ("rpm", po::value(&a.rpm)->value_name("MIN:MAX"), "spindle speed range, rpm")
      ("points", po::value(&a.s.points)->value_name("N"), "speeds of the printed limit, N + 1 (default 1000)")
      ("format", po::value(&a.format)->value_name("text|csv|json"), "output format (default text)")
      ("report", po::value(&a.report_dir)->value_name("DIR"), "write stability.html, .csv and .json into DIR");
  const po::variables_map vm = parse(args, desc, po::positional_options_description());
  refuse_output_onto_input({a.s.tool_file, a.s.material.material_file, a.s.frf});
  if (a.help) {
    print_help(io.out, kUsage, kHelp, desc);
    return 0;
  }
  for (const char* req : {"tool", "ae"})
    if (!vm.count(req)) throw Error(ErrorKind::settings, std::string("stability: --") + req + " is required (see --help)");
  if (a.up && a.down) throw Error(ErrorKind::settings, "stability: give one of --up and --down");
  if (a.format != "text" && a.format != "csv" && a.format != "json")
    throw Error(ErrorKind::settings, "stability: --format must be text, csv or json, not '" + a.format + "'");
  a.s.up_milling = a.up;
  if (vm.count("ap")) a.s.ap_mm = ap;
  if (!a.rpm.empty()) parse_rpm(a.rpm, a.s);
  if (!a.report_dir.empty()) writer::check_output_folder(a.report_dir);
  const job::StabilityResult r = job::stability(a.s);
  if (!a.report_dir.empty()) write_report(r, a.s, a.report_dir, args);
  if (a.format == "csv") io.out << to_csv(r);
  else if (a.format == "json") io.out << report::line(to_json(r));
  else io.out << to_text(r, a.s);
  return 0;
}

}  // namespace deflex::cli
