// deflex list WHAT: the names a command line can give (--machine, --dialect,
// --tool, --material), found where the commands find them: for the user, and
// for the bash completion (packaging/deflex.bash-completion).
#include <filesystem>
#include <set>

#include "common.hpp"
#include "deflex/force/material.hpp"
#include "deflex/profile/search.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::cli {

int cmd_list(const std::vector<std::string>& args, Io& io) {
  std::string config, tool_file, material_file;
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")(
      "config", po::value(&config), "config file (default: the search order of deflex --help)")(
      "tool-file", po::value(&tool_file), "tool library (default: config tool_file, else the installed one)")(
      "material-file", po::value(&material_file),
      "material library (default: config material_file, else the installed one)");
  std::vector<std::string> words;
  parse_with_files(args, desc, words, 1, true);
  if (help || words.empty()) {
    print_help(io.out, "deflex list machines|dialects|tools|materials",
               "Prints the names a command line can give, one per line: machine profiles (in the\n"
               "folders of the search order, the first of a name wins), the built-in dialects, the\n"
               "tools of the tool library and the materials of the material library in use.\n"
               "Nothing found is an error (exit 3) that names the folders or file looked in.\n",
               desc);
    return help ? 0 : static_cast<int>(Exit::usage);
  }
  const std::string& what = words[0];
  // An empty list is no answer (the installed data missing, a binary run
  // outside its install): say where deflex looked, as a configuration error.
  std::size_t n = 0;
  auto print = [&](const std::string& name) {
    io.out << name << "\n";
    ++n;
  };
  std::string looked;
  if (what == "machines") {
    std::set<std::string> seen;
    for (const std::string& d : profile::machine_folders()) {
      looked += (looked.empty() ? "" : ", ") + (std::filesystem::path(d).is_relative() ? "./" + d : d);
      std::error_code ec;
      for (const auto& e : std::filesystem::directory_iterator(d, ec))
        if (e.path().extension() == ".yaml" && seen.insert(e.path().stem().string()).second) print(e.path().stem().string());
    }
  } else if (what == "dialects") {
    for (const std::string& d : profile::dialect_names()) print(d);
  } else if (what == "tools") {
    const profile::Config c = profile::load_config(config);
    looked = tool_library_path(tool_file, c);
    for (const auto& [id, t] : stiffness::load_tool_library(looked).tools) print(id);
  } else if (what == "materials") {
    looked = material_library_path(material_file, profile::load_config(config));
    for (const force::MaterialEntry& m : force::load_material_library(looked).entries) print(m.name);
  } else {
    throw Error(ErrorKind::settings, "list: machines, dialects, tools or materials, not '" + what + "'");
  }
  if (n == 0) throw Error(ErrorKind::config, "list: no " + what + " found (looked in " + looked + ")");
  return 0;
}

}  // namespace deflex::cli
