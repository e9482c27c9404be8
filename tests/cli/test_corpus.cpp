// File-driven tests: the bad-input corpus (its expectations are what `check`
// prints, settings named by their flags), golden CLI runs, what diff prints,
// the byte-identical round trip of every program we have, and LinuxCNC's
// rs274 as an independent interpreter. Diff's pairing goes through the job
// API (tests/job/test_diff.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <regex>
#include <sstream>
#include <unistd.h>

#include "../support.hpp"
#include "deflex/writer/writer.hpp"

using namespace deflex;
namespace fs = std::filesystem;

namespace {

std::vector<fs::path> files_in(const fs::path& dir, std::initializer_list<const char*> exts) {
  std::vector<fs::path> v;
  if (!fs::exists(dir)) return v;
  for (auto& e : fs::recursive_directory_iterator(dir))
    for (const char* x : exts)
      if (e.is_regular_file() && e.path().extension() == x) v.push_back(e.path());
  std::sort(v.begin(), v.end());
  return v;
}

std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> v;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);)
    if (!l.empty()) v.push_back(l);
  return v;
}

// The CAM programs of tests/data/corpus (its README names their source): all
// four, or the tests that read them fail rather than read fewer.
std::vector<fs::path> cam_corpus() {
  const std::vector<fs::path> v = files_in("tests/data/corpus", {".nc", ".gcode"});
  REQUIRE(v.size() == 4);
  return v;
}

}  // namespace

TEST_SUITE("cli") {

TEST_CASE("bad-input corpus: each file produces the diagnostic its first line names") {
  auto files = files_in("tests/bad", {".nc"});
  REQUIRE(files.size() >= 20);
  for (const fs::path& f : files) {
    std::string text = test::read_file(f.string());
    std::string first = text.substr(0, text.find('\n'));
    REQUIRE_MESSAGE(first.rfind("; expect: ", 0) == 0, f.string());
    std::string expect = f.string() + ":" + first.substr(10);
    auto r = test::run_cli({"check", f.string(), "--dialect", "fanuc"});
    CHECK_MESSAGE(r.rc == 1, f.string());
    CHECK_MESSAGE(r.err.find(expect) != std::string::npos, (f.string() + "\nexpected: " + expect + "\ngot: " + r.err));
    // ... with the source line and a caret under the column.
    CHECK_MESSAGE(r.err.find("\n  ") != std::string::npos, f.string());
  }
}

TEST_CASE("golden CLI runs: stdout, stderr and exit code") {
  // Regression snapshots of deflex's own output (tests/golden/regen.sh): they
  // catch any change, not a wrong one. The physics under the wall runs'
  // figures is checked independently in test_golden_wall.cpp.
  auto cases = files_in("tests/golden", {".args"});
  REQUIRE(cases.size() >= 8);
  for (const fs::path& c : cases) {
    std::vector<std::string> args = split_lines(test::read_file(c.string()));
    fs::path base = c;
    base.replace_extension();
    std::string in = fs::exists(base.string() + ".stdin") ? test::read_file(base.string() + ".stdin") : "";
    auto r = test::run_cli(args, in);
    std::string want_out = test::read_file(base.string() + ".stdout");
    std::string want_err = fs::exists(base.string() + ".stderr") ? test::read_file(base.string() + ".stderr") : "";
    int want_rc = std::stoi(test::read_file(base.string() + ".rc"));
    CHECK_MESSAGE(r.rc == want_rc, c.string());
    CHECK_MESSAGE(r.out == want_out, (c.string() + "\n--- got stdout:\n" + r.out));
    CHECK_MESSAGE(r.err == want_err, (c.string() + "\n--- got stderr:\n" + r.err));
  }
}

TEST_CASE("diff prints an inserted split block and a moved line (job::diff's pairing: tests/job/test_diff.cpp)") {
  test::TempDir dir("diff");
  test::write_file(dir / "a.nc", test::kDiffSplitA);
  test::write_file(dir / "b.nc", test::kDiffSplitB);
  auto r = test::run_cli({"diff", dir / "a.nc", dir / "b.nc", "--dialect", "fanuc"});
  CHECK(r.rc == 0);
  CHECK(r.out.find("+4: inserted, splits the move of line 4; 0.000000 mm off it") != std::string::npos);
  CHECK(r.out.find("4 -> 5: dX +0.000000 dY +0.010000 dZ +0.000000 |d| 0.010000 mm") != std::string::npos);
  CHECK(r.out.find("max 0.010000 mm") != std::string::npos);
}

TEST_CASE("round trip: every program read and written back is byte-identical") {
  std::vector<fs::path> all;
  for (auto dir : {fs::path("samples"), fs::path("tests")})  // tests/ holds the CAM corpus
    for (auto& f : files_in(dir, {".nc", ".ngc", ".gcode", ".tap"})) all.push_back(f);
  REQUIRE(all.size() >= 25);
  auto fanuc = profile::load_dialect("fanuc");
  for (const fs::path& f : all) {
    std::string bytes = test::read_file(f.string());
    gcode::Program p(SourceText(f.string(), bytes));
    writer::Rewriter w(p, fanuc);
    CHECK_MESSAGE(w.str() == bytes, f.string());
  }
  // Through the command, for programs that interpret cleanly.
  for (const fs::path& f : cam_corpus()) {
    std::string dialect = f.extension() == ".gcode" ? "linuxcnc" : "fanuc";
    auto r = test::run_cli({"rewrite", f.string(), "--dialect", dialect});
    CHECK_MESSAGE(r.rc == 0, (f.string() + r.err));
    CHECK_MESSAGE(r.out == test::read_file(f.string()), f.string());
  }
}

TEST_CASE("rs274 (LinuxCNC) and deflex give the same end points within 1e-4 mm") {
  // LinuxCNC's example programs that use no LinuxCNC-only syntax (no o-words,
  // #parameters, expressions, ^ or cutter compensation), and the CAM corpus.
  std::vector<fs::path> progs;
  for (const char* n : {"3dtest.ngc", "arcspiral.ngc", "cds.ngc", "plasmatest.ngc", "tort.ngc"})
    progs.push_back(fs::path("/usr/share/linuxcnc/ncfiles") / n);
  for (auto& f : cam_corpus()) progs.push_back(f);
  REQUIRE_MESSAGE(fs::exists("/usr/bin/rs274"), "rs274 missing: run scripts/install-deps.sh --test");
  for (const fs::path& f : progs) {
    REQUIRE_MESSAGE(fs::exists(f), f.string());
    fs::path out = fs::temp_directory_path() / ("deflex-rs274-" + f.filename().string() + ".txt");
    std::string cmd = "/usr/bin/rs274 -g '" + f.string() + "' '" + out.string() + "' </dev/null >/dev/null 2>&1";
    REQUIRE(std::system(cmd.c_str()) == 0);
    // Parse rs274's canonical calls; its numbers are in program units, 4 decimals.
    struct Ref { std::string kind; std::array<double, 3> p; bool inch; };
    std::vector<Ref> ref;
    double units = 1.0;
    std::string plane = "XY";
    std::regex call(R"((USE_LENGTH_UNITS|SELECT_PLANE|STRAIGHT_TRAVERSE|STRAIGHT_FEED|ARC_FEED)\((.*)\))");
    std::istringstream in(test::read_file(out.string()));
    for (std::string line; std::getline(in, line);) {
      std::smatch m;
      if (!std::regex_search(line, m, call)) continue;
      std::string k = m[1], a = m[2];
      if (k == "USE_LENGTH_UNITS") { units = a.find("INCH") != std::string::npos ? 25.4 : 1.0; continue; }
      if (k == "SELECT_PLANE") { plane = a.substr(a.rfind('_') + 1); continue; }
      std::vector<double> v;
      std::istringstream as(a);
      for (std::string t; std::getline(as, t, ',') && v.size() < 6;) v.push_back(std::stod(t));
      std::array<double, 3> p{};
      std::string kind;
      if (k == "ARC_FEED") {
        if (plane == "XY") p = {v[0], v[1], v[5]};
        else if (plane == "XZ") p = {v[1], v[5], v[0]};
        else p = {v[5], v[0], v[1]};
        kind = v[4] < 0 ? "G2" : "G3";
      } else {
        p = {v[0], v[1], v[2]};
        kind = k == "STRAIGHT_TRAVERSE" ? "G0" : "G1";
      }
      for (double& x : p) x *= units;
      ref.push_back({kind, p, units != 1.0});
    }
    fs::remove(out);
    std::string dialect = "linuxcnc";
    auto ours = test::interpret_text(test::read_file(f.string()), dialect);
    CHECK_MESSAGE(ours.errors == 0, (f.string() + ours.diagnostics));
    // rs274 emits zero-length traverses on G49 and tool changes: drop
    // zero-length moves on both sides (both start at 0,0,0) before pairing.
    std::vector<Ref> mine, theirs;
    std::array<double, 3> last{0, 0, 0};
    for (const auto& m : ours.motions) {
      std::array<double, 3> e{m.end_mm[0], m.end_mm[1], m.end_mm[2]};
      if (e != last) mine.push_back({interp::to_string(m.kind), e, false});
      last = e;
    }
    last = {0, 0, 0};
    for (auto& r : ref) {
      if (r.p != last) theirs.push_back(r);
      last = r.p;
    }
    REQUIRE_MESSAGE(mine.size() == theirs.size(), f.string());
    // rs274 prints 4 decimals in program units, so its own figures carry up to
    // half a last digit of rounding: 0.00005 mm in G21, 0.00005 in = 1.27 um in
    // G20. The bound is 1e-4 mm beyond that print resolution.
    double worst = 0, worst_excess = 0;
    std::size_t bad = 0;
    for (std::size_t i = 0; i < mine.size(); ++i) {
      if (mine[i].kind != theirs[i].kind) ++bad;
      double half_digit_mm = theirs[i].inch ? 0.5e-4 * 25.4 : 0.5e-4;
      for (int k = 0; k < 3; ++k) {
        double diff = std::fabs(mine[i].p[k] - theirs[i].p[k]);
        worst = std::max(worst, diff);
        worst_excess = std::max(worst_excess, diff - half_digit_mm);
      }
    }
    CHECK_MESSAGE(bad == 0, f.string());
    CHECK_MESSAGE(worst_excess <= 1e-4, (f.string() + " worst " + std::to_string(worst)));
    MESSAGE(f.filename().string() << ": " << mine.size() << " motions, worst difference " << worst << " mm");
  }
}

}  // TEST_SUITE
