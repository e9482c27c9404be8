// Reading a program in pieces (gcode/reader.hpp): the pieces make the file,
// keep their line numbers, and the interpreter fed them gives what it gives
// on the whole file.
#include <doctest/doctest.h>

#include <filesystem>
#include <sstream>

#include "../support.hpp"
#include "deflex/gcode/reader.hpp"

using namespace deflex;
namespace fs = std::filesystem;

namespace {

struct TempFile {
  fs::path p;
  explicit TempFile(const std::string& text) {
    p = fs::temp_directory_path() / ("deflex-reader-" + std::to_string(::getpid()) + "-" + std::to_string(++count));
    test::write_file(p.string(), text);
  }
  ~TempFile() { fs::remove(p); }
  static inline int count = 0;
};

// Every piece of `path` at `lines` lines per piece.
std::vector<std::unique_ptr<gcode::Program>> pieces(const std::string& path, std::uint32_t lines) {
  gcode::ProgramReader r(path, nullptr, lines);
  std::vector<std::unique_ptr<gcode::Program>> v;
  while (auto p = r.next()) v.push_back(std::move(p));
  return v;
}

struct Collect : interp::MotionSink {
  std::vector<interp::Motion> m;
  void motion(const interp::Motion& x) override { m.push_back(x); }
};

}  // namespace

TEST_SUITE("gcode") {
  TEST_CASE("program reader: the pieces are the file, line by line") {
    const std::string text = "%\r\nO1 (A)\r\nG21 G90\r\n\r\nG0 X1. Y2.\r\nM30\r\n%\r\ntail";
    TempFile f(text);
    const gcode::Program whole(gcode::read_source(f.p.string()));
    for (std::uint32_t n : {1u, 2u, 3u, 7u, 0u}) {
      CAPTURE(n);
      const auto v = pieces(f.p.string(), n);
      REQUIRE(!v.empty());
      std::string joined;
      std::uint32_t next = 1;
      for (const auto& p : v) {
        CHECK(p->first_line() == next);
        CHECK(p->line_count() >= 1);
        if (n) CHECK(p->line_count() <= n);
        for (std::uint32_t l = p->first_line(); l <= p->last_line(); ++l)
          CHECK(p->source().line_text(l) == whole.source().line_text(l));
        // The tape end is the same line whatever piece it falls in.
        CHECK(p->closing_percent_line() == (p->last_line() >= 7 ? 7u : 0u));
        joined += p->bytes();
        next = p->last_line() + 1;
      }
      CHECK(joined == text);
      CHECK(next == whole.line_count() + 1);
      CHECK(v.size() == (n ? (whole.line_count() + n - 1) / n : 1));
    }
  }

  TEST_CASE("program reader: an empty file is one empty piece; a missing one is an I/O error") {
    TempFile f("");
    const auto v = pieces(f.p.string(), 4);
    REQUIRE(v.size() == 1);
    CHECK(v[0]->line_count() == 0);
    CHECK_THROWS_AS(gcode::ProgramReader("/nonexistent/x.nc", nullptr, 4), Error);
  }

  TEST_CASE("program passes: whole when small, calling subprograms or from stdin; else in pieces") {
    TempFile small("G0 X1\nM30\n"), sub("G0 X1\nM98 P100\nM30\nO100\nG1 X2\nM99\n"), big("G0 X1\nG0 X2\nG0 X3\nM30\n");
    CHECK(gcode::ProgramPasses(small.p.string(), nullptr, 4).whole());
    CHECK(gcode::ProgramPasses(sub.p.string(), nullptr, 2).whole());
    gcode::ProgramPasses b(big.p.string(), nullptr, 2);
    CHECK_FALSE(b.whole());
    int calls = 0, lasts = 0;
    b.each([&](const gcode::Program&, bool last) { ++calls, lasts += last; });
    CHECK(calls == 2);
    CHECK(lasts == 1);
    std::istringstream in("G0 X1\nG0 X2\nM30\n");
    CHECK(gcode::ProgramPasses("-", &in, 1).whole());
  }

  TEST_CASE("needs_whole_file: M98, G41, G42 in any spelling, nothing else") {
    for (const char* t : {"M98 P1\n", "m98P1", "N10 M098 P1\n", "G0 X1 M 98", "(M98)\n", "M9 8P3\n", "G41 D1\n",
                          "g42d2", "N5 G041 X1\n", "G4 2\n", "G0 G41", "M49 P1M+98\n", "G + 42\n"}) {
      CAPTURE(t);
      TempFile f(t);
      CHECK(gcode::needs_whole_file(f.p.string()));
    }
    for (const char* t : {"M9 P1\n", "M980\n", "M30\nM99\n", "G98 X1\n", "M198\n", "G40 G43 H1\n", "G410\n",
                          "G141\n", "G4 X1\n"}) {
      CAPTURE(t);
      TempFile f(t);
      CHECK_FALSE(gcode::needs_whole_file(f.p.string()));
    }
    CHECK(gcode::needs_whole_file("-"));
    // The file is read a MiB at a time: a word cut by a read still counts,
    // at every cut from before the M to after the 8.
    for (std::size_t at = (1u << 20) - 4; at <= (1u << 20); ++at) {
      CAPTURE(at);
      std::string text(at, 'X');
      text[0] = '(';
      text[at - 1] = ')';
      TempFile call(text + "M 9 8P1\n"), none(text + "M 9 80\n");
      CHECK(gcode::needs_whole_file(call.p.string()));
      CHECK_FALSE(gcode::needs_whole_file(none.p.string()));
    }
  }

  TEST_CASE("interpreter fed in pieces: the motions and messages of the whole file") {
    for (const char* path : {"samples/programs/pocket_finish.nc", "samples/programs/freeform.nc",
                             "samples/programs/side_wall.nc"}) {
      const gcode::Program whole(gcode::read_source(path));
      interp::Options o;
      o.dialect = profile::load_dialect("fanuc");
      std::ostringstream e0;
      Diagnostics d0(&e0, 0);
      Collect c0;
      const interp::Stats s0 = interp::interpret(whole, o, d0, c0);
      REQUIRE(c0.m.size() > 10);
      for (std::uint32_t n : {1u, 5u, 64u}) {
        CAPTURE(path);
        CAPTURE(n);
        std::ostringstream e1;
        Diagnostics d1(&e1, 0);
        Collect c1;
        interp::Interpreter it(o, d1, c1);
        const auto v = pieces(path, n);
        for (std::size_t k = 0; k < v.size(); ++k) it.feed(*v[k], k + 1 == v.size());
        const interp::Stats s1 = it.finish();
        CHECK(e1.str() == e0.str());
        CHECK(s1.lines == s0.lines);
        CHECK(s1.blocks == s0.blocks);
        CHECK(s1.motions == s0.motions);
        REQUIRE(c1.m.size() == c0.m.size());
        bool same = true;
        for (std::size_t i = 0; i < c0.m.size(); ++i)
          same = same && c0.m[i].line == c1.m[i].line && c0.m[i].end_mm == c1.m[i].end_mm &&
                 c0.m[i].center_mm == c1.m[i].center_mm && c0.m[i].feed_mm_per_min == c1.m[i].feed_mm_per_min &&
                 c0.m[i].kind == c1.m[i].kind && c0.m[i].tool == c1.m[i].tool;
        CHECK(same);
      }
    }
  }

  TEST_CASE("interpreter fed in pieces: an error stops it where it stops on the whole file") {
    const std::string text = "G21 G90\nG0 X1. Y1.\nG1 X2. F100\nG92 X0\nG1 X3.\nG1 X4.. \nM30\n";
    TempFile f(text);
    const test::Interpreted w = test::interpret_text(text);
    REQUIRE(w.errors == 2);  // the refused G92, then the lexical error of a line never run
    for (std::uint32_t n : {1u, 2u, 3u}) {
      CAPTURE(n);
      std::ostringstream e;
      Diagnostics d(&e, 0);
      Collect c;
      interp::Options o;
      o.dialect = profile::load_dialect("fanuc");
      interp::Interpreter it(o, d, c);
      auto v = pieces(f.p.string(), n);
      for (auto& p : v) it.feed(*p);
      const interp::Stats s = it.finish();
      CHECK(s.stopped);
      CHECK(s.stopped_line == 4);
      CHECK(c.m.size() == w.motions.size());
      // The same messages (the file name differs from interpret_text's).
      std::string want = w.diagnostics;
      for (std::size_t k; (k = want.find("t.nc")) != std::string::npos;) want.replace(k, 4, f.p.string());
      CHECK(e.str() == want);
    }
  }
}
