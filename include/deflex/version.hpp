// What deflex was built from: DEFLEX_VERSION (the project's version, a
// compile definition) and the git revision of the tree (cmake/revision.cmake).
#pragma once

namespace deflex {
const char* revision();
}  // namespace deflex
