// deflex rough: a roughing (or semi-finishing) program that leaves an
// allowance over the surface a finishing program cuts (plan/roughing.hpp), so
// the finishing program can be simulated on the stock a shop's roughing left
// (--stock-from rough.nc) when the shop has only the finishing program.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/interp/travel.hpp"
#include "deflex/plan/roughing.hpp"
#include "deflex/process/machining_time.hpp"
#include "deflex/report/summary.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/writer/writer.hpp"
#include "job.hpp"

namespace deflex::cli {
namespace {

std::string fmt(double v, int decimals) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

// The generated program read back as any program is (a self-check: it must
// interpret without a diagnostic and stay in the machine's travel).
std::vector<interp::Motion> read_back(const std::string& text, const std::string& name, const Setup& s) {
  const gcode::Program prog(SourceText(name, text));
  std::ostringstream err;
  Diagnostics diags(&err, 0);
  std::vector<interp::Motion> motions;
  Collect c;
  c.out = &motions;
  interp::interpret(prog, s.interp(), diags, c);
  for (const interp::Motion& m : motions) interp::check_travel(m, s.machine->travel, prog.source(), diags);
  if (diags.errors() || diags.warnings())
    throw Error(Exit::usage, "the roughing program does not fit this machine (nothing written):\n" + err.str());
  return motions;
}

}  // namespace

int cmd_rough(const std::vector<std::string>& args, Io& io) {
  ReadOptions read;
  std::string stock_given, tool_file, output, rough_tool, finish_tool;
  plan::RoughingOptions o;
  std::optional<double> stepdown, stepover;
  double cell_mm = 0.1, cl_spacing_mm = 0.5;
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")(
      "output,o", po::value(&output), "the program to write (atomically); default stdout")(
      "rough-tool", po::value(&rough_tool), "the cutter of the generated program, from the tool library (T<n>; required)")(
      "tool", po::value(&finish_tool), "the finishing program's tool for every cut (default: its T words)")(
      "tool-file", po::value(&tool_file), "tool library (YAML, Fusion 360 JSON or LinuxCNC .tbl)")(
      "stock", po::value(&stock_given), "box:X0,Y0,Z0,X1,Y1,Z1 (mm, work frame), an STL/STEP/IGES solid or a .zmap (default: config stock)")(
      "allowance", po::value(&o.allowance_mm)->default_value(0.5, "0.5"), "material left over the finished surface, along its normal, mm")(
      "stepdown", po::value<double>()->notifier([&](double v) { stepdown = v; }),
      "largest depth of one level, mm (default: half the tool diameter; 0: one pass on the floor, a semi-finish)")(
      "stepover", po::value<double>()->notifier([&](double v) { stepover = v; }),
      "distance between raster lines, mm (default: 40 % of the tool diameter)")(
      "sample", po::value(&o.sample_mm)->default_value(0.25, "0.25"), "distance between floor samples along a line, mm")(
      "spindle", po::value(&o.spindle_rpm)->default_value(8000), "spindle speed written, rpm")(
      "feed", po::value(&o.feed_mm_per_min)->default_value(1500), "feed written, mm/min")(
      "cell-mm", po::value(&cell_mm)->default_value(0.1, "0.1"), "Z-map cell of the target surface, mm");
  add_read_options(desc, read);
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
  if (help) {
    print_help(io.out, "deflex rough FINISH.nc --stock S --rough-tool T<n> [-o rough.nc]",
               "Writes the roughing a shop would have run before FINISH.nc: the finishing program\n"
               "is swept into the stock with its own tools to find the finished surface; the\n"
               "new program (Z-level raster along X, zig-zag, levels at most --stepdown deep,\n"
               "each level following the floor) leaves --allowance over that surface, measured\n"
               "along its normal. Lines start and end outside the stock. --stepdown 0 with a ball\n"
               "and a small --stepover is a semi-finishing pass. Then:\n"
               "  deflex compensate FINISH.nc --stock S --stock-from rough.nc ...\n"
               "The program cuts air where an earlier level already went: it stands for the\n"
               "stock a roughing leaves, it is not an optimised roughing strategy.\n",
               desc);
    return 0;
  }
  if (files.empty()) throw Error(Exit::usage, "rough: give the finishing program (see deflex rough --help)");
  if (files[0] == "-") throw Error(Exit::usage, "rough: the finishing program must be a file, not standard input");
  if (rough_tool.empty()) throw Error(Exit::usage, "rough: --rough-tool T<n> is required (a flat, bull-nose or ball end mill of the library)");
  if (!output.empty() && output != "-") writer::check_output_path(output, files[0]);
  if (!(cell_mm >= 0.005 && cell_mm <= 5)) throw Error(Exit::usage, "--cell-mm must be between 0.005 and 5");
  const Setup s = resolve_with_machine(read);
  const std::string spec = stock_spec(stock_given, s.config);
  const stiffness::ToolLibrary lib = stiffness::load_tool_library(tool_library_path(tool_file, s.config));
  const stiffness::Tool& rt = stiffness::find_tool(lib, rough_tool);
  if (!finish_tool.empty()) (void)stiffness::find_tool(lib, finish_tool);
  if (rough_tool.size() < 2 || rough_tool.size() > 6 || rough_tool[0] != 'T' ||
      rough_tool.find_first_not_of("0123456789", 1) != std::string::npos)
    throw Error(Exit::usage, "--rough-tool must be a tool number T<n> (n up to 99999): the program calls it with T and H words");
  o.tool = profile_of(rt);
  o.tool_number = std::stoi(rough_tool.substr(1));
  o.stepdown_mm = stepdown ? *stepdown : rt.diameter_mm / 2;
  o.stepover_mm = stepover ? *stepover : 0.4 * rt.diameter_mm;
  plan::check_options(o);
  const std::vector<interp::Motion> finish = read_earlier(files[0], s, lib, io, finish_tool);

  stock::SolidOptions so;
  so.cell_mm = cell_mm;
  stock::ZMap target = stock::make_stock(spec, so);
  const stock::GridSpec& g = target.grid();
  const double top = target.max_height_in(g.x0_mm, g.y0_mm, g.x0_mm + g.nx * g.cell_mm, g.y0_mm + g.ny * g.cell_mm);
  sweep_earlier(finish, target, lib, cl_spacing_mm, finish_tool);
  const plan::RoughingPlan p = plan::plan_roughing(target, top, o);

  // The lines are spread evenly over the stock's width (plan/roughing.hpp), so
  // they lie at most the stepover apart: the header names what was planned.
  const double spacing = p.line_y_mm.size() > 1 ? p.line_y_mm[1] - p.line_y_mm[0] : 0;
  const std::string name = output.empty() || output == "-" ? "<stdout>" : output;
  std::ostringstream text;
  plan::write_roughing(text, p, o, s.dialect,
                       {"DEFLEX ROUGH - THE STOCK BEFORE " + files[0],
                        rough_tool + " " + (rt.type == stock::EndShape::ball ? "BALL" : rt.type == stock::EndShape::bull ? "BULL NOSE" : "FLAT") +
                            " D" + fmt(rt.diameter_mm, 3) + " - ALLOWANCE " + fmt(o.allowance_mm, 3) + " MM OVER THE SURFACE OF " +
                            files[0] + (finish_tool.empty() ? "" : " CUT WITH " + finish_tool),
                        "STOCK " + spec + " - CELL " + fmt(cell_mm, 3) + " MM",
                        "Z-LEVEL RASTER ALONG X, " +
                            (o.stepdown_mm > 0 ? "STEPDOWN AT MOST " + fmt(o.stepdown_mm, 3) : std::string("ONE LEVEL")) +
                            ", LINES " +
                            fmt(spacing, 3) + " MM APART - THE STEPOVER " + fmt(o.stepover_mm, 3) +
                            " SPREAD EVENLY OVER THE STOCK - FEEDS AND SPEEDS NOT CHECKED: FOR SIMULATION"});
  const std::vector<interp::Motion> motions = read_back(text.str(), name, s);
  if (output.empty() || output == "-") io.out << text.str();
  else writer::write_file_atomically(output, files[0], [&](std::ostream& out) { out << text.str(); });

  const process::MachiningTime t = process::machining_time(motions, s.machine->axis_limits);
  io.err << name << ": " << p.levels_mm.size() << (p.levels_mm.size() == 1 ? " level" : " levels") << " from Z"
         << fmt(p.top_mm, 3) << " to the floor (lowest Z" << fmt(p.floor_min_mm, 3) << "), " << p.line_y_mm.size()
         << " lines " << fmt(spacing, 3) << " mm apart, " << plural(motions.size(), "move") << "; " << rough_tool << " leaves " << fmt(o.allowance_mm, 3)
         << " mm over the surface of " << files[0] << "; machining time " << report::clock(t.program.total_s)
         << (report::clock_has_hours(t.program.total_s) ? " [h:mm:ss]\n" : " [m:ss]\n");
  return 0;
}

}  // namespace deflex::cli
