// job::testcut() and job::probe() (testcut.hpp).
#include "deflex/job/testcut.hpp"

#include <filesystem>
#include <ostream>
#include <sstream>

#include "deflex/diag/plural.hpp"
#include "deflex/job/setup.hpp"
#include "deflex/profile/yaml.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/writer/writer.hpp"
#include "read_back.hpp"

namespace deflex::job {
namespace {

// n of "T<n>" (n up to 99999), else Error(settings) on `keyword`.
int tool_number(const std::string& t, const char* keyword, const char* why) {
  if (t.size() < 2 || t.size() > 6 || t[0] != 'T' || t.find_first_not_of("0123456789", 1) != std::string::npos)
    throw Error(ErrorKind::settings, std::string("{") + keyword + "} must be a tool number T<n> (n up to 99999): " + why);
  return std::stoi(t.substr(1));
}

const char* shape_name(stock::EndShape s) {
  return s == stock::EndShape::ball ? "BALL" : s == stock::EndShape::bull ? "BULL NOSE" : "FLAT";
}

plan::TestCutter cutter_of(const stiffness::Tool& t) {
  plan::TestCutter c;
  c.id = t.id;
  c.type = t.type;
  c.diameter_mm = t.diameter_mm;
  c.corner_radius_mm = t.type == stock::EndShape::flat ? 0.0 : t.corner_radius_mm;
  c.flutes = t.flutes;
  c.helix_deg = t.helix_deg;
  c.flute_length_mm = t.flute_length_mm;
  return c;
}

// The options with the settings' speeds: rpm given or 6000; f_z given, or
// the feed given over N n, or 0.05 mm. stiffness::Tool carries no cutting
// data, so the library has none to offer.
plan::TestCutOptions cut_options(const TestCutSettings& s, const plan::TestCutter& c) {
  plan::TestCutOptions o = s.options;
  if (s.feed_mm_per_min && s.fz_mm) throw Error(ErrorKind::settings, "give {feed_mm_per_min} or {fz_mm}, not both");
  if (s.spindle_rpm) o.spindle_rpm = *s.spindle_rpm;
  if (!(o.spindle_rpm > 0 && o.spindle_rpm <= 1e5)) throw Error(ErrorKind::settings, "{spindle_rpm} must be in (0, 100000] rpm");
  if (s.fz_mm) o.fz_mm = *s.fz_mm;
  if (s.feed_mm_per_min) {
    if (!(*s.feed_mm_per_min > 0 && *s.feed_mm_per_min <= 1e5))
      throw Error(ErrorKind::settings, "{feed_mm_per_min} must be in (0, 100000] mm/min");
    o.fz_mm = *s.feed_mm_per_min / (c.flutes * o.spindle_rpm);
  }
  return o;
}

std::vector<std::string> cut_header(const TestCutSettings& s, const plan::TestCutPlan& p, const std::string& box,
                                    const std::string& plan_file) {
  const plan::TestCutter& t = p.tool;
  return {"DEFLEX TESTCUT - WALLS FOR THE STIFFNESS FIT, PROBED WITH DEFLEX PROBE " + plan_file,
          "MACHINE " + p.machine + " - MATERIAL " + p.material + " - BLOCK " + box,
          s.tool + " " + shape_name(t.type) + " D" + fixed_decimals(t.diameter_mm, 3) + " " + plural(t.flutes, "FLUTE", "FLUTES") +
              " HELIX " + fixed_decimals(t.helix_deg, 1) + " - S" + fixed_decimals(p.spindle_rpm, 0) + " F" +
              fixed_decimals(p.feed_mm_per_min, 1) + " FZ " + fixed_decimals(p.fz_mm, 4),
          "DOWN MILLING, SPINDLE M3 - " + plural(p.features.size(), "WALL", "WALLS") + ", EACH ENTERED FROM AIR BESIDE THE BLOCK"};
}

}  // namespace

std::string plan_path_for(const std::string& program) {
  return std::filesystem::path(program).replace_extension(".yaml").string();
}

TestCutResult testcut(const TestCutSettings& s, Io& io) {
  (void)io;
  if (s.output.empty() || s.output == "-")
    throw Error(ErrorKind::settings, "testcut: the program goes to a file ({output} FILE.nc): its plan names it");
  TestCutResult r;
  r.program = s.output;
  r.plan_file = s.plan.empty() ? plan_path_for(s.output) : s.plan;
  if (r.plan_file == r.program) throw Error(ErrorKind::settings, "{plan} must not be the program ({output})");
  writer::check_output_path(r.program, "");
  writer::check_output_path(r.plan_file, "");
  if (s.tool.empty()) throw Error(ErrorKind::settings, "testcut: {tool} T<n> is required (a flat or bull-nose end mill of the library)");
  const int number = tool_number(s.tool, "tool", "the program calls it with T and H words");
  if (s.material.material.empty()) throw Error(ErrorKind::settings, "testcut: {material} is required (the plan names it)");
  if (s.stock.empty() || !s.stock.starts_with("box:"))
    throw Error(ErrorKind::settings, "testcut: {stock} must be the test block, box:X0,Y0,Z0,X1,Y1,Z1 (mm, work frame)");
  const stock::BoxSpec box = stock::parse_box(s.stock);
  const Setup setup = resolve_with_machine(s.read);
  MaterialSettings material = s.material;
  material.material_file = material_library_path(material.material_file, setup.config);
  const force::Coefficients k = coefficients_of(material);
  const stiffness::ToolLibrary lib = stiffness::load_tool_library(tool_library_path(s.tool_file, setup.config));
  const plan::TestCutter cutter = cutter_of(stiffness::find_tool(lib, s.tool));
  plan::TestCutOptions o = cut_options(s, cutter);
  o.tool_number = number;
  o.Ktc_N_per_mm2 = k.Ktc_N_per_mm2;
  o.Krc_N_per_mm2 = k.Krc_N_per_mm2;
  const plan::TestBlock b{box.x0_mm, box.y0_mm, box.z0_mm, box.x1_mm, box.y1_mm, box.z1_mm};
  r.plan = plan::plan_testcut(b, cutter, o);  // checks the options and the block first
  r.plan.machine = setup.machine->name;
  r.plan.material = s.material.material;
  r.plan.dialect = setup.dialect.name;
  std::ostringstream text, yaml;
  plan::write_testcut(text, r.plan, setup.dialect, cut_header(s, r.plan, s.stock, r.plan_file));
  r.moves = read_back(text.str(), r.program, setup, "the test cut").size();
  plan::write_plan_yaml(yaml, r.plan, r.program);
  writer::write_file_atomically(r.program, "", [&](std::ostream& f) { f << text.str(); });
  writer::write_file_atomically(r.plan_file, "", [&](std::ostream& f) { f << yaml.str(); });
  return r;
}

ProbeResult probe(const ProbeSettings& s, std::ostream& out, Io& io) {
  (void)io;
  const bool to_file = !s.output.empty() && s.output != "-";
  if (s.plan.empty()) throw Error(ErrorKind::settings, "probe: give the test cut's plan (testcut.yaml)");
  if (to_file) writer::check_output_path(s.output, s.plan);
  plan::ProbeOptions o = s.options;
  if (!s.probe_tool.empty()) o.probe_tool = tool_number(s.probe_tool, "probe_tool", "the program calls it with T and H words");
  plan::check_probe_options(o);  // before the plan is read
  const plan::TestCutPlan p = plan::read_plan_yaml(yaml::read_file(s.plan), s.plan);
  const profile::Dialect d = profile::load_dialect(s.read.dialect.empty() ? p.dialect : s.read.dialect);
  ProbeResult r;
  r.program = plan::plan_probe(p, o);
  r.name = to_file ? s.output : "<stdout>";
  for (const auto& f : r.program.features) r.points += f.size();
  const double ball = o.ball_diameter_mm;
  const std::vector<std::string> header = {
      "DEFLEX PROBING - THE WALLS OF " + s.plan + ": " + plural(r.points, "POINT", "POINTS"),
      "STYLUS BALL D" + fixed_decimals(ball, 3) + " - PROBE LENGTH " +
          (o.probe_length_mm > 0 ? fixed_decimals(o.probe_length_mm, 3) + " MM" : std::string("NOT GIVEN: NOT CHECKED")) +
          (o.probe_tool > 0 ? " - PROBE T" + std::to_string(o.probe_tool) : std::string(" - THE PROBE MUST BE IN THE SPINDLE, ITS LENGTH OFFSET ACTIVE")),
      "COORDINATES ARE THE BALL CENTRE: SET THE PROBE LENGTH OFFSET TO THE BALL CENTRE",
      "APPROACH " + fixed_decimals(o.approach_mm, 3) + " MM, OVERTRAVEL " + fixed_decimals(o.overtravel_mm, 3) + " MM, PROBING F" +
          fixed_decimals(o.probe_feed_mm_per_min, 1) + " - RAPIDS ONLY ABOVE Z" + fixed_decimals(r.program.clear_z_mm, 3)};
  std::ostringstream text;
  plan::write_probe(text, r.program, d, header);
  if (to_file) writer::write_file_atomically(s.output, s.plan, [&](std::ostream& f) { f << text.str(); });
  else out << text.str();
  return r;
}

}  // namespace deflex::job
