// path, check and rewrite read a long program in pieces (memory does not grow
// with its length): their output, messages and exit code are those of the
// whole file, whatever the piece size (DEFLEX_CHUNK_LINES). Compensate and
// simulate in pieces are tests/job/test_pieces.cpp.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <unistd.h>

#include "../support.hpp"

using namespace deflex;
namespace fs = std::filesystem;

namespace {

test::CliResult run_in(const std::string& lines, std::vector<std::string> args) {
  test::PieceLines p(lines);
  return test::run_cli(args);
}

}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("path, check, rewrite in pieces: byte for byte what the whole file gives") {
    const fs::path dir = fs::temp_directory_path() / ("deflex-pieces-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    // Programs with what crosses a piece boundary: a tape end with text after
    // it, no program end, mixed decimal points, G41, an error after a stop,
    // CRLF, no final line end, CR-only line ends.
    const std::vector<std::pair<std::string, std::string>> own = {
        {"tape.nc", "%\nO1\nG21 G90 G17\nT1 M6\nS1000 M3\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nX20 Y5\n%\nG1 X9 ###\n"},
        {"mixed.nc", "G21 G90\r\nT1 M6 S100 M3\r\nG0 X1. Y1. Z1.\r\nG1 X2000 F100\r\nG41 D1 X4.\r\nG1 X5. Y3.\r\n"
                     "G40 G1 X6.\r\nG92 X0\r\nG1 X3.\r\nG1 X4.. \r\nM30"},
        {"cr.nc", "G21 G90\rG0 X1 Y2\rM30\r"},
        {"blank.nc", "\n\n\n%\n\n"}};
    std::vector<std::string> files = {"samples/programs/pocket_finish.nc", "samples/programs/side_wall.nc",
                                      "samples/programs/freeform.nc"};
    for (const auto& [name, text] : own) {
      test::write_file((dir / name).string(), text);
      files.push_back((dir / name).string());
    }
    const std::vector<std::vector<std::string>> commands = {
        {"path", "--lines"}, {"check"}, {"check", "--format", "json"}, {"check", "--strict"}, {"rewrite"}};
    int compared = 0;
    for (const std::string& f : files)
      for (std::vector<std::string> c : commands) {
        c.push_back(f);
        const test::CliResult whole = run_in("0", c);
        for (const char* n : {"1", "3", "50"}) {
          CAPTURE(f);
          CAPTURE(c[0]);
          CAPTURE(n);
          const test::CliResult p = run_in(n, c);
          CHECK(p.rc == whole.rc);
          CHECK(p.out == whole.out);
          CHECK(p.err == whole.err);
          ++compared;
        }
      }
    CHECK(compared == 7 * 5 * 3);
    // rewrite -o in pieces writes the file back byte for byte.
    const std::string out = (dir / "out.nc").string();
    CHECK(run_in("3", {"rewrite", "samples/programs/side_wall.nc", "-o", out}).rc == 0);
    CHECK(test::read_file(out) == test::read_file("samples/programs/side_wall.nc"));
    fs::remove_all(dir);
  }

  TEST_CASE("DEFLEX_CHUNK_LINES must be a number") {
    const test::CliResult r = run_in("many", {"check", "samples/programs/side_wall.nc"});
    CHECK(r.rc == 2);
    CHECK(r.err.find("DEFLEX_CHUNK_LINES must be a whole number") != std::string::npos);
  }
}
