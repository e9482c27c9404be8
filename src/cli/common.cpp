#include "common.hpp"

#include <algorithm>
#include <exception>
#include <ostream>

namespace deflex::cli {

void add_read_options(po::options_description& d, job::ReadSettings& r, bool with_machine) {
  d.add_options()
    ("dialect", po::value(&r.dialect), "control dialect: fanuc (default), haas, linuxcnc, siemens-iso, "
                                       "heidenhain-iso, or a dialect .yaml file; overrides the machine's")
    ("config", po::value(&r.config), "config file (default: the first of ./deflex.yaml, ./config.yaml, "
                                     "$XDG_CONFIG_HOME/deflex/config.yaml, /etc/deflex/config.yaml, the installed "
                                     "defaults)")
    ("max-errors", po::value(&r.max_errors), "stop after N errors (0: no limit; default from config, 20)")
    ("block-delete", po::value(&r.block_delete)->default_value("off"),
     "block-delete switch: off executes '/' blocks (never compensated), on skips them")
    ("strict", po::bool_switch(&r.strict), "a program mixing axis words with and without a decimal point is an error, "
     "not a warning (the dialect's decimal rule then changes what some of them mean)")
    ("max-blocks", po::value(&r.max_blocks)->default_value(r.max_blocks),
     "most blocks executed and motions generated, subprogram and cycle repeats included (a guard against "
     "input that would run for hours)");
  if (with_machine)
    d.add_options()("machine", po::value(&r.machine), "machine profile: a .yaml file, or a name NAME for NAME.yaml in ./machines, ./samples/machines, "
                                                       "$XDG_CONFIG_HOME/deflex/machines, /etc/deflex/machines or the installed ones");
}

po::variables_map parse(const std::vector<std::string>& args, const po::options_description& desc,
                        const po::positional_options_description& pos) {
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(desc).positional(pos).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw Error(ErrorKind::settings, e.what());
  }
  return vm;
}

void parse_with_files(const std::vector<std::string>& args, const po::options_description& desc,
                      std::vector<std::string>& files, int max_files, bool words) {
  po::options_description all;
  all.add(desc).add_options()("file", po::value(&files));
  po::positional_options_description pos;
  pos.add("file", max_files);
  const po::variables_map vm = parse(args, all, pos);
  std::vector<std::string> inputs = words ? std::vector<std::string>() : files;
  // The options that name a file deflex reads (--machine and --dialect name
  // one by a name as often as by a path: left out).
  for (const char* o : {"stock", "stock-from", "stock-from-tools", "part", "reference", "job", "config", "tool-file", "material-file"}) {
    if (!vm.count(o)) continue;
    const boost::any& v = vm[o].value();
    if (const auto* one = boost::any_cast<std::string>(&v)) inputs.push_back(*one);
    if (const auto* many = boost::any_cast<std::vector<std::string>>(&v)) inputs.insert(inputs.end(), many->begin(), many->end());
  }
  refuse_output_onto_input(inputs);
}

void add_material_options(po::options_description& d, job::MaterialSettings& m) {
  auto opt = [](std::optional<double>& dst) {
    return po::value<double>()->notifier([&dst](double v) { dst = v; });
  };
  d.add_options()
      ("material", po::value(&m.material), "material name or alias in the material library")
      ("material-file", po::value(&m.material_file), "material library (default: config material_file, else the installed samples/materials.yaml)")
      ("kt", opt(m.kt), "K_tc, tangential cutting coefficient, N/mm^2")
      ("kr", opt(m.kr), "K_rc, radial cutting coefficient, N/mm^2")
      ("ka", opt(m.ka), "K_ac, axial cutting coefficient, N/mm^2")
      ("kte", opt(m.kte), "K_te, tangential edge coefficient, N/mm (default 0)")
      ("kre", opt(m.kre), "K_re, radial edge coefficient, N/mm (default 0)")
      ("kae", opt(m.kae), "K_ae, axial edge coefficient, N/mm (default 0)");
}
void add_part_options(po::options_description& d, job::PartSettings& p) {
  d.add_options()
      ("part", po::value(&p.part), "the part model (design surface): STL, STEP or IGES, work frame, mm (default: config part). "
       "Gives the surface normals and the gouge check")
      ("part-gap", po::value<double>()->notifier([&p](double v) { p.gap_mm = v; }),
       "warn where the programmed cutter cuts into the part or stands off a face of it by more than this, mm "
       "(default: config part_gap_mm, else 0.02)");
}

void print_help(std::ostream& out, const std::string& usage, const std::string& text,
                const po::options_description& desc) {
  out << "usage: " << usage << "\n\n" << text << "\n" << desc << "\n"
      << "output (every command):\n"
         "  -q [ --quiet ]        errors and warnings only (no notes, summary or progress)\n"
         "  -v [ --verbose ]      also the files and settings in use, and each stage's time\n"
         "  --progress arg (=auto) a progress line on stderr with the stage, percentage,\n"
         "                        elapsed time and ETA: auto (on a terminal), always, never\n\n";
}


namespace {

// --stock-from and --stock-from-tools keep their order: Boost stores each
// option's values apart, which loses which library follows which program, but
// its store() parses the occurrences in command-line order, each through this
// semantic's xparse, so each is appended to the list as it is parsed.
class EarlierOption : public po::typed_value<std::vector<std::string>> {
 public:
  EarlierOption(std::vector<EarlierOp>& ops, bool tools)
      : po::typed_value<std::vector<std::string>>(nullptr), ops_(ops), tools_(tools) {}
  void xparse(boost::any& store, const std::vector<std::string>& tokens) const override {
    po::typed_value<std::vector<std::string>>::xparse(store, tokens);
    for (const std::string& t : tokens) {
      if (!tools_) {
        ops_.push_back({t, ""});
      } else if (ops_.empty() || !ops_.back().tool_file.empty()) {
        throw po::error("--stock-from-tools " + t + " follows no --stock-from, or one that has its library already: " +
                        "it names the tool library of the --stock-from just before it");
      } else {
        ops_.back().tool_file = t;
      }
    }
  }

 private:
  std::vector<EarlierOp>& ops_;
  bool tools_;
};

}  // namespace

void add_stock_from_options(po::options_description& d, std::vector<EarlierOp>& ops) {
  d.add_options()
      ("stock-from", (new EarlierOption(ops, false))->composing()->value_name("FILE"),
       "an earlier program (roughing, semi-finishing) swept into the stock first with its own tools, geometry only; "
       "repeat for several, in order")
      ("stock-from-tools", (new EarlierOption(ops, true))->composing()->value_name("LIB"),
       "the tool library of the --stock-from just before it (YAML, Fusion 360 JSON or LinuxCNC .tbl), where that "
       "program's T numbers name another library than --tool-file's");
}

void describe(po::options_description& d, job::Settings& a, bool& help, std::string& job_file, bool compensating) {
  auto opt = [](std::optional<double>& dst) { return po::value<double>()->notifier([&dst](double v) { dst = v; }); };
  d.add_options()("help,h", po::bool_switch(&help), "show this help");
  if (compensating)
    d.add_options()("output,o", po::value(&a.output), "write the compensated program here (atomically); default stdout")
        ("feed-limit", po::value(&a.feed_limit_N), "also lower F where the peak cutting force would exceed this, N, or the cutting power or torque the machine profile's spindle S1 curve")
        ("expand-subprograms", po::bool_switch(&a.expand_subprograms),
         "write each subprogram call (M98) inline, with a comment naming it, so each pass gets its own compensation "
         "(messages then name lines of the expanded program); without it a subprogram that runs more than once stays as written");
  else d.add_options()("reference", po::value(&a.reference), "judge against this program's path (the design intent), e.g. the original of a compensated program");
  d.add_options()
      ("tool-file", po::value(&a.tool_file), "tool library (default: config tool_file, else the installed samples/tools.yaml)")
      ("tool", po::value(&a.tool), "use this tool for every cut (default: the program's T words, as T<n>)")
      ("spindle", opt(a.spindle_rpm), "spindle speed, rpm, for cutting moves the program gives no S (or S0)")
      ("feed", opt(a.feed_mm_per_min), "feed, mm/min, for cutting moves the program gives no F")
      ("stock", po::value(&a.stock), "box:X0,Y0,Z0,X1,Y1,Z1 (mm, work frame), an STL/STEP/IGES solid, a .zmap (deflex stock), or auto[:MARGIN] "
                                     "(a blank box round the cutting moves and the tool, MARGIN mm beyond them, default 1; "
                                     "its top at the highest cutting point) (default: config stock)")
      ("job", po::value(&job_file), "a job file (YAML): program, machine, tool_file, material, stock, stock_from, part, tolerance ... for one part; the command line overrides it");
  add_stock_from_options(d, a.stock_from);
  d.add_options()
      ("tolerance", opt(a.tolerance_mm), "surface tolerance, mm: points predicted inside +-tolerance stay as programmed (default 0.01)")
      ("gain", opt(a.gain), "mirror gain: 1 reflects the whole deflection, 0 changes nothing (default 1)")
      ("report", po::value(&a.report_dir), "write report.html, points.csv (one row per CL point), flank_profile.csv (flank cuts) and summary.json into this folder")
      ("cell-mm", po::value(&a.cell_mm)->default_value(0.05, "0.05"), "Z-map cell size, mm (0.05: within 0.2 um of a 0.025 mm grid at the p95 of every case studied, docs/benchmarks.md; 0.1 saves about a quarter of the time)")
      ("cl-spacing", po::value(&a.cl_spacing_mm)->default_value(0.5), "largest distance between CL points along a move, mm")
      ("max-iterations", po::value(&a.max_iterations)->default_value(8), "mirror updates per point at most (secant steps toward the fixed point)")
      ("threads", po::value(&a.threads)->default_value(0), "worker threads (0: all cores)")
      ("tool-only", po::bool_switch(&a.tool_only), "leave holder, spindle and machine out of the compliance")
      ("measured", po::value(&a.measured),
       "measurements of the part the program cut: a CSV of surface points x_mm,y_mm,z_mm (work frame, as CMM "
       "software exports them), a point cloud (.ply, .stl), or a probe log with --probe-program; the prediction is "
       "held against them (measured.csv and summary.json's \"measured\" in --report)")
      ("probe-program", po::value(&a.probe_program), "the probe program (deflex probe) whose log --measured is: it says which point each log line probed, and with which stylus")
      ("measured-reach", po::value(&a.measured_reach_mm)->default_value(0.5, "0.5"),
       "a measured point farther than this from the surface the program cuts has no prediction, mm");
  add_part_options(d, a.part);
  d.add_options()
      ("fixture", po::value(&a.workholding.fixtures)->composing()->value_name("box:X0,Y0,Z0,X1,Y1,Z1"),
       "the workpiece bends too: where it is held (mm, work frame; repeatable). The part's surface inside each box is "
       "clamped; its compliance (FEM of --part with the material's elastic constants) adds to the tool's at every "
       "contact (docs/physics.md)")
      ("workpiece-mesh", po::value(&a.workholding.mesh_mm)->value_name("MM"),
       "the part's element size with --fixture, mm (default: half its thinnest wall)")
      ("workpiece-spacing", po::value(&a.workholding.spacing_mm)->value_name("MM"),
       "with --fixture: the part's compliance is solved at nodes this far apart on the surface the program reaches "
       "and interpolated between them, mm (default: the coarsest of 12, 6 and 3 whose field is within 2 % of the "
       "FEM where least sure)")
      ("workpiece-stages", po::value(&a.workholding.stages)->value_name("N"),
       "with --fixture: the workpiece is the in-process stock, meshed at N moments (the starts of N equal groups of "
       "the program's passes; material still to come off stiffens it), instead of the finished part throughout "
       "(default 0). Each stage costs a mesh and a factorisation (docs/physics.md)");
  add_material_options(d, a.material);
  add_read_options(d, a.read);
}

std::vector<double> numbers_of(const std::string& list, const char* flag) {
  std::vector<double> v;
  std::size_t at = 0;
  while (at <= list.size()) {
    const std::size_t comma = std::min(list.find(',', at), list.size());
    const std::string item = list.substr(at, comma - at);
    std::size_t used = 0;
    double d = 0;
    try {
      d = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size())
      throw Error(ErrorKind::settings, std::string(flag) + " takes numbers separated by commas (mm), not '" + list + "'");
    v.push_back(d);
    at = comma + 1;
  }
  return v;
}


}  // namespace deflex::cli
