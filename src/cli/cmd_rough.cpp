// deflex rough: a roughing (or semi-finishing) program that leaves an
// allowance over the surface a finishing program cuts (job::rough), so the
// finishing program can be simulated on the stock a shop's roughing left
// (--stock-from rough.nc) when the shop has only the finishing program.
#include <cstdio>

#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/job/stock.hpp"
#include "deflex/report/summary.hpp"

namespace deflex::cli {

int cmd_rough(const std::vector<std::string>& args, Io& io) {
  job::RoughSettings s;
  plan::RoughingOptions& o = s.plan;
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")(
      "output,o", po::value(&s.output), "the program to write (atomically); default stdout")(
      "rough-tool", po::value(&s.rough_tool), "the cutter of the generated program, from the tool library (T<n>; required)")(
      "tool", po::value(&s.finish_tool), "the finishing program's tool for every cut (default: its T words)")(
      "tool-file", po::value(&s.tool_file), "tool library (YAML, Fusion 360 JSON or LinuxCNC .tbl)")(
      "stock", po::value(&s.stock), "box:X0,Y0,Z0,X1,Y1,Z1 (mm, work frame), an STL/STEP/IGES solid or a .zmap (default: config stock)")(
      "allowance", po::value(&o.allowance_mm)->default_value(0.5, "0.5"), "material left over the finished surface, along its normal, mm")(
      "stepdown", po::value<double>()->notifier([&](double v) { s.stepdown_mm = v; }),
      "largest depth of one level, mm (default: half the tool diameter; 0: one pass on the floor, a semi-finish)")(
      "stepover", po::value<double>()->notifier([&](double v) { s.stepover_mm = v; }),
      "distance between raster lines, mm (default: 40 % of the tool diameter)")(
      "sample", po::value(&o.sample_mm)->default_value(0.25, "0.25"), "distance between floor samples along a line, mm")(
      "spindle", po::value(&o.spindle_rpm)->default_value(8000), "spindle speed written, rpm")(
      "feed", po::value(&o.feed_mm_per_min)->default_value(1500), "feed written, mm/min")(
      "cell-mm", po::value(&s.cell_mm)->default_value(0.1, "0.1"), "Z-map cell of the target surface, mm");
  add_read_options(desc, s.read);
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
  if (files.empty()) throw Error(ErrorKind::settings, "rough: give the finishing program (see deflex rough --help)");
  if (s.rough_tool.empty())
    throw Error(ErrorKind::settings, "rough: --rough-tool T<n> is required (a flat, bull-nose or ball end mill of the library)");
  s.finish_program = files[0];
  const job::RoughResult r = job::rough(s, io.out, io);
  const process::MachiningTime& t = r.time;
  io.err << r.name << ": " << r.plan.levels_mm.size() << (r.plan.levels_mm.size() == 1 ? " level" : " levels")
         << " from Z" << fixed_decimals(r.plan.top_mm, 3) << " to the floor (lowest Z" << fixed_decimals(r.plan.floor_min_mm, 3) << "), "
         << r.plan.line_y_mm.size() << " lines " << fixed_decimals(r.line_spacing_mm, 3) << " mm apart, " << plural(r.moves, "move")
         << "; " << s.rough_tool << " leaves " << fixed_decimals(s.plan.allowance_mm, 3) << " mm over the surface of "
         << s.finish_program << "; machining time " << report::clock(t.program.total_s)
         << (report::clock_has_hours(t.program.total_s) ? " [h:mm:ss]\n" : " [m:ss]\n");
  return 0;
}

}  // namespace deflex::cli
