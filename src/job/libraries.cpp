// job::import_tools() and job::names() (libraries.hpp).
#include "deflex/job/libraries.hpp"

#include <filesystem>
#include <ostream>
#include <set>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/force/material.hpp"
#include "deflex/job/setup.hpp"
#include "deflex/profile/profile.hpp"
#include "deflex/profile/search.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stiffness/tool_import.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::job {
namespace {

// The profiles (*.yaml) of the machine folders, the first of a name winning,
// as the runs find a machine by name (profile::find_machine).
Names machine_names() {
  Names r;
  std::set<std::string> seen;
  for (const std::string& d : profile::machine_folders()) {
    r.looked += (r.looked.empty() ? "" : ", ") + (std::filesystem::path(d).is_relative() ? "./" + d : d);
    std::error_code ec;  // a folder that is not there has no profiles
    for (const auto& e : std::filesystem::directory_iterator(d, ec))
      if (e.path().extension() == ".yaml" && seen.insert(e.path().stem().string()).second)
        r.names.push_back(e.path().stem().string());
  }
  return r;
}

}  // namespace

ToolImportResult import_tools(const ToolImportSettings& s, Io& io) {
  if (!stiffness::is_foreign_tool_library(s.file))
    throw Error(ErrorKind::settings, "tools import: " + s.file + " is neither .json (Fusion 360) nor .tbl (LinuxCNC)");
  const bool write = !s.output.empty() && s.output != "-";
  if (write) writer::check_output_path(s.output, s.file);
  stiffness::ImportedLibrary imp = stiffness::import_tool_library(s.file);
  // What is written must load as a library: the same check a run's tool library gets.
  (void)stiffness::parse_tool_library(imp.yaml, s.output.empty() ? s.file : s.output);
  for (const std::string& skipped : imp.skipped) io.info() << s.file << ": note: skipped " << skipped << "\n";
  if (write) writer::write_file_atomically(s.output, s.file, [&](std::ostream& o) { o << imp.yaml; });
  return {imp.format, imp.tools, std::move(imp.skipped), std::move(imp.yaml)};
}

Names names(const NamesSettings& s) {
  Names r;
  switch (s.what) {
    case NameKind::machines:
      return machine_names();
    case NameKind::dialects:
      r.names = profile::dialect_names();
      break;
    case NameKind::tools:
      r.looked = tool_library_path(s.tool_file, profile::load_config(s.config));
      for (const auto& [id, t] : stiffness::load_tool_library(r.looked).tools) r.names.push_back(id);
      break;
    case NameKind::materials:
      r.looked = material_library_path(s.material_file, profile::load_config(s.config));
      for (const force::MaterialEntry& m : force::load_material_library(r.looked).entries) r.names.push_back(m.name);
      break;
  }
  return r;
}

}  // namespace deflex::job
