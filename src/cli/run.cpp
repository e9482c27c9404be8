// `deflex COMMAND ...`: dispatch, top-level help, and the mapping of failures
// to exit codes.
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>

#include "deflex/cli/command.hpp"
#include "deflex/cli/exit.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/diag/parallel_trace.hpp"
#include "deflex/profile/search.hpp"
#include "deflex/version.hpp"

namespace deflex::cli {
namespace {

struct Command {
  const char* name;
  CommandFn fn;
  const char* summary;
};

const Command kCommands[] = {
  {"compensate", cmd_compensate, "move cutting points so the deflected tool lands on the programmed surface"},
  {"simulate", cmd_simulate, "predict the surface error of a program (optionally against a reference)"},
  {"compare", cmd_compare, "simulate several programs for one part on the same stock: a table of figures"},
  {"path", cmd_path, "print the tool path: one line per motion, end point in mm (work frame)"},
  {"check", cmd_check, "report every diagnostic of a program and check travel limits"},
  {"diff", cmd_diff, "pair the motions of two programs and measure what moved"},
  {"rewrite", cmd_rewrite, "read, interpret and write a program back (byte-identical; atomic -o)"},
  {"rough", cmd_rough, "a roughing program that leaves an allowance over what a finishing program cuts"},
  {"testcut", cmd_testcut, "a calibration test cut (walls, down-milling) and its plan, for the stiffness fit"},
  {"probe", cmd_probe, "the on-machine probing program of a test cut's walls (G38.2 or G31 + DPRNT)"},
  {"fit", cmd_fit, "fit the machine profile's stiffness and force scale to a measured cut"},
  {"stock", cmd_stock, "the stock after earlier programs: a .zmap for the next run, or a closed STL for CAM"},
  {"list", cmd_list, "the names of machines, dialects, tools and materials a command line can give"},
  {"tools", cmd_tools, "import a Fusion 360 (JSON) or LinuxCNC (.tbl) tool library as deflex YAML"},
  {"stiffness", cmd_stiffness, "compliance C(h) of tool + holder + spindle (beam or solid FEM)"},
  {"forces", cmd_forces, "cutting forces over one revolution for one engagement"},
  {"calibrate", cmd_calibrate, "fit cutting/edge coefficients from slot-test forces"},
  {"stability", cmd_stability, "stability lobes (chatter): the largest stable depth of cut against speed"},
};

void top_help(std::ostream& out) {
  out << "deflex " DEFLEX_VERSION " - compensates milling-tool deflection in Fanuc/ISO programs\n\n"
         "usage: deflex COMMAND [OPTIONS] [FILE...]      deflex COMMAND --help\n\n"
         "commands:\n";
  for (const Command& c : kCommands) {
    out << "  " << c.name;
    for (std::size_t i = std::strlen(c.name); i < 12; ++i) out << ' ';
    out << c.summary << "\n";
  }
  out << "\nA FILE of '-' is standard input; programs go to standard output unless -o is\n"
         "given, and -o FILE is written atomically, never over the input.\n"
         "Diagnostics go to standard error as FILE:LINE:COL: error|warning: MESSAGE.\n"
         "Units: lengths in mm, forces in N, compliance in mm/N, angles in degrees.\n"
         "Configuration: --config FILE, else the first of ./deflex.yaml, ./config.yaml,\n"
         "$XDG_CONFIG_HOME/deflex/config.yaml, /etc/deflex/config.yaml and the installed\n"
         "defaults (deflex --version names the one in use).\n\n"
         "exit codes:\n"
         "  0   success (check: clean; diff: only coordinates of motion blocks differ)\n"
         "  1   input error in a program (diff: the programs differ in more than coordinates)\n"
         "  2   usage error on the command line\n"
         "  3   configuration error (config.yaml, machine profile, dialect, tool/material library;\n"
         "      list: nothing found where deflex looks)\n"
         "  4   I/O error (a file could not be read or written)\n"
         "  70  internal error (a bug in deflex: please report it)\n"
         "  129, 130, 143  ended by SIGHUP, SIGINT or SIGTERM: temporary files removed\n";
}

// The output options every command takes, anywhere after its name: taken out
// here, so no command parses them (common.cpp's print_help lists them).
std::vector<std::string> take_output_options(const std::vector<std::string>& args, Io& io) {
  std::vector<std::string> rest;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--") {  // the rest are files (a file named -v)
      rest.insert(rest.end(), args.begin() + static_cast<std::ptrdiff_t>(i), args.end());
      break;
    }
    if (a == "-q" || a == "--quiet") {
      io.quiet = true;
    } else if (a == "-v" || a == "--verbose") {
      io.verbose = true;
      diag::set_parallel_trace(true);  // -v shows the stages' parallelism
    } else if (a == "--progress" || a.starts_with("--progress=")) {
      std::string when;
      if (a == "--progress") {
        if (i + 1 == args.size()) throw Error(ErrorKind::settings, "--progress needs auto, always or never");
        when = args[++i];
      } else {
        when = a.substr(11);
      }
      if (when == "auto") io.progress = ProgressWhen::automatic;
      else if (when == "always") io.progress = ProgressWhen::always;
      else if (when == "never") io.progress = ProgressWhen::never;
      else throw Error(ErrorKind::settings, "--progress must be auto, always or never, not '" + when + "'");
    } else {
      rest.push_back(a);
    }
  }
  if (io.quiet && io.verbose) throw Error(ErrorKind::settings, "--quiet and --verbose contradict each other");
  return rest;
}

// The data folder in use, or where deflex looked when there is none (a
// binary run outside its install): never a folder that does not exist.
std::string data_line() {
  const std::string d = profile::data_dir();
  std::error_code ec;
  if (std::filesystem::is_directory(d, ec)) return d;
  std::string looked;
  for (const std::string& c : profile::data_dir_candidates()) looked += (looked.empty() ? "" : ", ") + c;
  return "none found (looked in " + looked + "; DEFLEX_DATA_DIR sets it)";
}

}  // namespace

int run(const std::vector<std::string>& argv, Io& io) {
  io.names = flag_of;  // the library's messages name settings by their flags
  try {
    if (argv.empty() || argv[0] == "--help" || argv[0] == "-h" || argv[0] == "help") {
      top_help(argv.empty() ? io.err : io.out);
      return argv.empty() ? static_cast<int>(Exit::usage) : 0;
    }
    if (argv[0] == "--version" || argv[0] == "-V") {
      io.out << "deflex " DEFLEX_VERSION " (git " << revision() << ")\n"
             << "data: " << data_line() << "\n"
             << "config: " << [] {
                  const std::string c = profile::find_config("");
                  return c.empty() ? std::string("none found (built-in defaults)") : c;
                }() << "\n";
      return 0;
    }
    for (const Command& c : kCommands)
      if (argv[0] == c.name)
        return c.fn(take_output_options(std::vector<std::string>(argv.begin() + 1, argv.end()), io), io);
    io.err << "deflex: error: unknown command '" << argv[0] << "' (see deflex --help)\n";
    return static_cast<int>(Exit::usage);
  } catch (const Error& e) {
    std::string w = e.message(io.names);
    // Messages that already carry a location keep it; others get the program name.
    if (w.find(": error: ") == std::string::npos) w = "deflex: error: " + w;
    io.err << w << (w.ends_with("\n") ? "" : "\n");
    return static_cast<int>(exit_code(e.kind()));
  } catch (const std::bad_alloc&) {
    io.err << "deflex: error: out of memory\n";
    return static_cast<int>(Exit::io);
  } catch (const std::exception& e) {
    io.err << "deflex: internal error: " << e.what() << "\n";
    return static_cast<int>(Exit::internal);
  }
}

}  // namespace deflex::cli
