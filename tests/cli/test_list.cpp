// deflex list and --version where nothing is installed: a binary run outside
// its clone and install (src/profile/search.cpp's order) says where it looked.
#include <doctest/doctest.h>

#include <stdlib.h>

#include <filesystem>

#include "../support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

TEST_SUITE("cli") {
  TEST_CASE("outside a clone and an install: --version names no missing folder, list finds nothing and says where") {
    std::string t = (fs::temp_directory_path() / "deflex-list-XXXXXX").string();
    const fs::path tmp = mkdtemp(t.data());
    fs::create_directories(tmp / "home");
    const std::string deflex = "env -u XDG_CONFIG_HOME HOME=" + (tmp / "home").string() + " DEFLEX_DATA_DIR=" +
                               (tmp / "nowhere").string() + " " + DEFLEX_BINARY;
    const test::CliResult v = test::run_shell(deflex + " --version", tmp.string());
    CHECK(v.rc == 0);
    CHECK(v.out.find("data: none found (looked in " + (tmp / "nowhere").string()) != std::string::npos);
    const test::CliResult m = test::run_shell(deflex + " list machines", tmp.string());
    CHECK(m.rc == 3);
    CHECK(m.out.empty());
    CHECK(m.err.find("deflex: error: list: no machines found (looked in ./machines, ./samples/machines, " +
                     (tmp / "home/.config/deflex/machines").string() + ", /etc/deflex/machines, " +
                     (tmp / "nowhere/samples/machines").string() + ")") != std::string::npos);
    // The dialects are built in: found anywhere.
    CHECK(test::run_shell(deflex + " list dialects", tmp.string()).rc == 0);
    // In the clone (its samples/machines) the same binary lists them.
    const test::CliResult here = test::run_shell(deflex + " list machines", DEFLEX_SOURCE_DIR);
    CHECK(here.rc == 0);
    CHECK(here.out.find("mill3\n") != std::string::npos);
    fs::remove_all(tmp);
  }
}
