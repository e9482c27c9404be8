// Losing nothing: what -o may write onto, that it is checked before any work,
// and that a failed write to standard output is an error.
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

TEST_CASE("fail fast, say where: what the simulation needs is checked first, at the line, with the exit code of the README") {
  TempDir d;
  const std::string out = (d.p / "out.nc").string();
  const std::vector<std::string> wall = {"--material", "Al6082-T4", "--stock", "box:0,-40,-30,100,0,0"};
  auto run = [&](const std::string& text, std::vector<std::string> extra) {
    const std::string in = (d.p / "in.nc").string();
    test::write_file(in, text);
    std::vector<std::string> args = {"compensate", in, "-o", out};
    args.insert(args.end(), wall.begin(), wall.end());
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_cli(args);
  };
  const std::string no_s = "G21 G90 G54\nT6 M6\nM3\nG0 X-10. Y3.5 Z5.\nG1 Z-12. F1000.\nX110.\nM30\n";
  auto r = run(no_s, {});
  CHECK(r.rc == 1);
  CHECK(r.err.find("in.nc:5:1: error: cutting with no spindle speed") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
  CHECK(run(no_s, {"--spindle", "6366"}).rc == 0);  // --spindle supplies it
  CHECK(fs::exists(out));
  fs::remove(out);
  // A move far outside the machine's travel: refused before any simulation.
  auto far = run("G21 G90 G54\nT6 M6\nS6000 M3\nG0 X-10. Y3.5 Z5.\nG1 Z-12. F1000.\nX100000.\nM30\n", {});
  CHECK(far.rc == 1);
  CHECK(far.err.find("in.nc:6:1: error: X travels to") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
  // A T word the library lacks: the library's error (3); a --tool it lacks: usage (2).
  auto t9 = run("G21 G90 G54\nT9 M6\nS6000 M3\nG0 X-10. Y3.5 Z5.\nG1 Z-12. F1000.\nX110.\nM30\n", {});
  CHECK(t9.rc == 3);
  CHECK(t9.err.find("in.nc:5:1: error: tool T9 is not in the tool library") != std::string::npos);
  CHECK(run(no_s, {"--spindle", "6366", "--tool", "T99"}).rc == 2);
  CHECK(run(no_s, {"--spindle", "6366", "--threads", "-1"}).rc == 2);
  CHECK_FALSE(fs::exists(out));
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

TEST_CASE("plausibility warnings: compiler style on stderr at the worst line, and in summary.json") {
  TempDir d;
  // The side wall as designed: no warning; summary.json has an empty array.
  auto ok = test::run_cli({"simulate", kWall, "--material", "Al6082-T4", "--stock", "box:0,-40,-30,100,0,0",
                           "--report", (d.p / "ok").string()});
  REQUIRE(ok.rc == 0);
  CHECK(ok.err.find("warning:") == std::string::npos);
  CHECK(test::read_file((d.p / "ok" / "summary.json").string()).find("\"warnings\": []") != std::string::npos);
  // The same path with the D6 ball T3 (flutes 9 mm) 12 mm into the wall's raw box.
  auto r = test::run_cli({"simulate", kWall, "--tool", "T3", "--material", "Al6082-T4", "--stock",
                          "box:0,-40,-30,100,10,0", "--report", (d.p / "bad").string()});
  INFO(r.err);
  REQUIRE(r.rc == 0);
  CHECK(r.err.find("side_wall.nc:16:1: warning: the cut reaches") != std::string::npos);
  CHECK(r.err.find("[flute_length]") != std::string::npos);
  CHECK(r.err.find("[roughing]") != std::string::npos);
  CHECK(r.err.find("N22 X110.") != std::string::npos);  // the source line under it
  const std::string js = test::read_file((d.p / "bad" / "summary.json").string());
  CHECK(js.find("\"kind\": \"flute_length\"") != std::string::npos);
  CHECK(js.find("\"kind\": \"roughing\"") != std::string::npos);
}

TEST_CASE("standard output onto an input file: refused before any work, saying the shell emptied it") {
  TempDir d;
  const std::string x = (d.p / "x.nc").string(), bin = DEFLEX_BINARY;
  auto fresh = [&] { fs::copy_file(kWall, x, fs::copy_options::overwrite_existing); };
  // Every command that reads a file and writes standard output; the refusal
  // comes before the config or the machine is looked at.
  for (const std::string& cmd :
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
