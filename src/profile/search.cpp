// Where deflex finds its files (include/deflex/profile/search.hpp).
#include "deflex/profile/search.hpp"

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

std::string data_dir() {
  const std::string e = env("DEFLEX_DATA_DIR");
  if (!e.empty()) return e;
  // Installed under any prefix (a .deb's /usr, cmake --install's /usr/local or
  // a user's ~/.local): the data beside the binary, ../share/deflex.
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path beside = exe.parent_path().parent_path() / "share" / "deflex";
    if (fs::is_regular_file(beside / "config.yaml", ec)) return beside.string();
  }
  return DEFLEX_DATA_DIR;
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
