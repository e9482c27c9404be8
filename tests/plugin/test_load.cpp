// deflex's plugins (src/plugin/load.cpp): the library reads STEP and IGES
// files and fits a machine through them, found where the build put them, an
// error that names what was searched when they are missing, and the program
// linking neither OpenCASCADE nor Ceres.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>

#include "../support.hpp"
#include "deflex/stock/build.hpp"
#include "deflex_plugin.hpp"

using namespace deflex;
namespace fs = std::filesystem;

namespace {

const std::string kBinary = DEFLEX_BINARY;
const fs::path kPlugins = fs::path(DEFLEX_BINARY).parent_path() / "plugins";

// DEFLEX_PLUGIN_DIR for the scope of one check.
struct PluginDir {
  explicit PluginDir(const std::string& d) { ::setenv("DEFLEX_PLUGIN_DIR", d.c_str(), 1); }
  ~PluginDir() { ::unsetenv("DEFLEX_PLUGIN_DIR"); }
  PluginDir(const PluginDir&) = delete;
  PluginDir& operator=(const PluginDir&) = delete;
};

}  // namespace

TEST_SUITE("plugin") {
  TEST_CASE("the folders searched: DEFLEX_PLUGIN_DIR alone; else the build tree's for its programs") {
    REQUIRE(std::getenv("DEFLEX_PLUGIN_DIR") == nullptr);
    CHECK(plugin::search_dirs() == std::vector<std::string>{kPlugins.string()});
    CHECK(fs::is_regular_file(kPlugins / "libdeflex_occt.so"));
    CHECK(fs::is_regular_file(kPlugins / "libdeflex_ceres.so"));
    PluginDir d("/nowhere");
    CHECK(plugin::search_dirs() == std::vector<std::string>{"/nowhere"});
  }

  TEST_CASE("an unreadable STEP or IGES file: deflex::Error from the plugin, as the reader threw it") {
    test::TempDir dir("plugin");
    test::write_file(dir / "bad.step", "ISO-10303-21;\ngarbage\n");
    test::write_file(dir / "bad.igs", "garbage\n");
    CHECK(test::error_of([&] { stock::read_solid_triangles(dir / "bad.step", 0.01); }, ErrorKind::io) ==
          dir / "bad.step" + ": cannot read as STEP");
    CHECK(test::error_of([&] { stock::read_solid_triangles(dir / "bad.igs", 0.01); }, ErrorKind::config) ==
          dir / "bad.igs" + ": the file holds no shape");
    // The command line's message and exit code (in the clone: its config.yaml),
    // OpenCASCADE's own message on stderr.
    const test::CliResult r =
        test::run_shell(kBinary + " stock --stock " + dir / "bad.step" + " -o " + dir / "x.zmap", DEFLEX_SOURCE_DIR);
    CHECK(r.rc == 4);
    CHECK(r.out.empty());
    CHECK(r.err.find("**** ERR StepFile : Undefined Parsing") == 0);
    CHECK(r.err.find("deflex: error: " + dir / "bad.step" + ": cannot read as STEP\n") != std::string::npos);
  }

  TEST_CASE("a missing plugin: an error naming it, what needs it and the folders searched") {
    test::TempDir dir("plugin");
    // In the clone: its config.yaml.
    const test::CliResult r = test::run_shell("DEFLEX_PLUGIN_DIR=" + dir.p.string() + " " + kBinary +
                                                  " stock --stock tests/stock/data/sphere_r10.step -o " + dir / "x.zmap",
                                              DEFLEX_SOURCE_DIR);
    CHECK(r.rc == 3);
    CHECK(r.err == "deflex: error: deflex's plugin libdeflex_occt.so (OpenCASCADE: STEP and IGES files) cannot be "
                   "loaded: searched " + dir.p.string() + " (DEFLEX_PLUGIN_DIR overrides)\n");
    // A plugin that is there but cannot be loaded: the loader's reason. The
    // back wall measured where mill3 puts it (tests/cli/test_fit.cpp).
    test::write_file(dir / "libdeflex_ceres.so", "not a shared object\n");
    test::write_file(dir / "m.csv", "x_mm,y_mm,z_mm\n50,96,-6\n50,96,-4\n50,96,-2\n");
    const test::CliResult f = test::run_shell(
        "DEFLEX_PLUGIN_DIR=" + dir.p.string() + " " + kBinary +
            " fit tests/data/fit/walls_xy.nc --machine samples/machines/mill3.yaml --material Al6082-T4"
            " --stock box:0,0,-20,100,100,0 --measured " + dir / "m.csv",
        DEFLEX_SOURCE_DIR);
    CAPTURE(f.err);
    CHECK(f.rc == 3);
    CHECK(f.err.find("deflex's plugin libdeflex_ceres.so (Ceres: the machine fit) cannot be loaded: searched " +
                     dir.p.string() + " (DEFLEX_PLUGIN_DIR overrides); " + dir / "libdeflex_ceres.so: ") !=
          std::string::npos);
  }

  TEST_CASE("the program links neither OpenCASCADE nor Ceres: they load with their plugin") {
    const test::CliResult r = test::run_shell("ldd " + kBinary, fs::temp_directory_path().string());
    REQUIRE(r.rc == 0);
    for (const char* lib : {"libTKernel", "libTKSTEP", "libceres", "libglog", "libcholmod"}) {
      CAPTURE(lib);
      CHECK(r.out.find(lib) == std::string::npos);
    }
  }
}
