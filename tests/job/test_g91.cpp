// Moves in G91 (increments) through job::compensate: walls, arcs and a pocket
// cut in increments are compensated as the same cuts in G90, none is left
// alone for being incremental, and every later position is the original's.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> v;
  std::size_t a = 0;
  for (std::size_t b; (b = text.find('\n', a)) != std::string::npos; a = b + 1) v.push_back(text.substr(a, b - a));
  return v;
}

// The rapids of a path: every line starting "G0 ".
std::vector<std::string> rapids(const std::string& path) {
  std::vector<std::string> v;
  for (const auto& l : lines_of(path))
    if (l.starts_with("G0 ")) v.push_back(l);
  return v;
}

// The traverses LinuxCNC's rs274 reads in `prog` with T6 a D12 (its table).
std::vector<std::string> rs274_traverses(const test::TempDir& dir, const std::string& prog) {
  REQUIRE_MESSAGE(fs::exists("/usr/bin/rs274"), "rs274 missing: run scripts/install-deps.sh --test");
  test::write_file(dir / "tools.tbl", "T6 P6 Z0 D12 ;\n");
  const std::string out = dir / "rs274.txt";
  const std::string cmd =
      "/usr/bin/rs274 -t " + dir / "tools.tbl" + " -g " + prog + " " + out + " </dev/null >/dev/null 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::vector<std::string> v;
  for (const std::string& l : lines_of(test::read_file(out)))
    if (l.find("STRAIGHT_TRAVERSE") != std::string::npos) v.push_back(l.substr(l.find("N.....")));
  return v;
}

// The [left_alone] warning of a run's messages, from ": warning:" on ("": none).
std::string left_alone(const std::string& err) {
  const std::size_t at = err.find("[left_alone]");
  return at == std::string::npos ? std::string() : err.substr(err.rfind(": warning:", at), at - err.rfind(": warning:", at));
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("G91: a wall pass in increments is compensated as the same pass in G90; every rapid ends as the original's") {
    test::TempDir dir("g91");
    // The first pass as an increment from X-10, its block setting G91 itself.
    const std::string g91 = test::side_wall_with(dir, "wall91.nc", "N22 G91 X120. F2546.4\nN23 G90\n");
    const std::string out90 = dir / "out90.nc", out91 = dir / "out91.nc";
    REQUIRE(test::compensate_side_wall("samples/programs/side_wall.nc", out90).ok());
    const auto r91 = test::compensate_side_wall(g91, out91, dir / "rep91");
    CAPTURE(r91.err);
    REQUIRE(r91.ok());
    CHECK(r91.err.find("[left_alone]") == std::string::npos);
    // The same compensated path, point for point (the written digits: exact).
    const std::string p91 = test::path_text(out91);
    CHECK(p91 == test::path_text(out90));
    // The blocks deflex put in before the G91 block are increments in G91 too.
    // Their digits are a regression snapshot of deflex's output (the first
    // step of the offset ramp into the material, -Y); what the physics must
    // show is checked on the same run's points.csv below.
    const std::string text = test::read_file(out91);
    CHECK(text.find("G91 G1 X5.714 Y-0.02 Z0. F2546.4\n") != std::string::npos);
    CHECK(text.find("N22 G91 X10.452 F2546.4\n") != std::string::npos);
    test::check_deflection_physics(test::read_csv(dir / "rep91/points.csv"), 0.01);
    // Every rapid ends where the original's does.
    const std::vector<std::string> rapids_o = rapids(test::path_text(g91));
    CHECK(rapids_o.size() >= 4);
    CHECK(rapids(p91) == rapids_o);
    // Read in pieces: the same bytes.
    const std::string outp = dir / "out91p.nc";
    {
      test::PieceLines p("3");
      const auto rp = test::compensate_side_wall(g91, outp, dir / "rep91p");
      CHECK(rp.err == r91.err);
    }
    CHECK(test::read_file(outp) == text);
  }

  TEST_CASE("G91 throughout: every rapid of the compensated program is the original's, read back by LinuxCNC's rs274") {
    test::TempDir dir("g91");
    // Two passes, G91 rapids between them.
    const std::string inc = dir / "inc.nc", incc = dir / "incc.nc";
    test::write_file(inc,
                     "%\nO1\nG21 G90 G17 G40 G49 G80\nT6 M06\nG00 G54 X-10. Y3.5 S6366 M03\nG43 H6 Z50.\nZ5.\n"
                     "G01 Z-12. F1000.\nG91\nG1 X40. F2546.4\nG1 X40.\nG1 X40.\nG0 Z17.\nG0 X-120. Y-2.5\n"
                     "G1 Z-17. F1000.\nG1 X60. F2546.4\nG1 X60.\nG0 Z62.\nG90\nM30\n%\n");
    const auto ri = test::compensate_side_wall(inc, incc);
    REQUIRE(ri.ok());
    CHECK(ri.result->result.compensated_points > 0);
    const std::vector<std::string> t0 = rs274_traverses(dir, inc), t1 = rs274_traverses(dir, incc);
    CHECK(t0.size() >= 5);
    CHECK(t1 == t0);
    CHECK(test::read_file(incc) != test::read_file(inc));
  }

  TEST_CASE("G91 arcs (I/J/K and R): the pocket's finishing pass in increments compensates as in G90") {
    test::TempDir dir("g91");
    // The pocket sample's finishing pass rewritten in increments, judged at
    // 0.5 um so most of it is compensated (and its G2 linearised).
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
    const std::string pocket91 = dir / "pocket91.nc";
    test::write_file(pocket91, pocket);
    REQUIRE(test::path_text(pocket91) == test::path_text("samples/programs/pocket_finish.nc"));
    auto tight = [&](const std::string& in, const std::string& out) {
      job::Settings s;
      s.program = in;
      s.stock = "box:-5,-5,-20,105,85,0";
      s.stock_from = test::pocket_predrilled();
      s.tolerance_mm = 0.0005;
      s.output = out;
      return test::compensate_job(s);
    };
    const auto a90 = tight("samples/programs/pocket_finish.nc", dir / "pa.nc"), a91 = tight(pocket91, dir / "pb.nc");
    REQUIRE(a90.ok());
    REQUIRE(a91.ok());
    CHECK(a91.result->written.blocks_inserted > 0);
    // No move is left alone for being in G91: what stays (the ball's points on
    // this single contour, whose normal the path cannot determine) stays alike.
    CHECK(a91.err.find("incremental") == std::string::npos);
    CHECK(left_alone(a91.err) == left_alone(a90.err));
    CHECK(test::path_text(dir / "pb.nc") == test::path_text(dir / "pa.nc"));
  }

  TEST_CASE("G91 sample: the side wall written in increments compensates as the side wall sample") {
    test::TempDir dir("g91s");
    const std::string g90 = "samples/programs/side_wall.nc", g91 = "samples/programs/side_wall_g91.nc";
    REQUIRE(test::path_text(g91) == test::path_text(g90));
    const std::string out90 = dir / "a.nc", out91 = dir / "b.nc";
    const auto a = test::compensate_side_wall(g90, out90), b = test::compensate_side_wall(g91, out91);
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    // Both passes, each followed by a rapid in G91 (whose increment takes the
    // tool back to where the original goes): the same compensated path.
    CHECK(test::summary_but_lines(*a.result) == test::summary_but_lines(*b.result));
    CHECK(b.err.find("[left_alone]") == std::string::npos);
    CHECK(test::path_text(out91) == test::path_text(out90));
    CHECK(test::read_file(out91).find("N24 G00 Z17.\n") != std::string::npos);
  }
}
