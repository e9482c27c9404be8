// Where deflex finds its files, installed or not, never in the source tree
// (README "Configuration"). The config file in use is the first of
//   --config FILE
//   ./deflex.yaml, ./config.yaml                (the folder deflex runs in)
//   $XDG_CONFIG_HOME/deflex/config.yaml         (~/.config when unset)
//   /etc/deflex/config.yaml
//   DATA/config.yaml                            (the installed defaults)
// and a machine profile named NAME (not a path) the first of NAME.yaml in
//   ./machines, ./samples/machines, $XDG_CONFIG_HOME/deflex/machines,
//   /etc/deflex/machines, DATA/samples/machines.
// DATA is $DEFLEX_DATA_DIR where set, else ../share/deflex beside the binary
// when it holds config.yaml (an install under any prefix), else the folder
// deflex was configured to install to (CMAKE_INSTALL_FULL_DATADIR/deflex). It
// mirrors a clone: config.yaml, postproc/ (the dialects, also compiled in),
// samples/ (machines, tools.yaml, materials.yaml, programs, stock, parts), so
// one config.yaml serves both.
#pragma once
#include <string>
#include <vector>

namespace deflex::profile {

std::string data_dir();
// The folders data_dir() looks at, in order: $DEFLEX_DATA_DIR alone where it is
// set, else share/deflex one to four folders above the file holding this
// code (the binary, a program linked with the library, Python's extension
// module), then the configured folder. None of them need exist (a binary
// copied out of its build tree has none).
std::vector<std::string> data_dir_candidates();
// The folders searched, in order, for a file `rel` of a user's configuration
// (".../deflex/" + rel beyond the current folder).
std::vector<std::string> config_candidates();
std::vector<std::string> machine_folders();
// The config file in use ("" when none exists: the built-in defaults).
std::string find_config(const std::string& given);
// A machine profile's file by name ("" when none).
std::string find_machine(const std::string& name);

}  // namespace deflex::profile
