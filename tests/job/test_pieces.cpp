// A long program read in pieces (memory does not grow with its length):
// job::compensate and job::simulate give what they give on the whole file,
// whatever the piece size (DEFLEX_CHUNK_LINES): the same bytes written, the
// same messages, the same error, the same summary and report files.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "support.hpp"

using namespace deflex;
namespace fs = std::filesystem;

namespace {

using test::PieceLines;

job::Settings on(const std::string& program, const std::string& stock) {
  job::Settings s;
  s.program = program;
  s.stock = stock;
  return s;
}

// job::compensate of `s` read in pieces of `lines` lines.
test::Outcome<job::CompensateResult> compensate_in(const std::string& lines, const job::Settings& s) {
  PieceLines p(lines);
  return test::compensate_job(s);
}

// Both ran alike: the same messages, and the same error or none.
template <class R>
void same_run(const test::Outcome<R>& got, const test::Outcome<R>& whole) {
  CHECK(got.ok() == whole.ok());
  CHECK(got.error == whole.error);
  CHECK(got.what == whole.what);
  CHECK(got.err == whole.err);
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("compensate in pieces: the same program, messages and error as on the whole program") {
    test::TempDir dir("cpieces");
    struct Case {
      job::Settings settings;
      std::vector<const char*> lines;  // DEFLEX_CHUNK_LINES to compare with 0
    };
    // A program with an error and one whose tool the library lacks, both
    // past the first piece.
    test::write_file(dir / "bad.nc",
                     "G21 G90\nT1 M6\nS8000 M3\nG0 X0. Y0. Z5.\nG1 Z-1. F300.\nG1 X10.\nG1 X20.\nG92 X0.\nG1 X30.\nM30\n");
    test::write_file(dir / "tool.nc", "G21 G90\nT1 M6\nS8000 M3\nG0 X0. Y0. Z5.\nG1 Z-1. F300.\nG1 X10.\n"
                                      "T77 M6\nG0 X20.\nG1 Z-1.\nG1 X30.\nM30\n");
    const std::string wall = "samples/programs/side_wall.nc", wall_box = "box:0,-40,-30,100,0,0";
    const std::string freeform = "samples/programs/freeform.nc", freeform_stl = "samples/stock/freeform_stock.stl";
    const std::string six = "samples/programs/six_surfaces.nc", six_stl = "samples/stock/six_surfaces_stock.stl";
    std::vector<Case> cases = {{on(wall, wall_box), {"1", "7"}},
                               {on(freeform, freeform_stl), {"1", "40"}},
                               {on("samples/programs/pocket_finish.nc", "box:-5,-5,-20,105,85,0"), {"9"}},
                               {on(six, six_stl), {"5000"}},
                               {on(six, six_stl), {"7000"}},
                               // A feed limit: the feeds planned by a first pass over the pieces.
                               {on(wall, wall_box), {"3"}},
                               {on(freeform, freeform_stl), {"25"}},
                               {on(dir / "bad.nc", "box:-5,-5,-5,40,5,0"), {"2"}},
                               {on(dir / "tool.nc", "box:-5,-5,-5,40,5,0"), {"2"}},
                               // T5's floor pass 12 mm deep under 10 mm flutes: its
                               // shank in the material, an error inside the write.
                               {on(test::edited_copy(dir, "samples/programs/pocket_finish.nc", "deep.nc",
                                                     "N60 G01 Z-1.", "N60 G01 Z-12."),
                                   "box:-5,-5,-20,105,85,0"),
                                {"9"}}};
    cases[2].settings.gain = 0;
    cases[2].settings.stock_from = test::pocket_predrilled();
    cases[3].settings.tool = "T1";
    cases[4].settings.part.part = "samples/parts/six_surfaces.stl";
    cases[5].settings.feed_limit_N = 150;
    cases[6].settings.feed_limit_N = 40;
    int compared = 0, failed = 0;
    for (const Case& c : cases) {
      job::Settings w = c.settings;
      w.output = dir / "whole.nc";
      fs::remove(w.output);
      const auto whole = compensate_in("0", w);
      failed += !whole.ok();
      for (const char* n : c.lines) {
        CAPTURE(c.settings.program);
        CAPTURE(n);
        job::Settings p = c.settings;
        p.output = dir / "pieces.nc";
        fs::remove(p.output);
        const auto got = compensate_in(n, p);
        same_run(got, whole);
        CHECK(got.out.empty());  // into the file
        CHECK(fs::exists(p.output) == fs::exists(w.output));
        if (fs::exists(w.output)) CHECK(test::read_file(p.output) == test::read_file(w.output));
        ++compared;
      }
      // To the output stream: the same bytes, after the check.
      if (whole.ok()) {
        const auto out = compensate_in(c.lines[0], c.settings);
        REQUIRE(out.ok());
        CHECK(out.out == test::read_file(w.output));
      }
    }
    CHECK(compared == 12);
    CHECK(failed == 3);  // bad.nc, tool.nc and the pocket's floor pass too deep for T5
  }

  TEST_CASE("simulate in pieces: the summary and messages of the whole program") {
    for (const char* n : {"1", "30"}) {
      for (const job::Settings& s : {on("samples/programs/freeform.nc", "samples/stock/freeform_stock.stl"),
                                     on("samples/programs/side_wall.nc", "box:0,-40,-30,100,0,0")}) {
        CAPTURE(n);
        CAPTURE(s.program);
        const auto whole = [&] {
          PieceLines p("0");
          return test::simulate_job(s);
        }();
        const auto got = [&] {
          PieceLines p(n);
          return test::simulate_job(s);
        }();
        REQUIRE(whole.ok());
        same_run(got, whole);
        REQUIRE(got.ok());
        CHECK(report::document(got.result->summary) == report::document(whole.result->summary));
        CHECK(whole.result->figures.error.points > 0);
      }
    }
  }

  TEST_CASE("report in pieces: every file of the folder byte for byte that of the whole program") {
    test::TempDir dir("rpieces");
    ::setenv("SOURCE_DATE_EPOCH", "1700000000", 1);  // the page's date
    struct Case {
      job::Settings settings;
      bool compensate = true;
    };
    std::vector<Case> cases = {
        {on("samples/programs/freeform.nc", "samples/stock/freeform_stock.stl")},
        {on("samples/programs/six_surfaces.nc", "samples/stock/six_surfaces_stock.stl")},
        {on("samples/programs/side_wall.nc", "box:0,-40,-30,100,0,0")},
        {on("samples/programs/pocket_finish.nc", "box:-5,-5,-20,105,85,0")},
        {on("samples/programs/freeform.nc", "samples/stock/freeform_stock.stl"), false}};
    cases[1].settings.part.part = "samples/parts/six_surfaces.stl";
    cases[2].settings.feed_limit_N = 150;
    cases[3].settings.gain = 0;
    cases[3].settings.stock_from = test::pocket_predrilled();
    const std::vector<std::string> files = {"points.csv", "summary.json", "report.html", "flank_profile.csv"};
    int compared = 0;
    for (const Case& c : cases) {
      CAPTURE(c.settings.program);
      CAPTURE(c.compensate);
      // Into the same folder (its name may be in the page), moved aside after.
      auto run = [&](const std::string& lines, const fs::path& keep) {
        job::Settings s = c.settings;
        s.report_dir = dir / "report";
        if (c.compensate) s.output = dir / "out.nc";
        PieceLines p(lines);
        std::pair<bool, std::string> ran;  // whether it ended well, its messages
        if (c.compensate) {
          const auto r = test::compensate_job(s);
          ran = {r.ok(), r.err};
        } else {
          const auto r = test::simulate_job(s);
          ran = {r.ok(), r.err};
        }
        if (fs::exists(dir / "report")) fs::rename(dir / "report", keep);
        return ran;
      };
      fs::remove_all(dir / "whole");
      fs::remove_all(dir / "pieces");
      const auto whole = run("0", dir.p / "whole"), pieces = run("37", dir.p / "pieces");
      CAPTURE(whole.second);
      REQUIRE(whole.first);
      CHECK(pieces.first);
      CHECK(pieces.second == whole.second);
      for (const std::string& f : files) {
        CAPTURE(f);
        REQUIRE(fs::exists(dir.p / "whole" / f) == fs::exists(dir.p / "pieces" / f));
        if (!fs::exists(dir.p / "whole" / f)) continue;
        const std::string w = test::read_file(dir / ("whole/" + f));
        CHECK(w.size() > 100);
        const bool same = test::read_file(dir / ("pieces/" + f)) == w;  // (not printed: a page is MBs)
        CHECK(same);
        ++compared;
      }
      // Nothing but the report's files is left in the folder (no spill, no temporary).
      for (const auto& e : fs::directory_iterator(dir.p / "pieces"))
        CHECK(std::find(files.begin(), files.end(), e.path().filename().string()) != files.end());
    }
    ::unsetenv("SOURCE_DATE_EPOCH");
    CHECK(compared >= 15);
  }
}
