// deflex tools import FILE [-o OUT]: a Fusion 360 JSON or LinuxCNC .tbl tool
// library as deflex YAML (stiffness/tool_import.hpp).
#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stiffness/tool_import.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::cli {

int cmd_tools(const std::vector<std::string>& args, Io& io) {
  std::string output;
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")(
      "output,o", po::value(&output), "write the YAML here (atomically); default stdout");
  std::vector<std::string> words;
  parse_with_files(args, desc, words, 2);
  if (help || words.empty()) {
    print_help(io.out, "deflex tools import FILE.json|FILE.tbl [-o tools.yaml]",
               "Converts a Fusion 360 / HSM tool library (JSON export) or a LinuxCNC tool table\n"
               "(.tbl) into a deflex tool library (YAML). Flat, ball and bull-nose end mills are\n"
               "converted; any other tool type is named on standard error and skipped, never\n"
               "guessed. What the library does not give (helix angle; for a tool table the type,\n"
               "flutes, flute length and stick-out) takes a stated default, written as a YAML\n"
               "comment on its line: review them. --tool-file reads both formats directly too.\n",
               desc);
    return help ? 0 : static_cast<int>(Exit::usage);
  }
  if (words[0] != "import" || words.size() != 2) throw Error(ErrorKind::settings, "tools: usage: deflex tools import FILE [-o OUT]");
  if (!stiffness::is_foreign_tool_library(words[1]))
    throw Error(ErrorKind::settings, "tools import: " + words[1] + " is neither .json (Fusion 360) nor .tbl (LinuxCNC)");
  if (!output.empty() && output != "-") writer::check_output_path(output, words[1]);
  const stiffness::ImportedLibrary imp = stiffness::import_tool_library(words[1]);
  // What was written must load as a library: the same check --tool-file makes.
  (void)stiffness::parse_tool_library(imp.yaml, output.empty() ? words[1] : output);
  for (const std::string& s : imp.skipped) io.info() << words[1] << ": note: skipped " << s << "\n";
  io.err << words[1] << ": " << imp.format << ": " << plural(imp.tools, "tool") << " converted, " << imp.skipped.size()
         << " skipped\n";
  if (output.empty() || output == "-") io.out << imp.yaml;
  else writer::write_file_atomically(output, words[1], [&](std::ostream& o) { o << imp.yaml; });
  return 0;
}

}  // namespace deflex::cli
