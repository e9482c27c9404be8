// The exit code of each failure class (listed in `deflex --help`). Only the CLI
// knows them: the library throws deflex::Error with an ErrorKind.
#pragma once
#include "deflex/diag/diagnostics.hpp"

namespace deflex::cli {

// Scripts and the documentation rely on these values: they never change.
enum class Exit : int {
  ok = 0,        // success; for check/diff: clean / only coordinates differ
  input = 1,     // the program (or a compared program) has errors / differs
  usage = 2,     // bad command line
  config = 3,    // config.yaml, machine profile, dialect or library error
  io = 4,        // a file could not be read or written
  internal = 70  // a bug in deflex (EX_SOFTWARE)
};

constexpr Exit exit_code(ErrorKind k) {
  switch (k) {
    case ErrorKind::input: return Exit::input;
    case ErrorKind::settings: return Exit::usage;  // a setting comes from the command line (or its job file)
    case ErrorKind::config: return Exit::config;
    case ErrorKind::io: return Exit::io;
    case ErrorKind::internal: return Exit::internal;
  }
  return Exit::internal;
}

}  // namespace deflex::cli
