// cmake --install: the installed deflex finds its data through
// DEFLEX_DATA_DIR, never through the source tree, runs the sample job from any
// folder, and takes its config in the documented order.
#include <doctest/doctest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "../support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

int exit_code(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }

// cmake --install of a build (default: this one) into a new temporary
// folder, returned; the installed tree is under its usr/.
fs::path install_to_temp(const fs::path& build = fs::path(DEFLEX_BINARY).parent_path()) {
  std::string t = (fs::temp_directory_path() / "deflex-install-XXXXXX").string();
  const fs::path tmp = mkdtemp(t.data());
  REQUIRE(exit_code(std::system(("cmake --install " + build.string() + " --prefix " + (tmp / "usr").string() + " > " +
                                 (tmp / "install.log").string() + " 2>&1")
                                    .c_str())) == 0);
  return tmp;
}

const char* const kBashCompletion = "/usr/share/bash-completion/bash_completion";

}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("cmake --install: the sample job from an empty folder; the config search order") {
    // What is installed comes from a build with CMake's default generator (Unix
    // Makefiles), the conventional `cmake -S . -B b && cmake --build b`: it differs
    // from Ninja where an output's folder is not created for a command. Its
    // folder lies beside the suite's build and stays, so a second run rebuilds
    // only what changed; with ccache, and the source folder as its base (the
    // same relative paths as the suite's build), a first run mostly hits the cache.
    const fs::path ours = fs::path(DEFLEX_BINARY).parent_path();
    const fs::path build = ours.parent_path() / (ours.filename().string() + "-make");
    const std::string ccache =
        std::system("command -v ccache > /dev/null 2>&1") == 0 ? " -DCMAKE_CXX_COMPILER_LAUNCHER=ccache" : "";
    const std::string log_file = (fs::temp_directory_path() / ("deflex-make-" + std::to_string(::getpid()) + ".log")).string();
    const std::string log = " >> " + log_file + " 2>&1";
    const std::string base = std::getenv("CCACHE_BASEDIR") ? "" : std::string("CCACHE_BASEDIR=") + DEFLEX_SOURCE_DIR + " ";
    const std::string make = "env -u CMAKE_GENERATOR " + base + "sh -c 'cmake -S " + DEFLEX_SOURCE_DIR + " -B " +
                             build.string() + " -DCMAKE_BUILD_TYPE=Release" + ccache + log +
                             " && cmake --build " + build.string() + " -j 2 --target deflex deflex_man" + log + "'";
    const int built = exit_code(std::system(make.c_str()));
    CAPTURE(test::read_file(log_file));
    REQUIRE(built == 0);
    CHECK(test::read_file((build / "CMakeCache.txt").string()).find("CMAKE_GENERATOR:INTERNAL=Unix Makefiles") !=
          std::string::npos);
    const fs::path tmp = install_to_temp(build);
    const fs::path bin = tmp / "usr/bin/deflex", data = tmp / "usr/share/deflex";
    CHECK(fs::is_regular_file(bin));
    for (const char* f : {"config.yaml", "samples/machines/mill3.yaml", "samples/tools.yaml", "samples/materials.yaml",
                          "postproc/fanuc.yaml", "samples/programs/six_surfaces.nc"})
      CHECK_MESSAGE(fs::is_regular_file(data / f), f);
    const fs::path work = tmp / "work", home = tmp / "home";
    fs::create_directories(work);
    fs::create_directories(home);
    // deflex as installed, in `dir`, with a home of its own and `data` as its data folder.
    auto run = [&](const fs::path& dir, const std::string& args, const fs::path& data_dir) {
      const std::string cmd = "cd " + dir.string() + " && env -u XDG_CONFIG_HOME HOME=" + home.string() +
                              " DEFLEX_DATA_DIR=" + data_dir.string() + " " + bin.string() + " " + args + " > " +
                              (tmp / "out").string() + " 2> " + (tmp / "err").string();
      const int rc = exit_code(std::system(cmd.c_str()));
      return test::CliResult{rc, test::read_file((tmp / "out").string()), test::read_file((tmp / "err").string())};
    };
    // The installed defaults from an empty folder, and the sample job with them:
    // the same program as the clone's config gives in the source tree.
    test::CliResult v = run(work, "--version", data);
    CHECK(v.rc == 0);
    CHECK(v.out.find("config: " + (data / "config.yaml").string()) != std::string::npos);
    const std::string job = "compensate " + (data / "samples/programs/six_surfaces.nc").string() + " --stock " +
                            (data / "samples/stock/six_surfaces_stock.stl").string() + " -o comp.nc";
    const test::CliResult c = run(work, job, data);
    CAPTURE(c.err);
    REQUIRE(c.rc == 0);
    const test::CliResult here = test::run_cli({"compensate", "samples/programs/six_surfaces.nc", "--stock",
                                                "samples/stock/six_surfaces_stock.stl", "-o", (tmp / "here.nc").string()});
    REQUIRE(here.rc == 0);
    CHECK(test::read_file((work / "comp.nc").string()) == test::read_file((tmp / "here.nc").string()));
    // Its plugins (src/plugin/load.cpp) installed beside it, <prefix>/lib/deflex,
    // and found there: a STEP stock loads OpenCASCADE's.
    for (const char* f : {"libdeflex_occt.so", "libdeflex_ceres.so"})
      CHECK_MESSAGE(fs::is_regular_file(tmp / "usr/lib/deflex" / f), f);
    const test::CliResult step =
        run(work, "stock --stock " + std::string(DEFLEX_SOURCE_DIR) + "/tests/stock/data/sphere_r10.step -o s.zmap", data);
    CAPTURE(step.err);
    CHECK(step.rc == 0);
    // Without its data the installed deflex does not fall back on the source
    // tree: the machine is not found, and the message says where it looked.
    const test::CliResult lost = run(work, job, tmp / "nowhere");
    CHECK(lost.rc == 2);  // no config at all: no machine named
    CHECK(lost.err.find("a machine profile is needed") != std::string::npos);
    const test::CliResult lost_m = run(work, job + " --machine mill3", tmp / "nowhere");
    CHECK(lost_m.rc == 3);
    CHECK(lost_m.err.find("samples/machines") != std::string::npos);
    CHECK(lost_m.err.find(DEFLEX_SOURCE_DIR) == std::string::npos);
    // The search order: ~/.config/deflex over the installed defaults,
    // ./config.yaml over that, ./deflex.yaml over ./config.yaml, --config over all.
    fs::create_directories(home / ".config/deflex");
    test::write_file((home / ".config/deflex/config.yaml").string(), "machine: mill3\n");
    CHECK(run(work, "--version", data).out.find("config: " + (home / ".config/deflex/config.yaml").string()) !=
          std::string::npos);
    test::write_file((work / "config.yaml").string(), "machine: mill3\n");
    CHECK(run(work, "--version", data).out.find("config: config.yaml") != std::string::npos);
    test::write_file((work / "deflex.yaml").string(), "machine: mill3\n");
    CHECK(run(work, "--version", data).out.find("config: deflex.yaml") != std::string::npos);
    // The installed config copied to ~/.config/deflex to be edited keeps naming
    // the installed libraries (relative paths: its folder, else the data's).
    fs::copy_file(data / "config.yaml", home / ".config/deflex/config.yaml", fs::copy_options::overwrite_existing);
    fs::remove(work / "config.yaml");
    fs::remove(work / "deflex.yaml");
    const test::CliResult copied = run(work, job + " --tolerance 0.005", data);
    CAPTURE(copied.err);
    CHECK(copied.rc == 0);
    test::write_file((work / "deflex.yaml").string(), "machine: mill3\n");
    // A config in use is read: its mistakes are the user's to see.
    test::write_file((work / "deflex.yaml").string(), "tolerance_mm: -1\n");
    const test::CliResult bad = run(work, "check " + (data / "samples/programs/side_wall.nc").string(), data);
    CHECK(bad.rc == 3);
    CHECK(bad.err.find("deflex.yaml") != std::string::npos);
    // The man pages (help2man, from --help at build time) and the completion.
    for (const char* f : {"deflex.1", "deflex-compensate.1", "deflex-list.1"})
      CHECK_MESSAGE(fs::is_regular_file(tmp / "usr/share/man/man1" / f), f);
    CHECK(test::read_file((tmp / "usr/share/man/man1/deflex-compensate.1").string()).find("feed\\-limit") !=  // roff escapes the hyphens
          std::string::npos);
    // The completion, as packaging/deflex.bash-completion (tried in bash in the suite cli_completion).
    CHECK(test::read_file((tmp / "usr/share/bash-completion/completions/deflex").string()) ==
          test::read_file("packaging/deflex.bash-completion"));
    fs::remove_all(tmp);
  }
}

// bash-completion's own script must be there to source; where it is not, this
// case is skipped, and CTest's entry cli_completion says so (cmake/tests.cmake).
TEST_SUITE("cli_completion") {
  TEST_CASE("bash completion of the installed deflex: commands, options, library names" *
            doctest::skip(!fs::exists(kBashCompletion))) {
    const fs::path tmp = install_to_temp();
    const fs::path data = tmp / "usr/share/deflex", work = tmp / "work", home = tmp / "home";
    fs::create_directories(work);
    fs::create_directories(home);
    const fs::path completion = tmp / "usr/share/bash-completion/completions/deflex";
    REQUIRE(fs::is_regular_file(completion));
    // What bash offers after each line, with the installed deflex first on PATH.
    auto offered = [&](const std::string& line) {
      const std::string script = tmp.string() + "/complete.sh";
      test::write_file(script, std::string("source ") + kBashCompletion + "\nsource " + completion.string() +
                                   "\nCOMP_LINE='" + line + "'; COMP_POINT=${#COMP_LINE}\n"
                                   "read -ra COMP_WORDS <<< \"$COMP_LINE\"; [[ $COMP_LINE == *' ' ]] && COMP_WORDS+=('')\n"
                                   "COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); _deflex; printf '%s\\n' \"${COMPREPLY[@]}\"\n");
      const std::string cmd = "cd " + work.string() + " && env HOME=" + home.string() + " DEFLEX_DATA_DIR=" +
                              data.string() + " PATH=" + (tmp / "usr/bin").string() + ":/usr/bin:/bin bash " + script +
                              " > " + (tmp / "out").string() + " 2>&1";
      std::system(cmd.c_str());
      return test::read_file((tmp / "out").string());
    };
    CHECK(offered("deflex comp") == "compensate\ncompare\n");
    CHECK(offered("deflex compensate --feed-") == "--feed-limit\n");
    CHECK(offered("deflex compensate x.nc --machine ") == "mill3\n");
    CHECK(offered("deflex simulate x.nc --dialect li") == "linuxcnc\n");
    CHECK(offered("deflex compensate x.nc --tool T") == "T1\nT2\nT3\nT4\nT5\nT6\nT7\n");
    CHECK(offered("deflex compensate x.nc --material Al") == "Al6082-T4\nAl7075-T6\n");
    CHECK(offered("deflex check x.nc --progress a") == "auto\nalways\n");
    fs::remove_all(tmp);
  }
}
