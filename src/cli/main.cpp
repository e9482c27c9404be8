#include <iostream>
#include <unistd.h>

#include "deflex/cli/command.hpp"

int main(int argc, char** argv) {
  std::ios::sync_with_stdio(false);
  std::vector<std::string> args(argv + 1, argv + argc);
  deflex::cli::Io io{std::cin, std::cout, std::cerr, static_cast<bool>(::isatty(2))};
  int rc = deflex::cli::run(args, io);
  std::cout.flush();
  return rc;
}
