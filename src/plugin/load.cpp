// Loading deflex's plugins (internal/deflex_plugin.hpp).
//
// Why plugins: OpenCASCADE (STEP and IGES files, the solid tool model) and
// Ceres (the machine fit, with glog, SuiteSparse and LAPACK) were linked into
// every deflex program, and the dynamic loader resolved their ~86,000
// relocations at each start: `deflex path` of a three-line program took
// 36.6 ms, 70 % of it in the loader (perf); a program linking deflex's other
// libraries (Boost.Program_options, yaml-cpp, TBB, libcrypto) starts in
// 2.3 ms, with OpenCASCADE 28.5 ms, with Ceres' dependencies too 31.1 ms.
// Few runs read a STEP file or fit a machine: their code is in
// libdeflex_occt.so and libdeflex_ceres.so, loaded here when first called,
// and `deflex path` takes about 7 ms, 4 ms of CPU instead of 35 (perf stat
// -r 20; docs/architecture.md, 'Plugins').
#include "deflex_plugin.hpp"

#include <dlfcn.h>
#include <link.h>

#include <cstdlib>
#include <filesystem>
#include <algorithm>
#include <map>
#include <mutex>

#include "deflex/diag/diagnostics.hpp"

#ifndef DEFLEX_BUILD_DIR
#define DEFLEX_BUILD_DIR ""
#endif
#ifndef DEFLEX_PLUGIN_BUILD_DIR
#define DEFLEX_PLUGIN_BUILD_DIR ""
#endif
#ifndef DEFLEX_PLUGIN_INSTALL_DIR
#define DEFLEX_PLUGIN_INSTALL_DIR "/usr/local/lib/deflex"
#endif
#ifndef DEFLEX_PLUGIN_LIBDIR
#define DEFLEX_PLUGIN_LIBDIR "lib/deflex"
#endif

namespace deflex::plugin {
namespace fs = std::filesystem;

namespace {

// The file this code was loaded from: the program (dladdr() names it by its
// argv[0], which need not be a path: /proc/self/exe instead) or the shared
// object linking deflex (Python's extension module).
fs::path this_object() {
  Dl_info info{};
  link_map* map = nullptr;
  if (!dladdr1(reinterpret_cast<const void*>(&search_dirs), &info, reinterpret_cast<void**>(&map), RTLD_DL_LINKMAP))
    return {};
  std::error_code ec;
  const fs::path p = map && map->l_name && *map->l_name ? fs::path(map->l_name) : fs::path("/proc/self/exe");
  return fs::weakly_canonical(p, ec);
}

bool within(const fs::path& file, const fs::path& dir) {
  if (dir.empty()) return false;
  std::error_code ec;
  const fs::path d = fs::weakly_canonical(dir, ec);
  const auto [end, _] = std::mismatch(d.begin(), d.end(), file.begin(), file.end());
  return end == d.end();
}

}  // namespace

std::vector<std::string> search_dirs() {
  if (const char* e = std::getenv("DEFLEX_PLUGIN_DIR"); e && *e) return {e};
  const fs::path self = this_object();
  // A program of the build tree loads the plugins built with it, never those
  // of an installed deflex (a folder up from build/ may be a prefix).
  if (within(self, DEFLEX_BUILD_DIR)) return {DEFLEX_PLUGIN_BUILD_DIR};
  std::vector<std::string> c;
  // Installed under any prefix, as profile/search.cpp finds the data: the
  // program in <prefix>/bin, Python's module in
  // <prefix>/lib/python3/dist-packages/deflex.
  if (fs::path(DEFLEX_PLUGIN_LIBDIR).is_relative()) {
    fs::path up = self.parent_path();
    for (int i = 0; i < 4 && up.has_parent_path() && up != up.root_path(); ++i) {
      up = up.parent_path();
      if (up != up.root_path()) c.push_back((up / DEFLEX_PLUGIN_LIBDIR).string());
    }
  }
  c.push_back(DEFLEX_PLUGIN_INSTALL_DIR);
  return c;
}

namespace {

void* open(const std::string& file, const char* needed_for) {
  std::string searched, why;
  for (const std::string& dir : search_dirs()) {
    const std::string path = (fs::path(dir) / file).string();
    searched += (searched.empty() ? "" : ", ") + dir;
    std::error_code ec;
    if (!fs::exists(path, ec)) continue;
    if (void* h = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) return h;
    why = std::string("; ") + ::dlerror();
    break;  // found but not loadable: say why rather than try an older copy
  }
  throw Error(ErrorKind::config, "deflex's plugin " + file + " (" + needed_for + ") cannot be loaded: searched " +
                                     searched + " (DEFLEX_PLUGIN_DIR overrides)" + why);
}

}  // namespace

const void* entry(const std::string& library, const char* name, const char* needed_for) {
  static std::mutex m;
  static std::map<std::string, void*> loaded;  // never closed: the tables point into them
  const std::string file = "lib" + library + ".so";
  std::lock_guard<std::mutex> lock(m);
  void*& h = loaded[file];
  if (!h) h = open(file, needed_for);
  using Entry = const void* (*)();
  const auto f = reinterpret_cast<Entry>(::dlsym(h, name));
  if (!f) throw Error(ErrorKind::config, "deflex's plugin " + file + " has no " + name + ": not of this deflex");
  return f();
}

}  // namespace deflex::plugin
