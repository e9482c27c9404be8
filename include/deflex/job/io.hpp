// Where a job's messages go: notes, warnings and errors in compiler style
// (FILE:LINE:COL: warning: ...), and the input stream a program of "-" is
// read from. The command line passes its standard streams, the tests and the
// Python bindings string streams.
#pragma once
#include <iosfwd>
#include <string>
#include <string_view>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::job {

struct Io {
  std::istream& in;    // a program (or reference) of "-"
  std::ostream& out;   // what a command prints as its result (the CLI's stdout)
  std::ostream& err;   // notes, warnings and errors
  bool quiet = false;    // errors and warnings only: no notes
  bool verbose = false;  // also the setup and each stage's time
  // Where notes go: err, or nowhere when quiet (warnings and errors always go
  // to err: what a machinist must know is never silenced).
  std::ostream& info();
  // How messages name settings (diag/settings.hpp): the command line by its
  // flags; empty, by the job's keywords.
  SettingNames names = {};
  // `text` with its {keyword}s named so, for what the job writes to err itself.
  std::string named(std::string_view text) const { return name_settings(text, names); }
  // Diagnostics printed to err, naming settings so.
  Diagnostics diagnostics(int max_errors) const;
};

}  // namespace deflex::job
