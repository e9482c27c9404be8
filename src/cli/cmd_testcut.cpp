// deflex testcut and deflex probe: the calibration test cut for a machine,
// tool and material on a block, with its plan (job::testcut), and the
// on-machine probing program of its walls (job::probe).
#include <algorithm>
#include <exception>

#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/job/testcut.hpp"

namespace deflex::cli {
namespace {

// An option whose absence the job sees (its default depends on the others).
auto optional_value(std::optional<double>& dst) {
  return po::value<double>()->notifier([&dst](double v) { dst = v; });
}

}  // namespace

int cmd_testcut(const std::vector<std::string>& args, Io& io) {
  job::TestCutSettings s;
  std::string ae, ap;
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")(
      "output,o", po::value(&s.output), "the test cut program to write (atomically; required)")(
      "plan", po::value(&s.plan), "the plan to write (YAML; default: the program's name with .yaml)")(
      "tool", po::value(&s.tool), "the end mill, from the tool library (T<n>; flat or bull nose; required)")(
      "tool-file", po::value(&s.tool_file), "tool library (YAML, Fusion 360 JSON or LinuxCNC .tbl)")(
      "material", po::value(&s.material.material), "the block's material, a name of the material library (required)")(
      "material-file", po::value(&s.material.material_file), "material library (default: the installed samples/materials.yaml)")(
      "stock", po::value(&s.stock), "the test block, box:X0,Y0,Z0,X1,Y1,Z1 (mm, work frame; required)")(
      "spindle", optional_value(s.spindle_rpm), "spindle speed, rpm (default 6000; the tool library has no cutting data)")(
      "feed", optional_value(s.feed_mm_per_min), "feed of the walls, mm/min (or --fz)")(
      "fz", optional_value(s.fz_mm), "feed per tooth, mm (default 0.05): the feed is fz x flutes x rpm")(
      "ae", po::value(&ae), "radial depths of the walls, mm, comma-separated (default 0.1, 0.25 and 0.5 D)")(
      "ap", po::value(&ap), "axial depths of the walls, mm, comma-separated (default 0.4 and 1.25 axial pitches)");
  add_read_options(desc, s.read);
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 0);
  if (help) {
    print_help(io.out, "deflex testcut --machine M --tool T<n> --material MAT --stock box:X0,Y0,Z0,X1,Y1,Z1 -o testcut.nc",
               "Writes a calibration program for this machine, tool and material on the block, and\n"
               "beside it its plan (testcut.yaml). The program side-mills straight walls, down\n"
               "(climb) milling with the spindle clockwise (M3): walls fed along +X on the back\n"
               "face (y = Y1) and along +Y on the left face (x = X0), at radial depths of 0.1,\n"
               "0.25 and 0.5 D and at two axial depths, below and above the axial pitch between\n"
               "flutes (pi D / (N tan helix): one flute at a time, then overlapping flutes, as\n"
               "in Morelli 2021). Each wall is entered from air beside the block; rapids run\n"
               "only above the block top + 5 mm. A block too small is refused with the\n"
               "smallest that fits. The plan states each wall's intended plane, its probe\n"
               "region (steady-state cut), a_e, a_p, f_z and program lines. --ae and --ap\n"
               "choose the depths in mm instead (every a_e at every a_p, on both faces). Then:\n"
               "  deflex probe testcut.yaml --dialect D -o probe.nc\n"
               "writes the on-machine probing program of those walls. A ball end mill cuts\n"
               "slope patches instead: the block's front top edge (y = Y0) chamfered at 15, 30\n"
               "and 45 deg, passes along +X down the slope 0.1 R apart, each at most 0.8 R deep.\n",
               desc);
    return 0;
  }
  if (!ae.empty()) s.options.ae_mm = numbers_of(ae, "--ae");
  if (!ap.empty()) s.options.ap_mm = numbers_of(ap, "--ap");
  const job::TestCutResult r = job::testcut(s, io);
  const plan::TestCutPlan& p = r.plan;
  const bool ball = p.tool.type == stock::EndShape::ball;
  io.info() << r.program << ": " << (ball ? plural(p.features.size(), "slope patch", "slope patches") : plural(p.features.size(), "wall"))
            << " of " << s.tool << " in " << p.material << ", S"
            << fixed_decimals(p.spindle_rpm, 0) << " F" << fixed_decimals(p.feed_mm_per_min, 1) << " (fz "
            << fixed_decimals(p.fz_mm, 4) << " mm), " << plural(r.moves, "move") << "; plan " << r.plan_file << "\n";
  return 0;
}

int cmd_probe(const std::vector<std::string>& args, Io& io) {
  job::ProbeSettings s;
  plan::ProbeOptions& o = s.options;
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")(
      "output,o", po::value(&s.output), "the probing program to write (atomically); default stdout")(
      "dialect", po::value(&s.read.dialect), "the control's dialect (default: the plan's)")(
      "ball-diameter", po::value(&o.ball_diameter_mm)->default_value(2, "2"), "stylus ball diameter, mm")(
      "probe-length", po::value(&o.probe_length_mm),
      "stylus length from the ball centre to the probe body, mm: checked against the deepest point (default: not checked)")(
      "probe-tool", po::value(&s.probe_tool), "the probe's tool number T<n>: T M6 and G43 H (default: already in the spindle)")(
      "step", po::value(&o.step_mm)->default_value(0.5, "0.5"), "between heights on a wall, mm (0.25 to 0.5)")(
      "approach", po::value(&o.approach_mm)->default_value(2, "2"), "each probing move starts this far off the intended surface, mm")(
      "probe-feed", po::value(&o.probe_feed_mm_per_min)->default_value(100, "100"), "feed of the probing moves, mm/min");
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
  if (help) {
    print_help(io.out, "deflex probe testcut.yaml [--dialect D] [-o probe.nc]",
               "Writes the on-machine probing program of the walls (or slopes) a test cut left (its plan from\n"
               "deflex testcut): on each wall's probe region, three positions along the feed and\n"
               "heights every --step from the floor up, each point approached along the wall's\n"
               "normal: the ball centre --approach off the surface, a probing move that stops on\n"
               "contact (LinuxCNC G38.2, logged by PROBEOPEN to probe_results.txt; Fanuc and the\n"
               "ISO controls G31, then DPRNT of #5061-#5063 with the point's id), and back.\n"
               "Below the block top + clearance every move is a feed or a probing move, never a\n"
               "rapid. Coordinates are the ball centre: set the probe's length offset to it.\n"
               "Before each probing move a comment names the point:\n"
               "  (DEFLEX PROBE 12 WX1 AT 10.000 5.000 -2.250 N 0.0000 1.0000 0.0000 BALL 1.000)\n"
               "= point id, feature, intended surface point X Y Z (mm), outward normal, ball radius.\n"
               "Activate the probe where the program stops (M0): its M code is machine-specific.\n",
               desc);
    return 0;
  }
  if (files.empty()) throw Error(ErrorKind::settings, "probe: give the test cut's plan (see deflex probe --help)");
  s.plan = files[0];
  const job::ProbeResult r = job::probe(s, io.out, io);
  io.info() << r.name << ": " << plural(r.points, "point") << " on " << plural(r.program.features.size(), "feature") << " of "
            << s.plan << ", ball D" << fixed_decimals(o.ball_diameter_mm, 3) << "\n";
  return 0;
}

}  // namespace deflex::cli
