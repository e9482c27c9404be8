// Where deflex finds its files (include/deflex/profile/search.hpp).
#include "deflex/profile/search.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>

#ifndef DEFLEX_DATA_DIR
#define DEFLEX_DATA_DIR "/usr/local/share/deflex"
#endif

namespace deflex::profile {
namespace fs = std::filesystem;

namespace {

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v && *v ? v : "";
}

// $XDG_CONFIG_HOME/deflex, ~/.config/deflex when unset ("" without a home).
std::string user_dir() {
  std::string x = env("XDG_CONFIG_HOME");
  if (x.empty()) {
    const std::string home = env("HOME");
    if (home.empty()) return "";
    x = home + "/.config";
  }
  return x + "/deflex";
}

}  // namespace

std::vector<std::string> data_dir_candidates() {
  const std::string e = env("DEFLEX_DATA_DIR");
  if (!e.empty()) return {e};
  std::vector<std::string> c;
  // Installed under any prefix (a .deb's /usr, cmake --install's /usr/local or
  // a user's ~/.local): the data in the prefix of the file this code was
  // loaded from, <prefix>/share/deflex. That file is the deflex binary
  // (<prefix>/bin), a program linking the library, or Python's extension
  // module (<prefix>/lib/python3/dist-packages/deflex): up to four folders up.
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&data_dir_candidates), &info) && info.dli_fname) {
    std::error_code ec;
    fs::path up = fs::weakly_canonical(info.dli_fname, ec).parent_path();
    for (int i = 0; i < 4 && up.has_parent_path() && up != up.root_path(); ++i) {
      up = up.parent_path();
      c.push_back((up / "share" / "deflex").string());
    }
  }
  c.push_back(DEFLEX_DATA_DIR);
  return c;
}

std::string data_dir() {
  const std::vector<std::string> c = data_dir_candidates();
  std::error_code ec;
  // Beside the binary only where it holds a config.yaml: a build tree's
  // ../share is no data folder.
  for (std::size_t i = 0; i + 1 < c.size(); ++i)
    if (fs::is_regular_file(fs::path(c[i]) / "config.yaml", ec)) return c[i];
  return c.back();
}

namespace {

// The places of a user's or the system's files: `local` (the current folder's),
// then `rel` under $XDG_CONFIG_HOME/deflex, /etc/deflex, and `data_rel` under DATA.
std::vector<std::string> places(std::vector<std::string> local, const std::string& rel, const std::string& data_rel) {
  if (const std::string u = user_dir(); !u.empty()) local.push_back(u + "/" + rel);
  local.push_back("/etc/deflex/" + rel);
  local.push_back(data_dir() + "/" + data_rel);
  return local;
}

}  // namespace

std::vector<std::string> config_candidates() {
  return places({"deflex.yaml", "config.yaml"}, "config.yaml", "config.yaml");
}

std::vector<std::string> machine_folders() { return places({"machines", "samples/machines"}, "machines", "samples/machines"); }

std::string find_config(const std::string& given) {
  if (!given.empty()) return given;
  std::error_code ec;
  for (const std::string& f : config_candidates())
    if (fs::is_regular_file(f, ec)) return f;
  return "";
}

std::string find_machine(const std::string& name) {
  std::error_code ec;
  for (const std::string& d : machine_folders()) {
    const fs::path p = fs::path(d) / (name + ".yaml");
    if (fs::is_regular_file(p, ec)) return p.string();
  }
  return "";
}

}  // namespace deflex::profile
