// deflex list WHAT: the names a command line can give (--machine, --dialect,
// --tool, --material), found where the commands find them: for the user, and
// for the bash completion (packaging/deflex.bash-completion).
#include "common.hpp"
#include "deflex/job/libraries.hpp"

namespace deflex::cli {

int cmd_list(const std::vector<std::string>& args, Io& io) {
  job::NamesSettings ns;
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")(
      "config", po::value(&ns.config), "config file (default: the search order of deflex --help)")(
      "tool-file", po::value(&ns.tool_file), "tool library (default: config tool_file, else the installed one)")(
      "material-file", po::value(&ns.material_file),
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
  if (what == "machines") ns.what = job::NameKind::machines;
  else if (what == "dialects") ns.what = job::NameKind::dialects;
  else if (what == "tools") ns.what = job::NameKind::tools;
  else if (what == "materials") ns.what = job::NameKind::materials;
  else throw Error(ErrorKind::settings, "list: machines, dialects, tools or materials, not '" + what + "'");
  const job::Names found = job::names(ns);
  // An empty list is no answer (the installed data missing, a binary run
  // outside its install): say where deflex looked, as a configuration error.
  if (found.names.empty()) throw Error(ErrorKind::config, "list: no " + what + " found (looked in " + found.looked + ")");
  for (const std::string& name : found.names) io.out << name << "\n";
  return 0;
}

}  // namespace deflex::cli
