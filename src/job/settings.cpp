// The job file (settings.hpp): the same run as the command line; the
// command line overrides it.
#include "deflex/job/settings.hpp"

#include <filesystem>
#include <functional>

#include "deflex/job/setup.hpp"
#include "deflex/profile/yaml.hpp"
#include "deflex/stiffness/workpiece.hpp"

namespace deflex::job {
namespace fs = std::filesystem;
namespace {

// `stock_from:` of a job: a list of paths or {program: P, tool_file: T} maps,
// in the order they ran; `path` makes a job's path relative to its folder.
// Throws a config Error at the line and column of a bad entry.
std::vector<EarlierOp> earlier_of_job(const yaml::Map& job, const std::function<std::string(const std::string&)>& path) {
  const YAML::Node list = job.get("stock_from");
  if (!list.IsSequence())
    job.fail("stock_from", "stock_from is a list of programs, in the order they ran: a path, or {program: P, "
                           "tool_file: T} for a program whose tools are in a library of its own");
  std::vector<EarlierOp> ops;
  for (const YAML::Node& n : list) {
    if (!n.IsMap()) {
      ops.push_back({path(yaml::text(n, "stock_from", job.file())), ""});
      continue;
    }
    const yaml::Map e(n, "stock_from entry", job.file(), {"program", "tool_file"});
    ops.push_back({path(e.text("program")), e.has("tool_file") ? path(e.text("tool_file")) : ""});
  }
  return ops;
}

// `fixture:` of a job: one box:X0,Y0,Z0,X1,Y1,Z1, or a list of them, each
// parsed here to fail at its line (in a flow list [..] an unquoted box's
// commas split it into items).
std::vector<std::string> fixtures_of_job(const yaml::Map& job) {
  const YAML::Node n = job.get("fixture");
  std::vector<YAML::Node> items;
  if (n.IsSequence())
    for (const YAML::Node& b : n) items.push_back(b);
  else
    items.push_back(n);
  std::vector<std::string> boxes;
  for (const YAML::Node& b : items) {
    boxes.push_back(yaml::text(b, "fixture", job.file()));
    try {
      stiffness::parse_fixture(boxes.back());
    } catch (const Error& e) {
      job.fail(b, std::string(e.what()) + " (quote a box in a [..] list: 'box:0,0,0,1,1,1')");
    }
  }
  return boxes;
}

}  // namespace

void apply_job_file(const std::string& file, Settings& a, std::vector<std::string>& files) {
  const YAML::Node root = yaml::load_text(yaml::read_file(file), file);
  const yaml::Map m(root, "job", file,
                    {"program", "machine", "dialect", "tool_file", "tool", "material", "material_file", "stock",
                     "stock_from", "part", "fixture", "workpiece_mesh_mm", "workpiece_spacing_mm", "workpiece_stages", "tolerance_mm", "gain", "output", "report", "measured", "probe_program"});
  const fs::path dir = fs::path(file).parent_path();
  // A path of the job is relative to the job's folder (the file sits beside
  // the program); a box, a built-in name or an absolute path is taken as is.
  auto path = [&](const std::string& p) { return p.empty() || fs::path(p).is_absolute() ? p : (dir / p).string(); };
  auto text = [&](const char* key, std::string& dst, bool is_path) {
    if (dst.empty() && m.has(key)) dst = is_path ? path(m.text(key)) : m.text(key);
  };
  if (files.empty() && m.has("program")) files.push_back(path(m.text("program")));
  const std::string machine = m.has("machine") ? m.text("machine") : "";
  if (a.read.machine.empty() && !machine.empty())
    a.read.machine = machine.find('/') != std::string::npos || machine.ends_with(".yaml") ? path(machine) : machine;
  text("dialect", a.read.dialect, false);
  text("tool_file", a.tool_file, true);
  text("tool", a.tool, false);
  text("material", a.material.material, false);
  text("material_file", a.material.material_file, true);
  if (a.stock.empty() && m.has("stock")) {
    const std::string st = m.text("stock");
    a.stock = st.rfind("box:", 0) == 0 ? st : path(st);
  }
  if (a.stock_from.empty() && m.has("stock_from")) a.stock_from = earlier_of_job(m, path);
  text("part", a.part.part, true);
  Workholding& w = a.workholding;
  if (w.fixtures.empty() && m.has("fixture")) w.fixtures = fixtures_of_job(m);
  if (w.mesh_mm == 0 && m.has("workpiece_mesh_mm")) w.mesh_mm = m.number("workpiece_mesh_mm", yaml::Range::positive());
  if (w.spacing_mm == 0 && m.has("workpiece_spacing_mm"))
    w.spacing_mm = m.number("workpiece_spacing_mm", yaml::Range::positive());
  if (w.stages == 0 && m.has("workpiece_stages"))
    w.stages = static_cast<int>(m.integer("workpiece_stages", 0, kMaxWorkpieceStages));
  if (!a.tolerance_mm && m.has("tolerance_mm")) a.tolerance_mm = m.number("tolerance_mm", yaml::Range::positive());
  if (!a.gain && m.has("gain")) a.gain = m.number("gain", yaml::Range::between(0, 2));
  text("output", a.output, true);
  text("report", a.report_dir, true);
  text("measured", a.measured, true);
  text("probe_program", a.probe_program, true);
  refuse_output_onto_input(input_files(a, files));  // the files the job names
}

std::vector<std::string> input_files(const Settings& s, const std::vector<std::string>& programs) {
  std::vector<std::string> inputs = programs;
  for (const EarlierOp& e : s.stock_from) inputs.insert(inputs.end(), {e.program, e.tool_file});
  inputs.insert(inputs.end(), {s.stock, s.part.part, s.tool_file, s.material.material_file, s.reference});
  return inputs;
}

}  // namespace deflex::job
