// The setup of a run (setup.hpp): config, machine, dialect, libraries, material.
#include "deflex/job/setup.hpp"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <ostream>
#include <sys/stat.h>

#include "deflex/diag/plural.hpp"
#include "deflex/force/material.hpp"
#include "deflex/gcode/reader.hpp"
#include "deflex/profile/search.hpp"
#include "deflex/profile/yaml.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::job {

Setup resolve(const ReadSettings& r) {
  Setup s;
  s.config = profile::load_config(r.config);
  std::string machine = !r.machine.empty() ? r.machine : s.config.machine;
  if (!machine.empty()) s.machine = profile::load_machine(machine);
  // Its holder: and stiffness: sections too, so a typo there is found by every
  // command, not only by the ones that compute deflections.
  if (s.machine) stiffness::parse_machine_stiffness(s.machine->root, s.machine->file);
  std::string dialect = !r.dialect.empty() ? r.dialect
                        : !s.config.dialect.empty() ? s.config.dialect
                        : s.machine ? s.machine->dialect : "fanuc";
  s.dialect = profile::load_dialect(dialect);
  s.strict = r.strict;
  s.max_errors = r.max_errors >= 0 ? r.max_errors : s.config.max_errors;
  if (r.block_delete != "on" && r.block_delete != "off")
    throw Error(ErrorKind::settings, "{block_delete} takes on or off");
  s.block_delete_switch = r.block_delete == "on";
  if (r.max_blocks == 0) throw Error(ErrorKind::settings, "{max_blocks} must be at least 1");
  s.max_blocks = r.max_blocks;
  return s;
}

interp::Options Setup::interp() const {
  interp::Options o;
  o.dialect = dialect;
  o.machine = machine ? &*machine : nullptr;
  o.block_delete_switch = block_delete_switch;
  o.max_blocks = max_blocks;
  o.repeated_lines = repeated_lines.get();
  // Shared by the copies of the options (the safety check reads back on another thread).
  struct Cache {
    std::mutex mu;
    std::optional<stiffness::ToolLibrary> lib;
  };
  auto lib = std::make_shared<Cache>();
  const std::string file = tool_library_path(tool_file, config);
  const profile::MachineProfile* m = o.machine;
  o.cutter_radius_mm = [lib, file, m](int d) -> std::optional<double> {
    if (m) {
      auto it = m->tool_offsets.find(d);
      if (it != m->tool_offsets.end()) return it->second.radius_mm + it->second.wear_mm;
    }
    std::lock_guard<std::mutex> hold(lib->mu);
    if (!lib->lib) lib->lib = stiffness::load_tool_library(file);
    auto t = lib->lib->tools.find("T" + std::to_string(d));
    if (t == lib->lib->tools.end()) return std::nullopt;
    return t->second.diameter_mm / 2;
  };
  return o;
}

void refuse_output_onto_input(const std::vector<std::string>& inputs) {
  struct stat out {};
  if (::fstat(1, &out) != 0 || !S_ISREG(out.st_mode)) return;  // a terminal, a pipe: nothing to overwrite
  for (const std::string& f : inputs) {
    struct stat in {};
    if (f.empty() || (f == "-" ? ::fstat(0, &in) : ::stat(f.c_str(), &in)) != 0) continue;
    if (in.st_dev != out.st_dev || in.st_ino != out.st_ino) continue;
    const std::string name = f == "-" ? std::string("<stdin>") : f;
    // `>` truncates the file before deflex starts: what it held is gone already.
    throw Error(ErrorKind::settings, name + ": error: input file is output file (standard output is redirected to it)" +
                                 (in.st_size == 0 ? std::string("; the shell emptied it before deflex ran: "
                                                                "restore it (a backup, or export it again)")
                                                  : std::string()) +
                                 "; write the output to another file, or with -o OUT");
  }
}

std::string config_string(const profile::Config& c, const char* key) {
  if (const YAML::Node root = yaml::node(c.root); root && root[key]) return yaml::text(root[key], key, c.file);
  return {};
}

std::string config_path(const profile::Config& c, const char* key) {
  std::string v = config_string(c, key);
  if (v.empty() || std::filesystem::path(v).is_absolute() || v.starts_with("box:")) return v;
  const std::string here = (std::filesystem::path(c.file).parent_path() / v).lexically_normal().string();
  // A copy of the installed config (in ~/.config/deflex or /etc/deflex) keeps
  // naming the installed libraries: samples/tools.yaml from the data folder.
  std::error_code ec;
  if (!std::filesystem::exists(here, ec)) {
    const std::filesystem::path installed = std::filesystem::path(profile::data_dir()) / v;
    if (std::filesystem::exists(installed, ec)) return installed.lexically_normal().string();
  }
  return here;
}
double config_number(const profile::Config& c, const char* key, double dflt) {
  if (const YAML::Node root = yaml::node(c.root); root && root[key]) return yaml::number(root[key], key, c.file);
  return dflt;
}

std::string tool_library_path(const std::string& option, const profile::Config& c) {
  if (!option.empty()) return option;
  const std::string f = config_path(c, "tool_file");
  return f.empty() ? default_library("samples/tools.yaml") : f;
}

std::string material_library_path(const std::string& option, const profile::Config& c) {
  if (!option.empty()) return option;
  const std::string f = config_path(c, "material_file");
  return f.empty() ? default_library("samples/materials.yaml") : f;
}

void report_part_gaps(const compensate::PartGaps& g, const SourceText& src, double gap_mm, Diagnostics& diags) {
  report_part_gaps(g, [&src](std::uint32_t) -> SourceText { return src; }, gap_mm, diags);
}

void report_part_gaps(const compensate::PartGaps& g, const std::function<SourceText(std::uint32_t)>& line_of,
                      double gap_mm, Diagnostics& diags) {
  auto lines = [](const std::vector<std::uint32_t>& l) {
    std::string s;
    for (std::size_t i = 0; i < l.size() && i < 12; ++i) s += (i ? ", " : "") + std::to_string(l[i]);
    return l.size() > 12 ? s + ", ..." : s;
  };
  char buf[256];
  if (g.overcut.points) {
    // The depth of a cutter through more than half the part is only a lower bound (part::Contact).
    const char* bound = g.overcut.worst_at_least ? "at least " : "";
    const char* why = g.overcut.worst_at_least ? " (through more than half the part's thickness there)" : "";
    std::snprintf(buf, sizeof buf, "the programmed cutter cuts %s%.4f mm into the part model here%s, the deepest of %s "
                  "beyond the %.4f mm gap", bound, g.overcut.worst_mm, why, plural(g.overcut.points, "CL point").c_str(),
                  gap_mm);
    diags.report(Severity::warning, line_of(g.overcut.worst_line), g.overcut.worst_line, 1,
                 std::string(buf) + " (" + plural(g.overcut.lines.size(), "line") + ": " + lines(g.overcut.lines) + ")");
  }
  if (g.standoff.points) {
    std::snprintf(buf, sizeof buf, "the programmed cutter stands %.4f mm off a face of the part model here, the largest of %s "
                  "beyond the %.4f mm gap", g.standoff.worst_mm, plural(g.standoff.points, "CL point").c_str(), gap_mm);
    diags.report(Severity::warning, line_of(g.standoff.worst_line), g.standoff.worst_line, 1,
                 std::string(buf) + " (" + plural(g.standoff.lines.size(), "line") + ": " + lines(g.standoff.lines) + ")");
  }
}

std::string default_library(const char* name) { return profile::data_dir() + "/" + name; }

force::Coefficients coefficients_of(const MaterialSettings& a, const std::string& fallback_material,
                                    std::string* described) {
  const bool by_k = a.kt || a.kr || a.ka;
  const bool edge = a.kte || a.kre || a.kae;
  if (!a.material.empty() && (by_k || edge))
    throw Error(ErrorKind::settings, "give either {material} or {kt_N_per_mm2}/{kr_N_per_mm2}/{ka_N_per_mm2}, not both");
  const std::string material = !a.material.empty() ? a.material : by_k ? std::string() : fallback_material;
  if (material.empty() && !by_k) throw Error(ErrorKind::settings, "give {material} M or the coefficients {kt_N_per_mm2} {kr_N_per_mm2} {ka_N_per_mm2}");
  if (!material.empty()) {
    const std::string file = a.material_file.empty() ? default_library("samples/materials.yaml") : a.material_file;
    const force::MaterialLibrary lib = force::load_material_library(file);
    const force::MaterialEntry& m = force::find_material(lib, material);
    if (described) *described = m.name + " (" + file + (m.source.empty() ? "" : "; source: " + m.source) + ")";
    return m.k;
  }
  if (!a.material_file.empty()) throw Error(ErrorKind::settings, "{material_file} needs {material}");
  if (!a.kt || !a.kr || !a.ka) throw Error(ErrorKind::settings, "{kt_N_per_mm2}, {kr_N_per_mm2} and {ka_N_per_mm2} go together");
  force::Coefficients k;
  k.Ktc_N_per_mm2 = *a.kt;
  k.Krc_N_per_mm2 = *a.kr;
  k.Kac_N_per_mm2 = *a.ka;
  k.Kte_N_per_mm = a.kte.value_or(0);
  k.Kre_N_per_mm = a.kre.value_or(0);
  k.Kae_N_per_mm = a.kae.value_or(0);
  if (described) {
    char buf[240];
    std::snprintf(buf, sizeof buf, "given: K_tc %g, K_rc %g, K_ac %g N/mm^2; K_te %g, K_re %g, K_ae %g N/mm",
                  k.Ktc_N_per_mm2, k.Krc_N_per_mm2, k.Kac_N_per_mm2, k.Kte_N_per_mm, k.Kre_N_per_mm, k.Kae_N_per_mm);
    *described = buf;
  }
  return k;
}

std::uint32_t piece_lines() {
  const char* v = std::getenv("DEFLEX_CHUNK_LINES");
  if (!v || !*v) return gcode::kPieceLines;
  std::uint32_t n = 0;
  const char* end = v + std::strlen(v);
  const auto r = std::from_chars(v, end, n);
  if (r.ec != std::errc() || r.ptr != end)
    throw Error(ErrorKind::settings, std::string("DEFLEX_CHUNK_LINES must be a whole number of lines (0: read whole), not '") + v + "'");
  return n;
}

Setup resolve_with_machine(const ReadSettings& r) {
  Setup s = resolve(r);
  if (!s.machine) throw Error(ErrorKind::settings, "a machine profile is needed ({machine}, or machine: in config.yaml)");
  return s;
}

std::string stock_spec(const std::string& given, const profile::Config& cfg) {
  const std::string s = !given.empty() ? given : config_path(cfg, "stock");
  if (s.empty()) throw Error(ErrorKind::settings, "no stock: give {stock} box:X0,Y0,Z0,X1,Y1,Z1 or a solid file (or stock: in config.yaml)");
  return s;
}

}  // namespace deflex::job
