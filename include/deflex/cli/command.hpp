// The subcommand interface. src/cli/ is the only place that knows
// Boost.Program_options; each subcommand parses its own arguments and runs
// the job API (deflex/job/).
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "deflex/job/io.hpp"

namespace deflex::cli {

// Output control (deflex COMMAND ... --quiet | --verbose, --progress=WHEN).
enum class ProgressWhen { automatic, always, never };

// Streams a command writes to (tests pass string streams), and how.
class TerminalLine;  // src/cli/terminal_line.hpp

struct Io : job::Io {
  bool err_is_terminal = false;  // --progress=auto: a progress line only on a terminal
  ProgressWhen progress = ProgressWhen::automatic;
  TerminalLine* line = nullptr;  // err's buffer on a terminal: the progress line drawn there
};

// The option that gives a setting the library names by `keyword`
// (diag/settings.hpp): the command line's name for it in messages.
std::string flag_of(std::string_view keyword);

// A subcommand: args are the words after the subcommand name. Returns the exit
// code (cli/exit.hpp); failures may also be thrown as deflex::Error.
using CommandFn = int (*)(const std::vector<std::string>& args, Io& io);

int cmd_path(const std::vector<std::string>& args, Io& io);
int cmd_check(const std::vector<std::string>& args, Io& io);
int cmd_diff(const std::vector<std::string>& args, Io& io);
int cmd_rewrite(const std::vector<std::string>& args, Io& io);
int cmd_stiffness(const std::vector<std::string>& args, Io& io);
int cmd_forces(const std::vector<std::string>& args, Io& io);
int cmd_stability(const std::vector<std::string>& args, Io& io);
int cmd_calibrate(const std::vector<std::string>& args, Io& io);
int cmd_compensate(const std::vector<std::string>& args, Io& io);
int cmd_simulate(const std::vector<std::string>& args, Io& io);
int cmd_compare(const std::vector<std::string>& args, Io& io);
int cmd_tools(const std::vector<std::string>& args, Io& io);
int cmd_list(const std::vector<std::string>& args, Io& io);
int cmd_stock(const std::vector<std::string>& args, Io& io);
int cmd_rough(const std::vector<std::string>& args, Io& io);
int cmd_fit(const std::vector<std::string>& args, Io& io);
int cmd_testcut(const std::vector<std::string>& args, Io& io);
int cmd_probe(const std::vector<std::string>& args, Io& io);

// Runs `deflex ARGS...` in-process (what main() does); used by golden tests.
int run(const std::vector<std::string>& argv, Io& io);

}  // namespace deflex::cli
