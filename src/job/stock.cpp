// job::rough() and job::rest_stock() (stock.hpp).
#include "deflex/job/stock.hpp"

#include <cstdio>
#include <ostream>
#include <sstream>

#include "deflex/diag/plural.hpp"
#include "deflex/interp/travel.hpp"
#include "deflex/job/earlier.hpp"
#include "deflex/job/run.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/stock/mesh_out.hpp"
#include "deflex/stock/zmap_file.hpp"
#include "deflex/writer/writer.hpp"
#include "read_back.hpp"

namespace deflex::job {

std::vector<interp::Motion> read_back(const std::string& text, const std::string& name, const Setup& s,
                                      const std::string& what) {
  const gcode::Program prog(SourceText(name, text));
  std::ostringstream err;
  Diagnostics diags(&err, 0);
  std::vector<interp::Motion> motions;
  interp::MotionList c(motions);
  interp::interpret(prog, s.interp(), diags, c);
  for (const interp::Motion& m : motions) interp::check_travel(m, s.machine->travel, prog.source(), diags);
  if (diags.errors() || diags.warnings())
    throw Error(ErrorKind::settings, what + " does not fit this machine (nothing written):\n" + err.str());
  return motions;
}

namespace {

// The settings checked and the plan's tool, stepdown and stepover set.
plan::RoughingOptions roughing_options(const RoughSettings& s, const stiffness::Tool& rt) {
  if (s.finish_program == "-") throw Error(ErrorKind::settings, "rough: the finishing program must be a file, not standard input");
  const std::string& t = s.rough_tool;
  if (t.size() < 2 || t.size() > 6 || t[0] != 'T' || t.find_first_not_of("0123456789", 1) != std::string::npos)
    throw Error(ErrorKind::settings, "{rough_tool} must be a tool number T<n> (n up to 99999): the program calls it with T and H words");
  plan::RoughingOptions o = s.plan;
  o.tool = profile_of(rt);
  o.tool_number = std::stoi(t.substr(1));
  o.stepdown_mm = s.stepdown_mm ? *s.stepdown_mm : rt.diameter_mm / 2;
  o.stepover_mm = s.stepover_mm ? *s.stepover_mm : 0.4 * rt.diameter_mm;
  plan::check_options(o);
  return o;
}

// The comment lines at the head of the program: what it stands for.
std::vector<std::string> header(const RoughSettings& s, const stiffness::Tool& rt, const plan::RoughingOptions& o,
                                const std::string& spec, double spacing_mm) {
  const char* shape = rt.type == stock::EndShape::ball ? "BALL" : rt.type == stock::EndShape::bull ? "BULL NOSE" : "FLAT";
  const std::string& f = s.finish_program;
  return {"DEFLEX ROUGH - THE STOCK BEFORE " + f,
          s.rough_tool + " " + shape + " D" + fixed_decimals(rt.diameter_mm, 3) + " - ALLOWANCE " + fixed_decimals(o.allowance_mm, 3) +
              " MM OVER THE SURFACE OF " + f + (s.finish_tool.empty() ? "" : " CUT WITH " + s.finish_tool),
          "STOCK " + spec + " - CELL " + fixed_decimals(s.cell_mm, 3) + " MM",
          "Z-LEVEL RASTER ALONG X, " +
              (o.stepdown_mm > 0 ? "STEPDOWN AT MOST " + fixed_decimals(o.stepdown_mm, 3) : std::string("ONE LEVEL")) + ", LINES " +
              fixed_decimals(spacing_mm, 3) + " MM APART - THE STEPOVER " + fixed_decimals(o.stepover_mm, 3) +
              " SPREAD EVENLY OVER THE STOCK - FEEDS AND SPEEDS NOT CHECKED: FOR SIMULATION"};
}

}  // namespace

stock::ZMap rest_stock(const StockSettings& s, Io& io, std::string* spec_out) {
  if (!(s.cell_mm >= 0.005 && s.cell_mm <= 5)) throw Error(ErrorKind::settings, "{cell_mm} must be between 0.005 and 5");
  const Setup setup = resolve_with_machine(s.read);
  const std::string spec = stock_spec(s.stock, setup.config);
  const stiffness::ToolLibrary lib = stiffness::load_tool_library(tool_library_path(s.tool_file, setup.config));
  const std::vector<EarlierRun> earlier = read_earlier_all(s.stock_from, setup, lib, io);
  stock::SolidOptions so;
  so.cell_mm = s.cell_mm;
  stock::ZMap z = stock::make_stock(spec, so);
  sweep_earlier_all(earlier, z, lib, s.cl_spacing_mm);
  if (spec_out) *spec_out = spec;
  return z;
}

StockFile write_rest_stock(const StockSettings& s, const std::string& output, double mesh_tolerance_mm, Io& io) {
  if (output.empty() || output == "-")
    throw Error(ErrorKind::settings, "the stock goes to a file ({output} FILE.zmap or FILE.stl: both are binary)");
  writer::check_output_path(output, "");
  if (!(mesh_tolerance_mm >= 0 && mesh_tolerance_mm <= 10))
    throw Error(ErrorKind::settings, "{mesh_tolerance_mm} must be in [0, 10] mm");
  StockFile f;
  const stock::ZMap z = rest_stock(s, io, &f.spec);
  f.grid = z.grid();
  f.zmap = stock::is_zmap_path(output);
  if (f.zmap) {
    writer::write_file_atomically(output, "", [&](std::ostream& o) { stock::write_zmap(o, z); });
    return f;
  }
  const std::vector<stock::Triangle> tris = stock::zmap_mesh(z, mesh_tolerance_mm);
  writer::write_file_atomically(output, "", [&](std::ostream& o) {
    stock::write_binary_stl(o, tris, "deflex stock: " + f.spec);
  });
  f.triangles = tris.size();
  return f;
}

RoughResult rough(const RoughSettings& s, std::ostream& out, Io& io) {
  if (!s.output.empty() && s.output != "-") writer::check_output_path(s.output, s.finish_program);
  if (!(s.cell_mm >= 0.005 && s.cell_mm <= 5)) throw Error(ErrorKind::settings, "{cell_mm} must be between 0.005 and 5");
  const Setup setup = resolve_with_machine(s.read);
  const std::string spec = stock_spec(s.stock, setup.config);
  const stiffness::ToolLibrary lib = stiffness::load_tool_library(tool_library_path(s.tool_file, setup.config));
  const stiffness::Tool& rt = stiffness::find_tool(lib, s.rough_tool);
  if (!s.finish_tool.empty()) (void)stiffness::find_tool(lib, s.finish_tool);
  const plan::RoughingOptions o = roughing_options(s, rt);
  const std::vector<interp::Motion> finish = read_earlier(s.finish_program, setup, lib, io, s.finish_tool);
  stock::SolidOptions so;
  so.cell_mm = s.cell_mm;
  stock::ZMap target = stock::make_stock(spec, so);
  const stock::GridSpec& g = target.grid();
  const double top = target.max_height_in(g.x0_mm, g.y0_mm, g.x0_mm + g.nx * g.cell_mm, g.y0_mm + g.ny * g.cell_mm);
  sweep_earlier(finish, target, lib, s.cl_spacing_mm, s.finish_tool);
  RoughResult r;
  r.plan = plan::plan_roughing(target, top, o);
  // The lines are spread evenly over the stock's width (plan/roughing.hpp), so
  // they lie at most the stepover apart: the header names what was planned.
  r.line_spacing_mm = r.plan.line_y_mm.size() > 1 ? r.plan.line_y_mm[1] - r.plan.line_y_mm[0] : 0;
  r.name = s.output.empty() || s.output == "-" ? "<stdout>" : s.output;
  std::ostringstream text;
  plan::write_roughing(text, r.plan, o, setup.dialect, header(s, rt, o, spec, r.line_spacing_mm));
  const std::vector<interp::Motion> motions = read_back(text.str(), r.name, setup, "the roughing program");
  if (s.output.empty() || s.output == "-") out << text.str();
  else writer::write_file_atomically(s.output, s.finish_program, [&](std::ostream& f) { f << text.str(); });
  r.moves = motions.size();
  r.time = process::machining_time(motions, setup.machine->axis_limits);
  return r;
}

}  // namespace deflex::job
