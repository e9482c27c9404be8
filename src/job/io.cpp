// Where a job's notes go (io.hpp).
#include "deflex/job/io.hpp"

#include <ostream>

namespace deflex::job {

std::ostream& Io::info() {
  static std::ostream none(nullptr);  // a stream without a buffer writes nothing
  return quiet ? none : err;
}

Diagnostics Io::diagnostics(int max_errors) const {
  Diagnostics d(&err, max_errors);
  d.set_names(names);
  return d;
}

}  // namespace deflex::job
