// deflex's plugins: shared objects loaded with dlopen() on first use, each
// behind an entry point that returns its module's table of functions
// (src/stock/internal/stock_occt_api.hpp, src/stiffness/occt_api.hpp,
// src/fit/ceres_api.hpp). Why, and how they are found: src/plugin/load.cpp.
#pragma once
#include <string>
#include <vector>

namespace deflex::plugin {

// The folders searched for a plugin, in order: $DEFLEX_PLUGIN_DIR alone when
// set; else the build tree's plugin folder when this code runs from a program
// of the build tree; else <prefix>/<libdir>/deflex for the prefixes up to four
// folders above the program (or shared object) this code was loaded from,
// then the install folder compiled in.
std::vector<std::string> search_dirs();

// The value of `entry`, an extern "C" function without arguments returning a
// pointer, in lib<library>.so. The library is loaded once (RTLD_LOCAL) and
// kept. Throws Error(ErrorKind::config) naming the library, `needed_for`, the
// folders searched and the loader's message when it cannot be loaded or has
// no such entry point.
const void* entry(const std::string& library, const char* entry, const char* needed_for);

// entry() as the table of functions Api its entry point returns.
template <class Api>
const Api& api(const std::string& library, const char* name, const char* needed_for) {
  return *static_cast<const Api*>(entry(library, name, needed_for));
}

}  // namespace deflex::plugin
