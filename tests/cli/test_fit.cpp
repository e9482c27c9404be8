// deflex fit on the command line: the fitted profile on stdout or into -o,
// the table on stderr; bad measurements stop it before any simulation, with
// nothing written. What the fit computes is in tests/fit/.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "../support.hpp"

using namespace deflex;

TEST_SUITE("cli") {
  TEST_CASE("fit: the profile into -o, the table on stderr; a malformed log is a located error, nothing written") {
    test::TempDir dir("fitcli");
    const std::string base = "samples/machines/mill3.yaml";
    const std::vector<std::string> run = {"fit", "tests/data/fit/walls_xy.nc", "--machine", base, "--material", "Al6082-T4",
                                          "--stock", "box:0,0,-20,100,100,0"};
    // Measured points of the back wall where mill3 itself puts them: the fit has nothing to change there.
    const std::string csv = dir / "m.csv";
    std::ofstream(csv) << "x_mm,y_mm,z_mm\n50,96,-6\n50,96,-4\n50,96,-2\n";
    std::vector<std::string> ok = run;
    ok.insert(ok.end(), {"--measured", csv, "-o", dir / "fitted.yaml"});
    const auto r = test::run_cli(ok);
    CHECK(r.rc == 0);
    CHECK(r.out.empty());
    CHECK(r.err.find("fit: 3 of 3 measured points compared") != std::string::npos);
    CHECK(r.err.find("  held: structure X: the measured points do not feel it") != std::string::npos);
    CHECK(test::read_file(dir / "fitted.yaml").find("name: mill3-fitted") != std::string::npos);
    // Fitted again from the fitted profile: one suffix, not two.
    std::vector<std::string> again = ok;
    again[3] = dir / "fitted.yaml";
    again.back() = dir / "fitted2.yaml";
    REQUIRE(test::run_cli(again).rc == 0);
    const std::string twice = test::read_file(dir / "fitted2.yaml");
    CHECK(twice.find("name: mill3-fitted\n") != std::string::npos);
    CHECK(twice.find("fitted-fitted") == std::string::npos);

    // A LinuxCNC log with one number missing on its second line.
    const std::string probe = dir / "probe.nc", log = dir / "log.txt";
    std::ofstream(probe) << "(DEFLEX PROBE 1 WX1 AT 50.000 96.000 -6.000 N 0.0000 1.0000 0.0000 BALL 1.000)\n"
                            "(DEFLEX PROBE 2 WX1 AT 50.000 96.000 -4.000 N 0.0000 1.0000 0.0000 BALL 1.000)\n";
    std::ofstream(log) << "50 97.01 -6 0 0 0 0 0 0\n50 97.01 -4 0 0 0 0 0\n";
    std::vector<std::string> bad = run;
    bad.insert(bad.end(), {"--measured", log, "--probe-program", probe, "-o", dir / "bad.yaml"});
    const auto b = test::run_cli(bad);
    CHECK(b.rc != 0);
    CHECK(b.err.find(log + ":2:") != std::string::npos);
    CHECK(b.err.find("50 97.01 -4 0 0 0 0 0") != std::string::npos);  // the source line
    CHECK_FALSE(std::filesystem::exists(dir / "bad.yaml"));
    CHECK(b.err.find("basis") == std::string::npos);  // stopped before any simulation

    // No measurements at all.
    std::vector<std::string> none = run;
    none.insert(none.end(), {"-o", dir / "none.yaml"});
    const auto n = test::run_cli(none);
    CHECK(n.rc == 2);
    CHECK(n.err.find("give the measurements (--measured)") != std::string::npos);
  }

  TEST_CASE("fit --also: another measured cut from a job file, fitted with the first; its features named by program and tool") {
    test::TempDir dir("fitcli");
    const std::string csv6 = dir / "t6.csv", csv1 = dir / "t1.csv", job = dir / "t1.yaml";
    // The back wall (normal +Y) where each tool leaves it: T6 (R 6) at y 96, T1 (R 5) at y 97.
    std::ofstream(csv6) << "x_mm,y_mm,z_mm\n50,96,-6\n50,96,-4\n50,96,-2\n";
    std::ofstream(csv1) << "x_mm,y_mm,z_mm\n50,97,-6\n50,97,-4\n50,97,-2\n";
    std::ofstream(job) << "program: " << std::filesystem::absolute("tests/data/fit/walls_xy.nc").string()
                       << "\ntool: T1\nmeasured: t1.csv\n";
    const auto r = test::run_cli({"fit", "tests/data/fit/walls_xy.nc", "--machine", "samples/machines/mill3.yaml", "--material",
                                  "Al6082-T4", "--stock", "box:0,0,-20,100,100,0", "--measured", csv6, "--also", job, "-o",
                                  dir / "fitted.yaml"});
    CHECK(r.rc == 0);
    CHECK(r.err.find("fit: 6 of 6 measured points compared") != std::string::npos);
    CHECK(r.err.find("  walls_xy.nc T1 ") != std::string::npos);
    CHECK(test::read_file(dir / "fitted.yaml").find("walls_xy.nc measured by " + csv1) != std::string::npos);
    // A job file without a program.
    const std::string bad = dir / "bad.yaml";
    std::ofstream(bad) << "tool: T1\nmeasured: t1.csv\n";
    const auto b = test::run_cli({"fit", "tests/data/fit/walls_xy.nc", "--machine", "samples/machines/mill3.yaml", "--material",
                                  "Al6082-T4", "--stock", "box:0,0,-20,100,100,0", "--measured", csv6, "--also", bad});
    CHECK(b.rc == 2);
    CHECK(b.err.find("--also needs a job file naming its program") != std::string::npos);
  }
}
