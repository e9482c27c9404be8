// Losing nothing: what -o may write onto, that it is checked before any work,
// and that a failed write to standard output is an error; the exit codes.
// What a run checks and warns is in tests/job/test_checks.cpp.
#include <doctest/doctest.h>

#include <filesystem>
#include <sys/stat.h>
#include <unistd.h>

#include "../support.hpp"

using namespace deflex;
namespace fs = std::filesystem;

namespace {

const char* kWall = "samples/programs/side_wall.nc";

// A fresh folder under the system temporary folder, removed at the end.
using test::TempDir;

}  // namespace

TEST_SUITE("cli") {

TEST_CASE("-o writes only regular files: a FIFO, a directory and a device are refused, nothing is created") {
  TempDir d;
  const fs::path fifo = d.p / "fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  for (const std::string& out : {fifo.string(), d.p.string(), std::string("/dev/null")}) {
    auto r = test::run_cli({"rewrite", kWall, "-o", out});
    INFO(out << ": " << r.err);
    CHECK(r.rc == 2);
    CHECK(r.err.find("not a regular file") != std::string::npos);
  }
  CHECK(fs::is_fifo(fifo));
  struct stat st {};
  REQUIRE(::stat("/dev/null", &st) == 0);
  CHECK(S_ISCHR(st.st_mode));
  CHECK(std::distance(fs::directory_iterator(d.p), fs::directory_iterator()) == 1);  // the FIFO only
}

TEST_CASE("-o into a missing folder or onto the input is refused before anything is computed") {
  TempDir d;
  auto r = test::run_cli({"compensate", kWall, "--material", "Al6082-T4", "--stock", "box:0,-40,-30,100,0,0", "-o",
                          (d.p / "no" / "x.nc").string()});
  CHECK(r.rc == 2);
  CHECK(r.err.find("does not exist") != std::string::npos);
  CHECK(r.err.find("compensated") == std::string::npos);  // no summary: nothing ran
  const fs::path in = d.p / "in.nc";
  fs::copy_file(kWall, in);
  auto s = test::run_cli({"compensate", in.string(), "--material", "Al6082-T4", "--stock", "box:0,-40,-30,100,0,0",
                          "-o", in.string()});
  CHECK(s.rc == 2);
  CHECK(s.err.find("overwrite the input") != std::string::npos);
  CHECK(s.err.find("compensated") == std::string::npos);
  CHECK(test::read_file(in.string()) == test::read_file(kWall));
  auto t = test::run_cli({"simulate", kWall, "--material", "Al6082-T4", "--stock", "box:0,-40,-30,100,0,0", "--report",
                          (d.p / "no" / "rep").string()});
  CHECK(t.rc == 2);
  CHECK(t.out.empty());
}

TEST_CASE("-o through a symlink replaces its target and keeps the link; an existing file keeps its mode") {
  TempDir d;
  const fs::path target = d.p / "target.nc", link = d.p / "link.nc";
  test::write_file(target.string(), "old\n");
  REQUIRE(::chmod(target.c_str(), 0640) == 0);
  fs::create_symlink(target, link);
  auto r = test::run_cli({"rewrite", kWall, "-o", link.string()});
  REQUIRE(r.rc == 0);
  CHECK(fs::is_symlink(link));
  CHECK(test::read_file(target.string()) == test::read_file(kWall));
  CHECK((fs::status(target).permissions() & fs::perms::all) ==
        (fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read));
  // A link to nothing is refused.
  fs::create_symlink(d.p / "missing.nc", d.p / "dangling.nc");
  CHECK(test::run_cli({"rewrite", kWall, "-o", (d.p / "dangling.nc").string()}).rc == 2);
}

TEST_CASE("exit codes: one case per row of the README's table") {
  TempDir d;
  const std::string bad_prog = (d.p / "bad.nc").string(), bad_yaml = (d.p / "m.yaml").string();
  test::write_file(bad_prog, "G21 G90\nG1 X1. Q#5\nM30\n");
  test::write_file(bad_yaml, "name: m\ndialect: fanuc\nbogus: 1\n");
  CHECK(test::run_cli({"check", kWall}).rc == 0);                                          // 0 success
  CHECK(test::run_cli({"check", bad_prog}).rc == 1);                                       // 1 input error
  CHECK(test::run_cli({"check", kWall, "--no-such-option"}).rc == 2);                      // 2 usage
  CHECK(test::run_cli({"check", kWall, "--machine", bad_yaml}).rc == 3);                   // 3 configuration
  CHECK(test::run_cli({"check", (d.p / "missing.nc").string()}).rc == 4);                  // 4 I/O
  // 70 is a bug: nothing reaches it on purpose; run() maps a stray exception to it.
}

TEST_CASE("no library writes to stdout: OpenCASCADE's errors on a junk STL go to stderr") {
  TempDir d;
  const std::string junk = (d.p / "junk.stl").string();
  std::string bytes(3000, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>((i * 2654435761u) >> 13);
  test::write_file(junk, bytes);
  // The binary, so that OCCT's own console printers would reach the real stdout.
  const std::string out = (d.p / "stdout.txt").string();
  const std::string cmd = std::string(DEFLEX_BINARY) + " simulate " + kWall +
                          " --material Al6082-T4 --stock " + junk + " > " + out + " 2>/dev/null";
  const int st = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(st));
  CHECK(WEXITSTATUS(st) == 4);  // the file could not be read
  CHECK(test::read_file(out).empty());
}

TEST_CASE("a failed write to standard output, or a closed standard input, is an I/O error, not exit 0") {
  // The binary itself: the check is in main(), after the command ran.
  const std::string cmd = std::string(DEFLEX_BINARY) + " rewrite " + kWall + " > /dev/full 2>/dev/null";
  const int st = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(st));
  CHECK(WEXITSTATUS(st) == 4);
  // A closed standard input is no empty program: an I/O error too.
  const int in = std::system((std::string(DEFLEX_BINARY) + " check - <&- 2>/dev/null").c_str());
  REQUIRE(WIFEXITED(in));
  CHECK(WEXITSTATUS(in) == 4);
}

}  // TEST_SUITE

TEST_SUITE("cli") {

TEST_CASE("standard output onto an input file: refused before any work, saying the shell emptied it") {
  TempDir d;
  const std::string x = (d.p / "x.nc").string(), bin = DEFLEX_BINARY;
  auto fresh = [&] { fs::copy_file(kWall, x, fs::copy_options::overwrite_existing); };
  // Every command that reads a file and writes standard output; the refusal
  // comes before the config or the machine is looked at.
  for (const char* cmd :
       {"compensate x.nc --stock box:0,0,-20,100,20,0", "simulate x.nc --stock box:0,0,-20,100,20,0", "rewrite x.nc",
        "path x.nc", "check x.nc", "diff x.nc x.nc", "compare x.nc --stock box:0,0,-20,100,20,0",
        "rough x.nc --stock box:0,0,-20,100,20,0 --rough-tool T1", "stock --stock-from x.nc -o s.stl",
        "compensate y.nc --stock x.nc", "path - < x.nc"}) {
    fresh();
    test::write_file((d.p / "y.nc").string(), test::read_file(kWall));
    const test::CliResult r = test::run_shell(bin + " " + cmd + " > x.nc", d.p.string());
    INFO(cmd << ": " << r.err);
    CHECK(r.rc == 2);
    CHECK(r.err.find("error: input file is output file (standard output is redirected to it); the shell emptied it "
                     "before deflex ran: restore it") != std::string::npos);
    CHECK(r.err.find("warning") == std::string::npos);  // nothing read: no "empty program"
  }
  // Appended to (>>), the input is whole: no word of emptying.
  fresh();
  const test::CliResult a = test::run_shell(bin + " rewrite x.nc >> x.nc", d.p.string());
  CHECK(a.rc == 2);
  CHECK(a.err == "x.nc: error: input file is output file (standard output is redirected to it); write the output to "
                 "another file, or with -o OUT\n");
  CHECK(test::read_file(x) == test::read_file(kWall));
  // Another file, and a pipe, are fine.
  CHECK(test::run_shell(bin + " rewrite x.nc > y.nc", d.p.string()).rc == 0);
  CHECK(test::run_shell(bin + " rewrite x.nc | cat > y.nc", d.p.string()).rc == 0);
}

}  // TEST_SUITE
