#include "common.hpp"

#include <ostream>

namespace deflex::cli {

void add_read_options(po::options_description& d, ReadOptions& r, bool with_machine) {
  d.add_options()
    ("dialect", po::value(&r.dialect), "control dialect: fanuc (default), haas, linuxcnc, siemens-iso, "
                                       "heidenhain-iso, or a dialect .yaml file; overrides the machine's")
    ("config", po::value(&r.config), "config file (default: ./config.yaml, else the one in the source tree)")
    ("max-errors", po::value(&r.max_errors), "stop after N errors (0: no limit; default from config, 20)")
    ("block-delete", po::value(&r.block_delete)->default_value("off"),
     "block-delete switch: off executes '/' blocks (never compensated), on skips them");
  if (with_machine)
    d.add_options()("machine", po::value(&r.machine), "machine profile: a name in samples/machines/ or a .yaml file");
}

Setup resolve(const ReadOptions& r) {
  Setup s;
  s.config = profile::load_config(r.config);
  std::string machine = !r.machine.empty() ? r.machine : s.config.machine;
  if (!machine.empty()) s.machine = profile::load_machine(machine);
  std::string dialect = !r.dialect.empty() ? r.dialect
                        : !s.config.dialect.empty() ? s.config.dialect
                        : s.machine ? s.machine->dialect : "fanuc";
  s.dialect = profile::load_dialect(dialect);
  s.max_errors = r.max_errors >= 0 ? r.max_errors : s.config.max_errors;
  if (r.block_delete != "on" && r.block_delete != "off")
    throw Error(Exit::usage, "--block-delete takes on or off");
  s.block_delete_switch = r.block_delete == "on";
  return s;
}

po::variables_map parse(const std::vector<std::string>& args, const po::options_description& desc,
                        const po::positional_options_description& pos) {
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(desc).positional(pos).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw Error(Exit::usage, e.what());
  }
  return vm;
}

void parse_with_files(const std::vector<std::string>& args, const po::options_description& desc,
                      std::vector<std::string>& files, int max_files) {
  po::options_description all;
  all.add(desc).add_options()("file", po::value(&files));
  po::positional_options_description pos;
  pos.add("file", max_files);
  parse(args, all, pos);
}

void print_help(std::ostream& out, const std::string& usage, const std::string& text,
                const po::options_description& desc) {
  out << "usage: " << usage << "\n\n" << text << "\n" << desc << "\n";
}

}  // namespace deflex::cli
