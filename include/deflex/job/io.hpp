// Where a job's messages go: notes, warnings and errors in compiler style
// (FILE:LINE:COL: warning: ...), and the input stream a program of "-" is
// read from. The command line passes its standard streams, the tests and the
// Python bindings string streams.
#pragma once
#include <iosfwd>

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
};

}  // namespace deflex::job
