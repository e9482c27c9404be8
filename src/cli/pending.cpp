// Commands whose module has not landed yet in this build (see CMakeLists.txt):
// they say so plainly instead of pretending.
#include "deflex/cli/command.hpp"
#include "deflex/diag/diagnostics.hpp"

namespace deflex::cli {
#ifdef DEFLEX_PENDING_STIFFNESS
int cmd_stiffness(const std::vector<std::string>&, Io&) { throw Error(Exit::usage, "stiffness: not built yet (issue 3)"); }
#endif
#ifdef DEFLEX_PENDING_FORCES
int cmd_forces(const std::vector<std::string>&, Io&) { throw Error(Exit::usage, "forces: not built yet (issue 4)"); }
int cmd_calibrate(const std::vector<std::string>&, Io&) { throw Error(Exit::usage, "calibrate: not built yet (issue 4)"); }
#endif
}  // namespace deflex::cli
