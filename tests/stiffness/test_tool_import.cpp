// Tool libraries from Fusion 360 (JSON) and LinuxCNC (.tbl): the samples field
// by field, what is skipped and why, malformed files at their position, and
// the import written by the CLI loading as the same library.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>

#include "../support.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stiffness/tool_import.hpp"

namespace fs = std::filesystem;
using namespace deflex;
using namespace deflex::stiffness;
using doctest::Approx;

namespace {
std::string import_error(const std::string& text, bool json) {
  try {
    json ? import_fusion_json(text, "lib.json") : import_linuxcnc_tbl(text, "t.tbl");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::config);
    return e.what();
  }
  return "";
}
}  // namespace

TEST_SUITE("stiffness") {
  TEST_CASE("tool import: the Fusion 360 sample, field by field, through --tool-file's reader") {
    const ToolLibrary lib = load_tool_library("samples/tool-libraries/fusion_library.json");
    REQUIRE(lib.tools.size() == 5);
    const Tool& f = lib.tools.at("T11");
    CHECK(f.type == stock::EndShape::flat);
    CHECK(f.diameter_mm == 10);
    CHECK(f.flutes == 3);
    CHECK(f.flute_length_mm == 22);
    CHECK(f.stickout_mm == 40);
    CHECK(f.shank_diameter_mm == 10);
    CHECK(f.material.name == "carbide");
    const Tool& b = lib.tools.at("T12");  // the first T12: the later duplicate is skipped
    CHECK(b.type == stock::EndShape::ball);
    CHECK(b.diameter_mm == 6);
    CHECK(b.corner_radius_mm == 3);
    CHECK(b.stickout_mm == 30);
    const Tool& r = lib.tools.at("T13");
    CHECK(r.type == stock::EndShape::bull);
    CHECK(r.corner_radius_mm == 1.5);
    CHECK(r.flutes == 4);
    const Tool& in = lib.tools.at("T14");  // inches to mm
    CHECK(in.diameter_mm == Approx(6.35));
    CHECK(in.flute_length_mm == Approx(19.05));
    CHECK(in.stickout_mm == Approx(38.1));
    CHECK(in.material.name == "hss");
    const Tool& d = lib.tools.at("T17");  // stated defaults
    CHECK(d.flutes == 2);
    CHECK(d.flute_length_mm == 16);
    CHECK(d.stickout_mm == 24);
    CHECK(d.helix_deg == 30);
    const ImportedLibrary imp = import_tool_library("samples/tool-libraries/fusion_library.json");
    REQUIRE(imp.skipped.size() == 3);
    CHECK(imp.skipped[0].find("'Drill 6.8 for M8' (drill): not a flat, ball or bull-nose end mill") != std::string::npos);
    CHECK(imp.skipped[1].find("(chamfer mill)") != std::string::npos);
    CHECK(imp.skipped[2].find("T12 is already 'Ball D6 finishing'") != std::string::npos);
    CHECK(imp.yaml.find("stickout_mm: 24  # default LCF + D") != std::string::npos);
  }

  TEST_CASE("tool import: the LinuxCNC sample; defaults stated, a tool without D skipped") {
    const ToolLibrary lib = load_tool_library("samples/tool-libraries/linuxcnc.tbl");
    REQUIRE(lib.tools.size() == 3);
    CHECK(lib.tools.at("T2").diameter_mm == 6);
    CHECK(lib.tools.at("T2").type == stock::EndShape::flat);  // the stated default
    CHECK(lib.tools.at("T3").flute_length_mm == 36);   // 3 D
    CHECK(lib.tools.at("T3").stickout_mm == 48);       // 4 D
    const ImportedLibrary imp = import_tool_library("samples/tool-libraries/linuxcnc.tbl");
    REQUIRE(imp.skipped.size() == 1);
    CHECK(imp.skipped[0] == "T5 (line 5): no diameter D");
    CHECK(imp.yaml.find("description: ball D6") != std::string::npos);
    CHECK(imp.yaml.find("stickout_mm: 48  # default 4 D") != std::string::npos);
  }

  TEST_CASE("tool import: malformed libraries at their position") {
    CHECK(import_error("{\"data\": [\n  {\"type\": \"flat end mill\",, }\n]}", true).find("lib.json:2:28: error: not valid JSON") == 0);
    // libFuzzer's inputs: a number beyond a double is a config error, not an internal one.
    CHECK(import_error("4e0333", true).find("lib.json: error: not valid JSON") == 0);
    CHECK(import_error(test::read_file("tests/stiffness/data/fuzz_json_overflow.json"), true).find("lib.json: error: not valid JSON") == 0);
    CHECK(import_error("[1, 2]", true).find("lib.json: error: a Fusion 360 tool library is a JSON object") == 0);
    CHECK(import_error(R"({"data": [{"type": "ball end mill", "description": "B", "geometry": {"DC": "6"}, "post-process": {"number": 3}}]})", true)
              .find("lib.json: data[0] 'B' (ball end mill) T3: error: geometry.DC must be a number") == 0);
    CHECK(import_error(R"({"data": [{"type": "bull nose end mill", "geometry": {"DC": 6, "RE": 4}, "post-process": {"number": 3}}]})", true)
              .find("RE (the corner radius) in (0, DC/2]") != std::string::npos);
    CHECK(import_error("T1 P1 D10\nT2 D6 K4\n", false).find("t.tbl:2:7: error: 'K' is not a word") == 0);
    CHECK(import_error("T1 D10\nT1 D6\n", false).find("t.tbl:2:1: error: T1 is listed twice") == 0);
    CHECK(import_error("T1 Dx\n", false).find("t.tbl:1:4: error: 'Dx' needs a number") == 0);
  }

  TEST_CASE("deflex tools import -o: the file written loads as the same library; other files are refused") {
    std::string t = (fs::temp_directory_path() / "deflex-tools-XXXXXX").string();
    const fs::path dir = mkdtemp(t.data());
    const std::string out = (dir / "tools.yaml").string();
    const auto r = test::run_cli({"tools", "import", "samples/tool-libraries/fusion_library.json", "-o", out});
    REQUIRE(r.rc == 0);
    CHECK(r.err.find("5 tools converted, 3 skipped") != std::string::npos);
    const ToolLibrary a = load_tool_library(out), b = load_tool_library("samples/tool-libraries/fusion_library.json");
    REQUIRE(a.tools.size() == b.tools.size());
    // A named pair, not a structured binding: clang 14 cannot capture bindings (CAPTURE is a lambda).
    for (const auto& entry : a.tools) {
      const std::string& id = entry.first;
      CAPTURE(id);
      CHECK(entry.second.diameter_mm == b.tools.at(id).diameter_mm);
      CHECK(entry.second.stickout_mm == b.tools.at(id).stickout_mm);
      CHECK(entry.second.type == b.tools.at(id).type);
    }
    CHECK(test::run_cli({"tools", "import", "samples/tools.yaml"}).rc == 2);
    // A program runs with the imported library directly.
    const auto s = test::run_cli({"simulate", "tests/engage/data/ball_finish.nc", "--stock", "box:0,0,-10,40,30,0",
                                  "--material", "Al7075-T6", "--tool-file", "samples/tool-libraries/fusion_library.json",
                                  "--tool", "T12"});
    CHECK(s.rc == 0);
    fs::remove_all(dir);
  }
}
