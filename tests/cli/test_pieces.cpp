// path, check and rewrite read a long program in pieces (memory does not grow
// with its length): their output, messages and exit code are those of the
// whole file, whatever the piece size (DEFLEX_CHUNK_LINES).
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <unistd.h>

#include "../support.hpp"

using namespace deflex;
namespace fs = std::filesystem;

namespace {

// DEFLEX_CHUNK_LINES for the scope of one run.
struct PieceLines {
  explicit PieceLines(const std::string& n) { ::setenv("DEFLEX_CHUNK_LINES", n.c_str(), 1); }
  ~PieceLines() { ::unsetenv("DEFLEX_CHUNK_LINES"); }
};

test::CliResult run_in(const std::string& lines, std::vector<std::string> args) {
  PieceLines p(lines);
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

TEST_SUITE("cli") {
  TEST_CASE("compensate in pieces: the same program, messages and exit code as on the whole program") {
    const fs::path dir = fs::temp_directory_path() / ("deflex-cpieces-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    struct Case {
      std::vector<std::string> args;
      std::vector<const char*> lines;  // DEFLEX_CHUNK_LINES to compare with 0
    };
    // A program with an error and one whose tool the library lacks, both
    // past the first piece.
    test::write_file((dir / "bad.nc").string(),
                     "G21 G90\nT1 M6\nS8000 M3\nG0 X0. Y0. Z5.\nG1 Z-1. F300.\nG1 X10.\nG1 X20.\nG92 X0.\nG1 X30.\nM30\n");
    test::write_file((dir / "tool.nc").string(), "G21 G90\nT1 M6\nS8000 M3\nG0 X0. Y0. Z5.\nG1 Z-1. F300.\nG1 X10.\n"
                                                 "T77 M6\nG0 X20.\nG1 Z-1.\nG1 X30.\nM30\n");
    const std::vector<Case> cases = {
        {{"samples/programs/side_wall.nc", "--stock", "box:0,-40,-30,100,0,0"}, {"1", "7"}},
        {{"samples/programs/freeform.nc", "--stock", "samples/stock/freeform_stock.stl"}, {"1", "40"}},
        {{"samples/programs/pocket_finish.nc", "--stock", "box:-5,-5,-20,105,85,0", "--gain", "0"}, {"9"}},
        {{"samples/programs/six_surfaces.nc", "--stock", "samples/stock/six_surfaces_stock.stl", "--tool", "T1"},
         {"5000"}},
        {{"samples/programs/six_surfaces.nc", "--stock", "samples/stock/six_surfaces_stock.stl", "--part",
          "samples/parts/six_surfaces.stl"},
         {"7000"}},
        // --feed-limit: the feeds planned by a first pass over the pieces.
        {{"samples/programs/side_wall.nc", "--stock", "box:0,-40,-30,100,0,0", "--feed-limit", "150"}, {"3"}},
        {{"samples/programs/freeform.nc", "--stock", "samples/stock/freeform_stock.stl", "--feed-limit", "40"},
         {"25"}},
        {{(dir / "bad.nc").string(), "--stock", "box:-5,-5,-5,40,5,0"}, {"2"}},
        {{(dir / "tool.nc").string(), "--stock", "box:-5,-5,-5,40,5,0"}, {"2"}}};
    int compared = 0;
    for (const Case& c : cases) {
      std::vector<std::string> whole_args = {"compensate"};
      whole_args.insert(whole_args.end(), c.args.begin(), c.args.end());
      const std::string wout = (dir / "whole.nc").string(), pout = (dir / "pieces.nc").string();
      fs::remove(wout);
      std::vector<std::string> w = whole_args;
      w.insert(w.end(), {"-o", wout});
      const test::CliResult whole = run_in("0", w);
      for (const char* n : c.lines) {
        CAPTURE(c.args[0]);
        CAPTURE(n);
        fs::remove(pout);
        std::vector<std::string> p = whole_args;
        p.insert(p.end(), {"-o", pout});
        const test::CliResult got = run_in(n, p);
        CHECK(got.rc == whole.rc);
        CHECK(got.err == whole.err);
        CHECK(fs::exists(pout) == fs::exists(wout));
        if (fs::exists(wout)) CHECK(test::read_file(pout) == test::read_file(wout));
        ++compared;
      }
      // To standard output: the same bytes, after the check.
      if (whole.rc == 0) {
        const test::CliResult out = run_in(c.lines[0], whole_args);
        CHECK(out.rc == 0);
        CHECK(out.out == test::read_file(wout));
      }
    }
    CHECK(compared == 11);
    fs::remove_all(dir);
  }
}

TEST_SUITE("cli") {
  TEST_CASE("simulate in pieces: the summary and messages of the whole program") {
    for (const char* n : {"1", "30"}) {
      for (std::vector<std::string> c : std::vector<std::vector<std::string>>{
               {"simulate", "samples/programs/freeform.nc", "--stock", "samples/stock/freeform_stock.stl"},
               {"simulate", "samples/programs/side_wall.nc", "--stock", "box:0,-40,-30,100,0,0"}}) {
        CAPTURE(n);
        CAPTURE(c[1]);
        const test::CliResult whole = run_in("0", c), p = run_in(n, c);
        CHECK(whole.rc == 0);
        CHECK(p.rc == whole.rc);
        CHECK(p.out == whole.out);
        CHECK(p.err == whole.err);
        CHECK(whole.out.find("CL points") != std::string::npos);
      }
    }
  }
}

TEST_SUITE("cli") {
  TEST_CASE("--report in pieces: every file of the folder byte for byte that of the whole program") {
    const fs::path dir = fs::temp_directory_path() / ("deflex-rpieces-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    ::setenv("SOURCE_DATE_EPOCH", "1700000000", 1);  // the page's date
    const std::vector<std::vector<std::string>> cases = {
        {"compensate", "samples/programs/freeform.nc", "--stock", "samples/stock/freeform_stock.stl"},
        {"compensate", "samples/programs/six_surfaces.nc", "--stock", "samples/stock/six_surfaces_stock.stl", "--part",
         "samples/parts/six_surfaces.stl"},
        {"compensate", "samples/programs/side_wall.nc", "--stock", "box:0,-40,-30,100,0,0", "--feed-limit", "150"},
        {"compensate", "samples/programs/pocket_finish.nc", "--stock", "box:-5,-5,-20,105,85,0", "--gain", "0"},
        {"simulate", "samples/programs/freeform.nc", "--stock", "samples/stock/freeform_stock.stl"}};
    const std::vector<std::string> files = {"points.csv", "summary.json", "report.html", "flank_profile.csv"};
    int compared = 0;
    for (const auto& c : cases) {
      CAPTURE(c[0]);
      CAPTURE(c[1]);
      // Into the same folder (its name is in the page's command line), moved aside after.
      auto run = [&](const std::string& lines, const fs::path& keep) {
        std::vector<std::string> a = c;
        a.insert(a.end(), {"--report", (dir / "report").string(), "-o", (dir / "out.nc").string()});
        if (c[0] == "simulate") a.resize(a.size() - 2);
        const test::CliResult r = run_in(lines, a);
        fs::rename(dir / "report", keep);
        return r;
      };
      fs::remove_all(dir / "whole");
      fs::remove_all(dir / "pieces");
      const test::CliResult whole = run("0", dir / "whole"), pieces = run("37", dir / "pieces");
      CAPTURE(whole.err);
      REQUIRE(whole.rc == 0);
      CHECK(pieces.rc == 0);
      CHECK(pieces.err == whole.err);
      for (const std::string& f : files) {
        CAPTURE(f);
        REQUIRE(fs::exists(dir / "whole" / f) == fs::exists(dir / "pieces" / f));
        if (!fs::exists(dir / "whole" / f)) continue;
        const std::string w = test::read_file((dir / "whole" / f).string());
        CHECK(w.size() > 100);
        const bool same = test::read_file((dir / "pieces" / f).string()) == w;  // (not printed: a page is MBs)
        CHECK(same);
        ++compared;
      }
      // Nothing but the report's files is left in the folder (no spill, no temporary).
      for (const auto& e : fs::directory_iterator(dir / "pieces"))
        CHECK(std::find(files.begin(), files.end(), e.path().filename().string()) != files.end());
    }
    ::unsetenv("SOURCE_DATE_EPOCH");
    CHECK(compared >= 15);
    fs::remove_all(dir);
  }
}
