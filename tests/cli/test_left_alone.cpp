// Every move left alone says why: points outside the
// tolerance on moves deflex does not move are counted per reason and named at
// the first line, never silently missing from "N points compensated".
#include <doctest/doctest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "../support.hpp"
#include "deflex/report/json.hpp"

#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace deflex;

namespace {

// The sample side wall with its first pass (line 16) rewritten by `edit`.
std::string wall_with(const fs::path& dir, const std::string& name, const std::string& pass) {
  std::string text = test::read_file("samples/programs/side_wall.nc");
  const std::string first = "N22 X110. F2546.4\n";
  REQUIRE(text.find(first) != std::string::npos);
  text.replace(text.find(first), first.size(), pass);
  const std::string p = (dir / name).string();
  test::write_file(p, text);
  return p;
}

// deflex compensate of a side wall program on the sample's stock, `more` options after.
test::CliResult compensate_wall(const std::string& in, const std::string& out, std::vector<std::string> more = {}) {
  std::vector<std::string> a = {"compensate", in, "-o", out, "--stock", "box:0,-40,-30,100,0,0"};
  a.insert(a.end(), more.begin(), more.end());
  return test::run_cli(a);
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> v;
  std::size_t a = 0;
  for (std::size_t b; (b = text.find('\n', a)) != std::string::npos; a = b + 1) v.push_back(text.substr(a, b - a));
  return v;
}

}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("G91: walls, arcs and a pocket cut in increments are compensated as the same cuts in G90; every later position is the original's") {
    const fs::path dir = fs::temp_directory_path() / ("deflex-g91-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    // The first pass as an increment from X-10, its block setting G91 itself.
    const std::string g91 = wall_with(dir, "wall91.nc", "N22 G91 X120. F2546.4\nN23 G90\n");
    const auto compensate = [](const std::string& in, const std::string& out) { return compensate_wall(in, out); };
    const std::string out90 = (dir / "out90.nc").string(), out91 = (dir / "out91.nc").string();
    REQUIRE(compensate("samples/programs/side_wall.nc", out90).rc == 0);
    const test::CliResult r91 = compensate(g91, out91);
    CAPTURE(r91.err);
    REQUIRE(r91.rc == 0);
    CHECK(r91.err.find("[left_alone]") == std::string::npos);
    // The same compensated path, point for point (the written digits: exact).
    const std::string p90 = test::run_cli({"path", out90}).out, p91 = test::run_cli({"path", out91}).out;
    CHECK(p91 == p90);
    // The blocks deflex put in before the G91 block are increments in G91 too.
    // Their digits are a regression snapshot of deflex's output (the first
    // step of the offset ramp into the material, -Y); what the physics must
    // show is checked on the same run's points.csv below.
    const std::string text = test::read_file(out91);
    CHECK(text.find("G91 G1 X6.667 Y-0.02 Z0. F2546.4\n") != std::string::npos);
    CHECK(text.find("N22 G91 X110. Y0.02 F2546.4\n") != std::string::npos);
    const test::CliResult rep91 = compensate_wall(g91, (dir / "rep91.nc").string(), {"--report", (dir / "rep91").string()});
    REQUIRE(rep91.rc == 0);
    test::check_deflection_physics(test::read_csv((dir / "rep91/points.csv").string()), 0.01);
    // Every rapid ends where the original's does.
    const std::vector<std::string> orig = lines_of(test::run_cli({"path", g91}).out), comp = lines_of(p91);
    std::vector<std::string> rapids_o, rapids_c;
    for (const auto& l : orig) if (l.starts_with("G0 ")) rapids_o.push_back(l);
    for (const auto& l : comp) if (l.starts_with("G0 ")) rapids_c.push_back(l);
    CHECK(rapids_o.size() >= 4);
    CHECK(rapids_c == rapids_o);
    // Read in pieces: the same bytes.
    ::setenv("DEFLEX_CHUNK_LINES", "3", 1);
    const std::string outp = (dir / "out91p.nc").string();
    CHECK(compensate(g91, outp).err == r91.err);
    ::unsetenv("DEFLEX_CHUNK_LINES");
    CHECK(test::read_file(outp) == text);
    // A program in G91 throughout (two passes, G91 rapids between them), read
    // back by LinuxCNC's rs274: every rapid of the output is the original's.
    const std::string inc = (dir / "inc.nc").string(), incc = (dir / "incc.nc").string();
    test::write_file(inc,
                     "%\nO1\nG21 G90 G17 G40 G49 G80\nT6 M06\nG00 G54 X-10. Y3.5 S6366 M03\nG43 H6 Z50.\nZ5.\n"
                     "G01 Z-12. F1000.\nG91\nG1 X40. F2546.4\nG1 X40.\nG1 X40.\nG0 Z17.\nG0 X-120. Y-2.5\n"
                     "G1 Z-17. F1000.\nG1 X60. F2546.4\nG1 X60.\nG0 Z62.\nG90\nM30\n%\n");
    const test::CliResult ri = compensate(inc, incc);
    REQUIRE(ri.rc == 0);
    CHECK(ri.err.find("0 points compensated") == std::string::npos);
    REQUIRE_MESSAGE(fs::exists("/usr/bin/rs274"), "rs274 missing: run scripts/install-deps.sh --test");
    test::write_file((dir / "tools.tbl").string(), "T6 P6 Z0 D12 ;\n");
    auto traverses = [&](const std::string& prog) {
      const std::string out = (dir / "rs274.txt").string();
      const std::string cmd = "/usr/bin/rs274 -t " + (dir / "tools.tbl").string() + " -g " + prog + " " + out +
                              " </dev/null >/dev/null 2>&1";
      REQUIRE(std::system(cmd.c_str()) == 0);
      std::vector<std::string> v;
      for (const std::string& l : lines_of(test::read_file(out)))
        if (l.find("STRAIGHT_TRAVERSE") != std::string::npos) v.push_back(l.substr(l.find("N.....")));
      return v;
    };
    const std::vector<std::string> t0 = traverses(inc), t1 = traverses(incc);
    CHECK(t0.size() >= 5);
    CHECK(t1 == t0);
    CHECK(test::read_file(incc) != test::read_file(inc));
    // Arcs in G91 (I/J/K and R): the pocket sample's finishing pass rewritten
    // in increments, judged at 0.5 um so most of it is compensated (and its
    // G2 linearised): the same compensated path as the sample in G90.
    std::string pocket = test::read_file("samples/programs/pocket_finish.nc");
    const std::vector<std::pair<std::string, std::string>> to_g91 = {
        {"N60 G01 Z-1. F400.\n", "N60 G01 Z-1. F400.\nN65 G91\n"}, {"N70 X60.\n", "N70 X80.\n"},
        {"N80 Y-8.5\n", "N80 Y1.5\n"}, {"N90 X-20.\n", "N90 X-80.\n"}, {"N100 Y-7.\n", "N100 Y1.5\n"},
        {"N110 X60.\n", "N110 X80.\n"}, {"N120 G02 X70. Y3. I0. J10.\n", "N120 G02 X10. Y10. I0. J10.\n"},
        {"N130 G01 Y20.\n", "N130 G01 Y17.\n"}, {"N140 G03 X60. Y30. R10.\n", "N140 G03 X-10. Y10. R10.\n"},
        {"N150 G01 X-20.\n", "N150 G01 X-80.\nN155 G90\n"}};
    for (const auto& [from, to] : to_g91) {
      REQUIRE(pocket.find(from) != std::string::npos);
      pocket.replace(pocket.find(from), from.size(), to);
    }
    const std::string pocket91 = (dir / "pocket91.nc").string();
    test::write_file(pocket91, pocket);
    REQUIRE(test::run_cli({"path", pocket91}).out == test::run_cli({"path", "samples/programs/pocket_finish.nc"}).out);
    auto tight = [&](const std::string& in, const std::string& out) {
      return test::run_cli({"compensate", in, "--stock", "box:-5,-5,-20,105,85,0", "--tolerance", "0.0005", "-o", out});
    };
    const test::CliResult a90 = tight("samples/programs/pocket_finish.nc", (dir / "pa.nc").string()),
                          a91 = tight(pocket91, (dir / "pb.nc").string());
    REQUIRE(a90.rc == 0);
    REQUIRE(a91.rc == 0);
    CHECK(a91.err.find("blocks inserted") != std::string::npos);
    // No move is left alone for being in G91: what stays (the ball's points on
    // this single contour, whose normal the path cannot determine) stays alike.
    CHECK(a91.err.find("incremental") == std::string::npos);
    auto left_alone = [](const std::string& err) {
      const std::size_t at = err.find("[left_alone]");
      return at == std::string::npos ? std::string() : err.substr(err.rfind(": warning:", at), at - err.rfind(": warning:", at));
    };
    CHECK(left_alone(a91.err) == left_alone(a90.err));
    CHECK(test::run_cli({"path", (dir / "pb.nc").string()}).out == test::run_cli({"path", (dir / "pa.nc").string()}).out);
    fs::remove_all(dir);
  }

  TEST_CASE("G91 sample: the side wall written in increments compensates as the side wall sample") {
    const fs::path dir = fs::temp_directory_path() / ("deflex-g91s-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string g90 = "samples/programs/side_wall.nc", g91 = "samples/programs/side_wall_g91.nc";
    REQUIRE(test::run_cli({"path", g91}).out == test::run_cli({"path", g90}).out);
    const std::string out90 = (dir / "a.nc").string(), out91 = (dir / "b.nc").string();
    const test::CliResult a = compensate_wall(g90, out90), b = compensate_wall(g91, out91);
    REQUIRE(a.rc == 0);
    REQUIRE(b.rc == 0);
    // Both passes, each followed by a rapid in G91 (whose increment takes the
    // tool back to where the original goes): the same compensated path.
    CHECK(a.err.substr(a.err.find("predicted error")) == b.err.substr(b.err.find("predicted error")));
    CHECK(b.err.find("[left_alone]") == std::string::npos);
    CHECK(test::run_cli({"path", out91}).out == test::run_cli({"path", out90}).out);
    CHECK(test::read_file(out91).find("N24 G00 Y0.079 Z17.\n") != std::string::npos);
    fs::remove_all(dir);
  }

  TEST_CASE("left alone: a compensable pass whose end starts a block deflex cannot move is named, not silent") {
    const fs::path dir = fs::temp_directory_path() / ("deflex-held-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    // The first pass ends where a drilling cycle starts: its end stays, and
    // so does the pass (nothing to ramp to).
    const std::string in = wall_with(dir, "held.nc", "N22 X110. F2546.4\nN23 G99 G81 X110. Y3.5 Z-12.5 R-11. F200.\nN23 G80\n");
    const test::CliResult r = compensate_wall(in, (dir / "out.nc").string());
    REQUIRE(r.rc == 0);
    CHECK(r.err.find("held.nc:16:1: warning: 207 points outside +-0.0100 mm are left as programmed on moves ending where "
                     "a block deflex cannot re-target starts") != std::string::npos);
    fs::remove_all(dir);
  }

  TEST_CASE("left alone: a pass deflex does not move is named with its count, on stderr and in summary.json") {
    const fs::path dir = fs::temp_directory_path() / ("deflex-left-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    // The first pass as a block-delete block (run or not at the operator's switch).
    const std::string prog = wall_with(dir, "wall_bd.nc", "/N22 X110. F2546.4\n");
    auto run = [&](const std::string& p, const fs::path& report) {
      return compensate_wall(p, (dir / "out.nc").string(), {"--report", report.string()});
    };
    const test::CliResult bd = run(prog, dir / "rbd"), plain = run("samples/programs/side_wall.nc", dir / "r90");
    REQUIRE(bd.rc == 0);
    REQUIRE(plain.rc == 0);
    const std::string want = prog + ":16:1: warning: ";
    const std::size_t at = bd.err.find(want);
    REQUIRE(at != std::string::npos);
    const std::string line = bd.err.substr(at, bd.err.find('\n', at) - at);
    CHECK(line.find("points outside +-0.0100 mm are left as programmed on block-delete '/' moves") != std::string::npos);
    CHECK(line.find("[left_alone]") != std::string::npos);
    const report::Json s = report::Json::parse(test::read_file((dir / "rbd/summary.json").string()));
    REQUIRE(s["left_alone"].size() == 1);
    CHECK(s["left_alone"][0]["reason"] == "block delete '/'");
    CHECK(s["left_alone"][0]["first_line"] == 16);
    // The count is the first pass's points outside the tolerance: on the plain
    // program the same pass is compensated, and nothing is left alone.
    const std::size_t n = s["left_alone"][0]["points"];
    CHECK(n > 150);
    CHECK(n <= s["cl_points"].get<std::size_t>());
    CHECK(plain.err.find("[left_alone]") == std::string::npos);
    CHECK(report::Json::parse(test::read_file((dir / "r90/summary.json").string()))["left_alone"].empty());
    fs::remove_all(dir);
  }
}

TEST_SUITE("cli") {
  TEST_CASE("left as written: one note per reason with the block count and the first line, in pieces too") {
    const std::vector<std::string> a = {"compensate", "samples/programs/pocket_finish.nc", "--stock",
                                        "box:-5,-5,-20,105,85,0", "-o", "/tmp/deflex-left-pf.nc"};
    const test::CliResult r = test::run_cli(a);
    REQUIRE(r.rc == 0);
    const std::string note =
        "samples/programs/pocket_finish.nc: note: 2 executed blocks stay as written: canned-cycle moves (drilling is not a "
        "surface); the first at line 21\n";
    CHECK(r.err.find(note) != std::string::npos);
    CHECK(r.err.find("canned-cycle") == r.err.rfind("canned-cycle"));  // once, not per block
    ::setenv("DEFLEX_CHUNK_LINES", "5", 1);
    const test::CliResult p = test::run_cli(a);
    ::unsetenv("DEFLEX_CHUNK_LINES");
    CHECK(p.err == r.err);
    // The plain side wall has no such move: no note.
    CHECK(test::run_cli({"compensate", "samples/programs/side_wall.nc", "--stock", "box:0,-40,-30,100,0,0", "-o",
                         "/tmp/deflex-left-sw.nc"})
              .err.find("stay as written") == std::string::npos);
  }
}
