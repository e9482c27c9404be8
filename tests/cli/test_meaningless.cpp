// Runs that pass every range check but mean nothing: a stock no cutting move
// reaches, a tolerance that moves nothing, a gain that over-corrects. Each is
// said before the simulation (an error under --strict), never a silent
// "0 points outside".
#include <doctest/doctest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <unistd.h>

#include "../support.hpp"

using namespace deflex;

namespace {

// bear.nc's first 14 lines: a D10 flat end slotting 80 mm along X at Z-17.368.
const std::string kSlot =
    "T1M6\nG21\nG17\nG0Z20.000\nG0X0.000Y0.000S15000M3\nG0X0.001Y0.001Z10.000\nG1Z-17.368F6000.0\n"
    "G1X0.161\nX79.999\nY0.126\nY0.501\nX79.839\nX0.001\nY0.626\nM30\n";

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

}  // namespace

TEST_SUITE("cli") {

TEST_CASE("a stock no cutting move reaches is said, with both extents, before anything is simulated") {
  for (const char* stock : {"box:500,500,-10,600,600,0",  // another part's blank
                            "box:0,0,-30,80,80,-20"}) {    // below every cut
    INFO(stock);
    const auto r = test::run_cli({"compensate", "-", "--stock", stock, "--threads", "1"}, kSlot);
    CHECK(r.rc == 0);
    CHECK(has(r.err, "warning: no cutting move reaches the stock: the cutting moves' tips span X 0.001..79.999 "
                     "Y 0.001..0.626 Z -17.368..10.000 mm (tools up to R 5.000 mm)"));
    CHECK(r.out == kSlot);  // nothing to move: the program as written
    // --strict: an error, nothing written, no simulation run.
    const auto s = test::run_cli({"compensate", "-", "--stock", stock, "--strict", "--threads", "1"}, kSlot);
    CHECK(s.rc == 1);
    CHECK(s.out.empty());
    CHECK(has(s.err, "error: no cutting move reaches the stock"));
    CHECK_FALSE(has(s.err, "predicted error"));
  }
  // A stock the plunge alone removes (an 80 mm part's blank typed in inch):
  // the moves reach it, but no point is in material after the plunge.
  const auto r = test::run_cli({"simulate", "-", "--stock", "box:0,0,-25,3.15,3.15,0", "--threads", "1"}, kSlot);
  CHECK(r.rc == 0);
  CHECK(has(r.err, "none of the 380 cutting points is in the stock"));
  CHECK(has(r.err, "[no_material]"));
  // The stock the program cuts: neither.
  const auto ok = test::run_cli({"simulate", "-", "--stock", "box:0,0,-25,80,80,0", "--threads", "1"}, kSlot);
  CHECK_FALSE(has(ok.err, "reaches the stock"));
  CHECK_FALSE(has(ok.err, "[no_material]"));
}

TEST_CASE("a tolerance at or over the offset cap and a gain over 1 are warned (errors under --strict)") {
  const std::vector<std::string> base = {"compensate", "-", "--stock", "box:0,0,-25,80,80,0", "--threads", "1"};
  auto run = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_cli(args, kSlot);
  };
  const auto t = run({"--tolerance", "1000"});
  CHECK(t.rc == 0);
  CHECK(has(t.err, "warning: the tolerance 1000 mm (--tolerance, or tolerance_mm in the config) is not below the offset cap "
                   "max_offset_mm = 0.1 mm"));
  CHECK(t.out == kSlot);  // indeed nothing moved
  const auto g = run({"--gain", "2"});
  CHECK(g.rc == 0);
  CHECK(has(g.err, "warning: --gain 2 over-corrects: at the mirror's fixed point the surface error becomes -1 times"));
  CHECK(run({"--gain", "2", "--strict"}).rc == 2);
  CHECK(run({"--tolerance", "0.1", "--strict"}).rc == 2);
  // What is usual says nothing.
  const auto ok = run({"--tolerance", "0.01", "--gain", "0.8"});
  CHECK_FALSE(has(ok.err, "the tolerance"));
  CHECK_FALSE(has(ok.err, "--gain"));
}

TEST_CASE("a run names what it used, in the summary and in summary.json") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("deflex-used-" + std::to_string(::getpid()));
  const auto r = test::run_cli({"simulate", "-", "--stock", "box:0,0,-25,80,80,0", "--threads", "1", "--report",
                                dir.string()}, kSlot);
  REQUIRE(r.rc == 0);
  CHECK(has(r.err, "  used: machine mill3 (samples/machines/mill3.yaml, dialect fanuc); T1: flat D10 mm "
                   "(samples/tools.yaml); material C35 (samples/materials.yaml); config config.yaml\n"));
  const auto js = nlohmann::json::parse(test::read_file((dir / "summary.json").string())).at("used");
  CHECK(js.at("machine") == "mill3");
  CHECK(js.at("dialect") == "fanuc");
  CHECK(js.at("tools") == nlohmann::json::array({"T1: flat D10 mm"}));
  CHECK(js.at("material") == "C35 (samples/materials.yaml)");
  const auto c = test::run_cli({"compensate", "-", "--stock", "box:0,0,-25,80,80,0", "--threads", "1", "--tool", "T7"},
                               kSlot);
  CHECK(has(c.err, "; T7: ball D10 mm (samples/tools.yaml);"));
  fs::remove_all(dir);
}

TEST_CASE("--stock auto[:MARGIN] is the blank round the cutting moves and the tool, and says so") {
  const auto r = test::run_cli({"simulate", "-", "--stock", "auto:2", "--threads", "1"}, kSlot);
  REQUIRE(r.rc == 0);
  // Tips X 0.001..79.999, Y 0.001..0.626, Z -17.368..10 (the plunge starts at
  // Z10); R 5 + 2 beyond them, 2 below, the top at the highest tip.
  CHECK(has(r.err, "note: --stock auto:2 is the blank box:-6.999,-6.999,-19.368,86.999,7.626,10.000 (round the "
                   "cutting moves and the tool, 2 mm beyond them"));
  const auto same = test::run_cli({"simulate", "-", "--stock", "box:-6.999,-6.999,-19.368,86.999,7.626,10.000",
                                   "--threads", "1"}, kSlot);
  CHECK(same.out == r.out);
  CHECK(test::run_cli({"simulate", "-", "--stock", "auto:-1"}, kSlot).rc == 2);
  CHECK(test::run_cli({"simulate", "-", "--stock", "automatic"}, kSlot).rc == 2);
}

}  // TEST_SUITE
