// `deflex tools import` and `deflex list` as calls: a foreign tool library
// converted to deflex's YAML, and the names a command line can give, found
// where the runs find them.
#pragma once
#include <string>
#include <vector>

#include "deflex/job/io.hpp"

namespace deflex::job {

struct ToolImportSettings {
  std::string file;    // a Fusion 360 JSON export (.json) or a LinuxCNC tool table (.tbl)
  std::string output;  // the YAML written here atomically; "" or "-": not written (the result holds it)
};

struct ToolImportResult {
  std::string format;                // what the file was read as ("Fusion 360 JSON", "LinuxCNC tool table")
  int tools = 0;                     // tools converted
  std::vector<std::string> skipped;  // one line each: which tool, why
  std::string yaml;                  // the deflex tool library, its defaults commented
};

// A settings Error for a file of neither format (by its extension) and an
// output that is the input, before anything is read; the YAML must load as a
// library (the check a run's tool library gets) before it is written. Each
// skipped tool is a note on io.info().
ToolImportResult import_tools(const ToolImportSettings& s, Io& io);

enum class NameKind { machines, dialects, tools, materials };

struct NamesSettings {
  NameKind what = NameKind::machines;
  std::string config;         // config.yaml ("": searched, profile/search.hpp)
  std::string tool_file;      // the tool library ("": config tool_file, else the installed one)
  std::string material_file;  // the material library ("": config material_file, else the installed one)
};

struct Names {
  std::vector<std::string> names;  // in the order found; a machine's first file of a name wins
  std::string looked;              // where: the machine folders, or the library file ("" for the built-in dialects)
};

// Machine profiles in the folders of the search order, the built-in
// dialects, the tools or the materials of the library in use. Nothing found
// is no error here: an empty list, with where it was looked for.
Names names(const NamesSettings& s);

}  // namespace deflex::job
