#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <unistd.h>

#include "deflex/cli/command.hpp"
#include "signals.hpp"
#include "terminal_line.hpp"

int main(int argc, char** argv) {
  std::ios::sync_with_stdio(false);
  deflex::cli::remove_temporaries_on_signals();
  std::vector<std::string> args(argv + 1, argv + argc);
  deflex::cli::Io io{{std::cin, std::cout, std::cerr}};
  io.err_is_terminal = ::isatty(2);
  deflex::cli::TerminalLine line(std::cerr.rdbuf());
  if (io.err_is_terminal) {
    std::cerr.rdbuf(&line);
    io.line = &line;
  }
  int rc = deflex::cli::run(args, io);
  if (io.line) line.show("");
  // A failed write to standard output (a full disk, a closed descriptor) is
  // lost data: an I/O error, never exit 0.
  std::cout.flush();
  if (!std::cout || std::fflush(stdout) != 0) {
    std::cerr << "deflex: error: writing to standard output failed: " << std::strerror(errno ? errno : EIO) << "\n";
    return 4;
  }
  return rc;
}
