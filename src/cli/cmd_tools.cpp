// deflex tools import FILE [-o OUT]: a Fusion 360 JSON or LinuxCNC .tbl tool
// library as deflex YAML (job::import_tools); here the options and the printing.
#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/job/libraries.hpp"

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
  const job::ToolImportResult imp = job::import_tools({words[1], output}, io);
  io.err << words[1] << ": " << imp.format << ": " << plural(imp.tools, "tool") << " converted, " << imp.skipped.size()
         << " skipped\n";
  if (output.empty() || output == "-") io.out << imp.yaml;
  return 0;
}

}  // namespace deflex::cli
