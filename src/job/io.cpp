// Where a job's notes go (io.hpp).
#include "deflex/job/io.hpp"

#include <ostream>

namespace deflex::job {

std::ostream& Io::info() {
  static std::ostream none(nullptr);  // a stream without a buffer writes nothing
  return quiet ? none : err;
}

}  // namespace deflex::job
