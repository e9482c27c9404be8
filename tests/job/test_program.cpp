// The calls behind path, rewrite, tools import, list and calibrate
// (include/deflex/job/program.hpp, libraries.hpp, physics.hpp) against the
// commands that print them: the same motions, bytes, names and material
// entry; a program with an error hands over nothing and writes nothing; an
// output that is the input is refused before it is read.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "support.hpp"
#include "deflex/job/libraries.hpp"
#include "deflex/job/physics.hpp"
#include "deflex/job/program.hpp"
#include "deflex/profile/profile.hpp"
#include "deflex/stiffness/tool.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

using test::Streams;

struct Keep : interp::MotionSink {
  std::vector<interp::Motion> motions;
  void motion(const interp::Motion& m) override { motions.push_back(m); }
};

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> v;
  std::istringstream s(text);
  for (std::string l; std::getline(s, l);) v.push_back(l);
  return v;
}

// The pieces a program is read in, for the scope (DEFLEX_CHUNK_LINES).
struct PieceLines {
  explicit PieceLines(const std::string& n) { ::setenv("DEFLEX_CHUNK_LINES", n.c_str(), 1); }
  ~PieceLines() { ::unsetenv("DEFLEX_CHUNK_LINES"); }
};

// Each motion against `deflex path --lines`' line for it: LINE KIND X Y Z.
void check_printed(const std::vector<interp::Motion>& motions, const std::string& printed) {
  const std::vector<std::string> rows = lines_of(printed);
  REQUIRE(rows.size() == motions.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    CAPTURE(rows[i]);
    std::istringstream row(rows[i]);
    std::uint32_t line = 0;
    std::string kind;
    double x_mm = 0, y_mm = 0, z_mm = 0;
    row >> line >> kind >> x_mm >> y_mm >> z_mm;
    CHECK(line == motions[i].line);
    CHECK(kind == interp::to_string(motions[i].kind));
    // Printed with 6 decimals: within half of the last one.
    CHECK(std::abs(x_mm - motions[i].end_mm[0]) <= 5e-7);
    CHECK(std::abs(y_mm - motions[i].end_mm[1]) <= 5e-7);
    CHECK(std::abs(z_mm - motions[i].end_mm[2]) <= 5e-7);
  }
}

// A program whose last line is refused (a macro B block, as tests/bad/macro.nc):
// every motion before it runs in the diagnostic pass.
const char* kFailsAtLine5 = "G21 G90 G54\nG0 X0 Y0 Z5\nG1 Z-1 F300\nG1 X10\n#100=5.\nG1 Y10\nM30\n";

// Holds the motions until finish() says whether they stand (job::HoldingSink).
struct Held : job::HoldingSink {
  std::vector<interp::Motion> held, motions;
  int finished = 0;
  void motion(const interp::Motion& m) override { held.push_back(m); }
  void finish(bool no_error) override {
    ++finished;
    if (no_error) motions = held;
  }
};

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("job::path in one pass (a holding sink) hands over and reports what the two passes do") {
    test::TempDir t;
    // Warnings early (I without an arc, no G20/G21), an error in a late piece;
    // the same without the error; an error in the text's own checks (strict).
    const std::string late_error = t / "late_error.nc", fine = t / "fine.nc", strict = t / "strict.nc";
    std::string body = "G90 G54\nT1 M6 S1000 M3\nG0 X0 Y0 Z5\nG1 Z-1 F300 I2\n";
    for (int i = 0; i < 40; ++i)
      body += "G1 X" + std::to_string(i) + ". Y" + std::to_string(i % 3) + (i % 4 ? ".\n" : ". J1.\n");
    test::write_file(late_error, body + "G1 X1. Y2. Q\nG1 X3.\nM30\n");
    test::write_file(fine, body + "M30\n");
    test::write_file(strict, body + "G1 X3000\nM30\n");
    for (const std::string& file : {late_error, fine, strict, std::string("samples/programs/pocket_finish.nc")})
      for (const std::string piece : {"0", "7"}) {
        CAPTURE(file);
        CAPTURE(piece);
        PieceLines pl(piece);
        job::PathSettings ps{file, {}, ""};
        ps.read.dialect = "fanuc";
        ps.read.strict = file == strict;
        Streams two;
        Keep keep;
        const job::PathResult a = job::path(ps, keep, two.io);
        // The text checks before the interpretation, beside it, and beside it
        // with its messages held 3 at most (it then waits for the checks).
        for (const std::pair<int, int>& mode : {std::pair{1, 4096}, std::pair{0, 4096}, std::pair{0, 3}}) {
          const int threads = mode.first, held_messages = mode.second;
          CAPTURE(threads);
          CAPTURE(held_messages);
          ps.threads = threads;
          ps.held_messages = static_cast<std::size_t>(held_messages);
          Streams one;
          Held held;
          const job::PathResult b = job::path(ps, held, one.io);
          CHECK(held.finished == 1);
          CHECK(a.handed == b.handed);
          CHECK(a.handed == (file == fine || file.find("pocket") != std::string::npos));
          CHECK(a.errors == b.errors);
          CHECK(a.warnings == b.warnings);
          CHECK(a.stats.motions == b.stats.motions);
          CHECK(a.stats.stopped_line == b.stats.stopped_line);
          CHECK(two.err.str() == one.err.str());
          CHECK(keep.motions.size() == held.motions.size());
          for (std::size_t i = 0; i < std::min(keep.motions.size(), held.motions.size()); ++i) {
            CHECK(keep.motions[i].line == held.motions[i].line);
            CHECK(keep.motions[i].end_mm == held.motions[i].end_mm);
          }
        }
      }
  }

  TEST_CASE("job::path hands over the motions `deflex path` prints, read whole or in pieces") {
    const std::string program = "samples/programs/pocket_finish.nc";
    const auto cli = test::run_cli({"path", "--lines", program});
    REQUIRE(cli.rc == 0);
    for (const char* piece : {"0", "5"}) {
      CAPTURE(piece);
      PieceLines pl(piece);
      Streams s;
      Keep keep;
      const job::PathResult r = job::path({program, {}, ""}, keep, s.io);
      CHECK(r.handed);
      CHECK(r.errors == 0);
      CHECK(r.stats.motions == keep.motions.size());
      CHECK(r.name == program);
      CHECK(s.out.str().empty());  // the sink has the motions; nothing is printed
      check_printed(keep.motions, cli.out);
    }
  }

  TEST_CASE("job::path: a program with an error hands nothing over, and io.err locates the error") {
    test::TempDir t;
    const std::string file = t / "fails.nc";
    test::write_file(file, kFailsAtLine5);
    Streams s;
    Keep keep;
    const job::PathResult r = job::path({file, {}, ""}, keep, s.io);
    CHECK_FALSE(r.handed);
    CHECK(r.errors >= 1);
    CHECK(keep.motions.empty());
    CHECK(s.err.str().find(file + ":5:1: error: ") != std::string::npos);
    // The same program without its bad line hands its motions over.
    test::write_file(file, "G21 G90 G54\nG0 X0 Y0 Z5\nG1 Z-1 F300\nG1 X10\nG1 Y10\nM30\n");
    Streams ok;
    Keep whole;
    CHECK(job::path({file, {}, ""}, whole, ok.io).handed);
    CHECK(whole.motions.size() == 4);
  }

  TEST_CASE("job::path: more executed blocks than max_blocks hands nothing over") {
    Streams s;
    s.in.str("G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F300\nG1 X10\nG1 Y10\nG1 X0\nM30\n");
    Keep keep;
    job::PathSettings ps{"-", {}, ""};
    ps.read.max_blocks = 3;
    const job::PathResult r = job::path(ps, keep, s.io);
    CHECK_FALSE(r.handed);
    CHECK(r.errors >= 1);
    CHECK(keep.motions.empty());
  }

  TEST_CASE("job::rewrite gives the input's bytes back, to io.out and to a file") {
    test::TempDir t;
    const std::string program = "tests/golden/crlf_inch.nc";
    const std::string input = test::read_file(program);
    REQUIRE(input.find("\r\n") != std::string::npos);  // the line ends are part of what comes back
    Streams s;
    int writing_calls = 0;
    job::rewrite({program, {}, ""}, s.io, [&] { ++writing_calls; });
    CHECK(s.out.str() == input);
    CHECK(writing_calls == 1);
    Streams f;
    job::rewrite({program, {}, t / "out.nc"}, f.io, [&] { ++writing_calls; });
    CHECK(test::read_file(t / "out.nc") == input);
    CHECK(f.out.str().empty());
    CHECK(writing_calls == 1);  // a file is no standard output
  }

  TEST_CASE("job::rewrite refuses a program with errors and writes no file") {
    test::TempDir t;
    const std::string file = t / "fails.nc", out = t / "out.nc";
    test::write_file(file, kFailsAtLine5);
    Streams s;
    bool wrote = false;
    try {
      job::rewrite({file, {}, out}, s.io, [&] { wrote = true; });
      FAIL("no error");
    } catch (const Error& e) {
      CHECK(e.kind() == ErrorKind::input);
      CHECK(std::string(e.what()) == file + ": error: not written: the program has errors");
    }
    CHECK_FALSE(fs::exists(out));
    CHECK(std::distance(fs::directory_iterator(t.p), fs::directory_iterator()) == 1);  // the program alone
    CHECK(s.err.str().find(file + ":5:1: error: ") != std::string::npos);
    // To io.out: nothing either.
    Streams o;
    CHECK_THROWS_AS(job::rewrite({file, {}, ""}, o.io, [&] { wrote = true; }), Error);
    CHECK(o.out.str().empty());
    CHECK_FALSE(wrote);
  }

  TEST_CASE("job::rewrite refuses an output that is the input, before reading it") {
    test::TempDir t;
    const std::string file = t / "p.nc";
    test::write_file(file, kFailsAtLine5);  // read, it would report its error
    Streams s;
    CHECK_THROWS_AS(job::rewrite({file, {}, file}, s.io), Error);
    CHECK(s.err.str().empty());
    CHECK(test::read_file(file) == kFailsAtLine5);
  }

  TEST_CASE("job::import_tools converts what `deflex tools import` prints, and writes it when asked") {
    test::TempDir t;
    for (const std::string lib : {"samples/tool-libraries/fusion_library.json", "samples/tool-libraries/linuxcnc.tbl"}) {
      CAPTURE(lib);
      const auto cli = test::run_cli({"tools", "import", lib});
      REQUIRE(cli.rc == 0);
      Streams s;
      const job::ToolImportResult r = job::import_tools({lib, ""}, s.io);
      CHECK(r.yaml == cli.out);
      CHECK(r.tools == static_cast<int>(stiffness::parse_tool_library(r.yaml, lib).tools.size()));
      CHECK(cli.err.find(r.format) != std::string::npos);
      CHECK(s.out.str().empty());
      const std::string out = t / "tools.yaml";
      job::import_tools({lib, out}, s.io);
      CHECK(test::read_file(out) == r.yaml);
    }
  }

  TEST_CASE("job::import_tools refuses a file of neither format and an output that is the input") {
    test::TempDir t;
    Streams s;
    const std::string yaml = t / "tools.yaml";
    test::write_file(yaml, test::read_file("samples/tools.yaml"));
    try {
      job::import_tools({yaml, ""}, s.io);
      FAIL("no error");
    } catch (const Error& e) {
      CHECK(e.kind() == ErrorKind::settings);
    }
    const std::string tbl = t / "lathe.tbl";
    test::write_file(tbl, test::read_file("samples/tool-libraries/linuxcnc.tbl"));
    CHECK_THROWS_AS(job::import_tools({tbl, tbl}, s.io), Error);
    CHECK(test::read_file(tbl) == test::read_file("samples/tool-libraries/linuxcnc.tbl"));
  }

  TEST_CASE("job::names are the names `deflex list` prints") {
    for (const auto& [word, kind] : {std::pair{"dialects", job::NameKind::dialects},
                                     std::pair{"tools", job::NameKind::tools},
                                     std::pair{"materials", job::NameKind::materials},
                                     std::pair{"machines", job::NameKind::machines}}) {
      const std::string what = word;  // CAPTURE's lambda cannot take a structured binding (clang 14)
      CAPTURE(what);
      const auto cli = test::run_cli({"list", word});
      REQUIRE(cli.rc == 0);
      job::NamesSettings ns;
      ns.what = kind;
      const job::Names n = job::names(ns);
      CHECK_FALSE(n.names.empty());
      CHECK(n.names == lines_of(cli.out));
    }
    job::NamesSettings dialects;
    dialects.what = job::NameKind::dialects;
    CHECK(job::names(dialects).names == profile::dialect_names());
  }

  TEST_CASE("job::calibrate: the entry `deflex calibrate` prints, written to a file when asked") {
    test::TempDir t;
    const std::string csv = "samples/calibration/slot_tests_al7075.csv";
    const auto cli = test::run_cli({"calibrate", csv});
    REQUIRE(cli.rc == 0);
    const job::CalibrationResult r = job::calibrate({csv, "", ""});
    CHECK(cli.out.ends_with("\nmaterial entry:\n" + r.yaml));
    CHECK(r.entry.name == r.tests.material);  // the CSV's '# material:'
    CHECK(r.fit.residual_N.size() == r.tests.tests.size());
    const job::CalibrationResult named = job::calibrate({csv, "mine", t / "m.yaml"});
    CHECK(named.entry.name == "mine");
    CHECK(test::read_file(t / "m.yaml") == named.yaml);
    CHECK(named.yaml.find("mine") != std::string::npos);
    const std::string copy = t / "tests.csv";  // refused, it stays as it is
    test::write_file(copy, test::read_file(csv));
    CHECK_THROWS_AS(job::calibrate({copy, "", copy}), Error);
    CHECK(test::read_file(copy) == test::read_file(csv));
  }
}
