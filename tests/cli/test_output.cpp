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
struct TempDir {
  fs::path p;
  TempDir() {
    std::string t = (fs::temp_directory_path() / "deflex-out-XXXXXX").string();
    p = mkdtemp(t.data());
  }
  ~TempDir() { fs::remove_all(p); }
};

}  // namespace

TEST_SUITE("cli") {

TEST_CASE("-o writes only regular files: a FIFO, a directory and a device are refused, nothing is created") {
  TempDir d;
  const fs::path fifo = d.p / "fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  for (const std::string out : {fifo.string(), d.p.string(), std::string("/dev/null")}) {
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

TEST_CASE("a failed write to standard output is an I/O error, not exit 0") {
  // The binary itself: the check is in main(), after the command ran.
  const std::string cmd = std::string(DEFLEX_BINARY) + " rewrite " + kWall + " > /dev/full 2>/dev/null";
  const int st = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(st));
  CHECK(WEXITSTATUS(st) == 4);
}

}  // TEST_SUITE
