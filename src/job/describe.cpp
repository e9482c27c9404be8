// What a run used and where it came from (job.hpp), and the plausibility
// findings as messages and JSON (internal.hpp).
#include <cstdio>
#include <set>

#include "deflex/job/job.hpp"
#include "deflex/job/earlier.hpp"
#include "deflex/report/html.hpp"
#include "deflex/report/summary.hpp"
#include "deflex/version.hpp"
#include "internal.hpp"

namespace deflex::job {
namespace {

// A number as a person writes it: 0.01, 80, 2.5.
std::string report_number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

// The tools the cutting moves use, by id.
std::set<std::string> cutting_tools(const Run& j) {
  std::set<std::string> tools = j.cutting_tools;  // in pieces; else:
  for (const interp::Motion& m : j.motions)
    if (m.kind != interp::MotionKind::rapid) tools.insert(compensate::tool_id(m, j.settings));
  return tools;
}

// "T1: flat D10 mm", "T2: bull nose D12 mm r1".
std::string tool_text(const std::string& id, const stiffness::Tool& t) {
  const bool bull = t.type == stock::EndShape::bull;
  return id + ": " + (t.type == stock::EndShape::ball ? "ball" : bull ? "bull nose" : "flat") + " D" +
         report_number(t.diameter_mm) + " mm" + (bull ? " r" + report_number(t.corner_radius_mm) : "");
}

// The material's name and library, without the source that Run::material
// adds after a ';' ("C35 (samples/materials.yaml; source: ...)").
std::string material_text(const Run& j) {
  const std::size_t cut = j.material.find(';');
  return cut == std::string::npos ? j.material : j.material.substr(0, cut) + ")";
}

}  // namespace

Used used(const Run& j) {
  Used u;
  const profile::MachineProfile& m = *j.setup.machine;
  u.json = {{"config", j.setup.config.file.empty() ? report::Json() : report::Json(j.setup.config.file)},
            {"machine", m.name}, {"machine_file", m.file}, {"dialect", j.setup.dialect.name},
            {"tool_file", j.physics.tools.file}, {"material", material_text(j)}};
  report::Json tools = report::Json::array();
  std::string t_text;
  for (const std::string& id : cutting_tools(j)) {
    const std::string t = tool_text(id, j.physics.tools.tools.at(id));
    tools.push_back(t);
    t_text += (t_text.empty() ? "" : ", ") + t;
  }
  u.json["tools"] = tools;
  u.text = "used: machine " + m.name + " (" + m.file + ", dialect " + j.setup.dialect.name + "); " +
           (t_text.empty() ? "no cutting tool" : t_text) + " (" + j.physics.tools.file + "); material " +
           material_text(j) + "; config " + (j.setup.config.file.empty() ? "none" : j.setup.config.file);
  return u;
}

std::vector<std::pair<std::string, std::string>> provenance(const Run& j, const std::string& command) {
  const std::string& reference = j.given.reference;
  std::vector<std::pair<std::string, std::string>> p;
  p.emplace_back("program", j.prog.source().name());
  p.emplace_back("program SHA-256", j.pieces ? j.sha256 : report::sha256_hex(j.prog.source().bytes()));
  if (!reference.empty()) p.emplace_back("judged against", reference);
  p.emplace_back("machine", j.setup.machine->name + " (" + j.setup.machine->file + "), dialect " + j.setup.dialect.name);
  for (const std::string& id : cutting_tools(j)) {
    const stiffness::Tool& t = j.physics.tools.tools.at(id);
    char buf[200];
    std::snprintf(buf, sizeof buf, "%s, %d flutes, helix %g deg, stick-out %g mm, flutes %g mm long",
                  tool_text(id, t).c_str(), t.flutes, t.helix_deg, t.stickout_mm, t.flute_length_mm);
    p.emplace_back("tool", buf);
  }
  p.emplace_back("tool library", j.physics.tools.file);
  p.emplace_back("material", j.material);
  p.emplace_back("stock", j.stock_spec);
  for (const EarlierOp& e : j.given.stock_from) p.emplace_back("stock from", earlier_text(e));
  p.emplace_back("part model", j.part_spec.empty() ? "none (normals fitted through the path, or from the travel)" : j.part_spec);
  p.emplace_back("tolerance", report_number(j.settings.tolerance_mm) + " mm");
  p.emplace_back("deflex", std::string(DEFLEX_VERSION " (git ") + revision() + ")");
  p.emplace_back("date", report::utc_now());
  p.emplace_back("command", command);
  return p;
}

namespace detail {

void print_plausibility(const Run& j, const compensate::Plausibility& pl, Io& io) {
  Diagnostics diags = io.diagnostics(0);
  std::vector<std::uint32_t> lines;
  for (const compensate::Finding& f : pl.findings) lines.push_back(f.line);
  const auto text = lines_of_file(j, lines);
  for (const compensate::Finding& f : pl.findings)
    diags.report(Severity::warning, text.at(f.line), f.line, 1, f.message + " [" + f.kind + "]");
}

report::Json spindle_json(const report::RunFigures& f, const profile::SpindleRating& r) {
  report::Json rating;
  if (r.set) rating = {{"max_rpm", r.max_rpm}, {"source", r.source}, {"S6", r.s6.has_value()}};
  return {{"peak_power_kW", report::fixed(f.peak_power_kW, 4)}, {"peak_torque_Nm", report::fixed(f.peak_torque_Nm, 3)},
          {"rating", std::move(rating)}};
}

report::Json stability_json(const report::RunFigures& f) {
  return {{"checked_points", f.stability_checked}, {"points_above_limit", f.above_limit},
          {"worst_ap_over_limit", report::fixed(f.worst_ap_over_limit, 4)}};
}

report::Json warnings_json(const compensate::Plausibility& pl) {
  report::Json a = report::Json::array();
  for (const compensate::Finding& f : pl.findings)
    a.push_back({{"kind", f.kind}, {"count", f.count}, {"worst", report::fixed(f.worst, 4)},
                 {"limit", report::fixed(f.limit, 4)}, {"tool", f.tool}, {"line", f.line},
                 {"line_count", f.line_count}, {"lines", f.lines},
                 {"message", name_settings(f.message, {})}});  // settings by keyword, as the job names them
  return a;
}

}  // namespace detail
}  // namespace deflex::job
