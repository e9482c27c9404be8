// Every YAML file deflex reads goes through one strict reader (deflex::yaml):
// an unknown key anywhere is exit 3 at its line and column, as is a value
// that is missing, not finite or out of range.
#include <doctest/doctest.h>

#include <filesystem>
#include <unistd.h>

#include "../support.hpp"

using namespace deflex;
namespace fs = std::filesystem;

namespace {

struct Dir {
  fs::path p = fs::temp_directory_path() / ("deflex-strict-" + std::to_string(::getpid()));
  Dir() {
    fs::create_directories(p);
    test::write_file(file("p.nc"), "G21 G90 G54\nG0 X0 Y0 Z10.\nM30\n");
    test::write_file(file("config.yaml"), "max_errors: 5\n");
  }
  ~Dir() { fs::remove_all(p); }
  std::string file(const char* name) const { return (p / name).string(); }
};

const char* kMachine =
    "name: m\ndialect: fanuc\ntravel_mm:\n  x: [-400, 400]\n"
    "holder:\n  length_mm: 65\n  nose_diameter_mm: 32\n"
    "stiffness:\n  tool_clamp:\n    radial_N_per_um: 400\n  spindle:\n    radial_N_per_um: 200\n"
    "  structure:\n    stiffness_N_per_um: {x: 60, y: 50, z: 150}\n";

// `deflex check` with the machine text `machine` (and the config text `config`).
test::CliResult check_with(const Dir& d, const std::string& machine, const std::string& config = "max_errors: 5\n") {
  test::write_file(d.file("m.yaml"), machine);
  test::write_file(d.file("config.yaml"), config);
  return test::run_cli({"check", d.file("p.nc"), "--machine", d.file("m.yaml"), "--config", d.file("config.yaml")});
}

// The machine profile with `line` inserted after the line starting `after`.
std::string insert_after(std::string text, const std::string& after, const std::string& line) {
  const auto at = text.find('\n', text.find(after)) + 1;
  return text.insert(at, line);
}

}  // namespace

TEST_SUITE("profile") {

TEST_CASE("strict yaml: the sample-like profile is clean") {
  Dir d;
  const auto r = check_with(d, kMachine);
  CHECK(r.err == "");
  CHECK(r.rc == 0);
}

TEST_CASE("strict yaml: an unknown key in each section of the machine profile is exit 3 at its line:col") {
  Dir d;
  struct Case { const char* after; const char* line; const char* at; const char* section; };
  const Case cases[] = {
      {"dialect:", "limits: {x: 1}\n", ":3:1:", "machine profile"},
      {"  x: [-400", "  w: [0, 1]\n", ":5:3:", "travel_mm"},
      {"  nose_diameter_mm", "  colour: red\n", ":8:3:", "holder"},
      {"stiffness:", "  damping: 1\n", ":9:3:", "stiffness"},
      {"  tool_clamp:", "    radial_N_per_mm: 1\n", ":10:5:", "stiffness.tool_clamp"},
      {"  spindle:", "    speed_rpm: 12000\n", ":12:5:", "stiffness.spindle"},
      {"    stiffness_N_per_um", "    damping: 0.1\n", ":15:5:", "stiffness.structure"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.section);
    const auto r = check_with(d, insert_after(kMachine, c.after, c.line));
    CHECK(r.rc == 3);
    CHECK(r.err.find(d.file("m.yaml") + c.at + " error: unknown key '") == 0);
    CHECK(r.err.find(std::string("in ") + c.section + " (expected: ") != std::string::npos);
  }
}

TEST_CASE("strict yaml: a NaN or infinite travel limit is an error, not an unchecked axis") {
  Dir d;
  for (const char* v : {".nan", ".inf", "-.inf"}) {
    std::string m = kMachine;
    m.replace(m.find("400]"), 3, v);
    const auto r = check_with(d, m);
    CHECK(r.rc == 3);
    CHECK(r.err.find(d.file("m.yaml") + ":4:") == 0);
    CHECK(r.err.find("must be finite") != std::string::npos);
  }
}

TEST_CASE("strict yaml: config.yaml: unknown key, huge max_errors, bad numbers") {
  Dir d;
  auto r = check_with(d, kMachine, "max_errors: 5\nmachnie: mill3\n");
  CHECK(r.rc == 3);
  CHECK(r.err.find(d.file("config.yaml") + ":2:1: error: unknown key 'machnie' in config") == 0);
  r = check_with(d, kMachine, "max_errors: 1e30\n");
  CHECK(r.rc == 3);
  CHECK(r.err.find(d.file("config.yaml") + ":1:13: error: max_errors must be in [0, 1000000]") == 0);
  r = check_with(d, kMachine, "max_errors: 2.5\n");
  CHECK(r.rc == 3);
  r = check_with(d, kMachine, "max_errors: 5\ntolerance_mm: .nan\n");
  CHECK(r.rc == 3);
  CHECK(r.err.find(":2:15: error: tolerance_mm must be finite") != std::string::npos);
}

TEST_CASE("strict yaml: a dialect: unknown key, no name, decimals out of range") {
  Dir d;
  auto run = [&](const std::string& text) {
    test::write_file(d.file("d.yaml"), text);
    return test::run_cli({"check", d.file("p.nc"), "--dialect", d.file("d.yaml"), "--config", d.file("config.yaml")});
  };
  auto r = run("name: x\ndecimal_point_rule: calculator\nspeling: 1\n");
  CHECK(r.rc == 3);
  CHECK(r.err.find(d.file("d.yaml") + ":3:1: error: unknown key 'speling' in dialect") == 0);
  r = run("decimal_point_rule: calculator\n");
  CHECK(r.rc == 3);
  CHECK(r.err.find(d.file("d.yaml") + ":1:1: error: missing key 'name' in dialect") == 0);
  r = run("name: x\ndecimals_mm: 1e30\n");
  CHECK(r.rc == 3);
  CHECK(r.err.find(":2:14: error: decimals_mm must be in [0, 9]") != std::string::npos);
  r = run("name: x\ntrailing_zeros: maybe\n");
  CHECK(r.rc == 3);
  CHECK(r.err.find(":2:17: error: trailing_zeros must be true or false") != std::string::npos);
}

TEST_CASE("strict yaml: an unknown key in a tool and in a material is exit 3 at its line:col") {
  Dir d;
  test::write_file(d.file("tools.yaml"),
                   "tools:\n  A:\n    type: ball\n    diameter_mm: 10\n    flute_length_mm: 20\n"
                   "    stickout_mm: 40\n    material: carbide\n    colour: red\n");
  auto r = test::run_cli({"stiffness", "--tool-file", d.file("tools.yaml"), "--tool", "A"});
  CHECK(r.rc == 3);
  CHECK(r.err.find(d.file("tools.yaml") + ":8:5: error: unknown key 'colour' in tool 'A'") == 0);
  test::write_file(d.file("tools.yaml"),
                   "tools:\n  A:\n    type: ball\n    diameter_mm: 10\n    flute_length_mm: 20\n"
                   "    stickout_mm: 40\n    material: carbide\n");
  test::write_file(d.file("mat.yaml"),
                   "materials:\n  X:\n    model: mechanistic\n    source: test\n    K_tc_N_per_mm2: 2000\n"
                   "    K_rc_N_per_mm2: 800\n    hardness_HB: 200\n");
  r = test::run_cli({"forces", "--tool-file", d.file("tools.yaml"), "--tool", "A", "--material", "X",
                     "--material-file", d.file("mat.yaml"), "--ae", "1", "--ap", "1", "--fz", "0.05", "--down"});
  CHECK(r.rc == 3);
  CHECK(r.err.find(d.file("mat.yaml") + ":7:5: error: unknown key 'hardness_HB' in material 'X'") == 0);
}

}  // TEST_SUITE
