// A machine profile of one section, written to a temporary folder: what the
// section tests of deflex::profile read back (its first line is line 3).
#pragma once
#include <doctest/doctest.h>

#include <filesystem>
#include <string>
#include <unistd.h>

#include "../support.hpp"

namespace deflex::test {

struct SectionProfile {
  std::string section;
  std::filesystem::path dir;
  std::string file;
  explicit SectionProfile(std::string name)
      : section(std::move(name)),
        dir(std::filesystem::temp_directory_path() / ("deflex-" + section + "-" + std::to_string(::getpid()))),
        file((dir / "m.yaml").string()) {
    std::filesystem::create_directories(dir);
  }
  ~SectionProfile() { std::filesystem::remove_all(dir); }
  // Loads "name: m\n<section>:\n" + `body`.
  profile::MachineProfile load(const std::string& body) const {
    write_file(file, "name: m\n" + section + ":\n" + body);
    return profile::load_machine(file);
  }
  // The message of the configuration error loading it gives ("no error" if none).
  std::string error(const std::string& body) const {
    try {
      load(body);
    } catch (const Error& e) {
      CHECK(e.kind() == ErrorKind::config);
      return e.what();
    }
    return "no error";
  }
};

}  // namespace deflex::test
