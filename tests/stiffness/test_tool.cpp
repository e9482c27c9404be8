#include <doctest/doctest.h>

#include <string>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/profile/yaml.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/shape.hpp"
#include "deflex/stiffness/tool.hpp"
#include "../support.hpp"
#include "helpers.hpp"

using namespace deflex;
using namespace deflex::stiffness;
using namespace deflex::stiffness::testing;

namespace {
// The message of the config error `yaml` raises, or "" if none.
std::string tool_error(const std::string& yaml) {
  try {
    parse_tool_library(yaml, "lib.yaml");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::config);
    return e.what();
  }
  return "";
}
std::string machine_error(const std::string& yaml) {
  try {
    parse_machine_stiffness(yaml::document(YAML::Load(yaml)), "m.yaml");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::config);
    return e.what();
  }
  return "";
}
const char* kGood =
    "tools:\n"
    "  A:\n"
    "    type: bull\n"
    "    diameter_mm: 12\n"
    "    corner_radius_mm: 1.5\n"
    "    flute_length_mm: 20\n"
    "    stickout_mm: 40\n"
    "    material: carbide\n";
}  // namespace

TEST_SUITE("stiffness") {
  TEST_CASE("tools: the sample library has every tool type and the paper-001 tool") {
    const ToolLibrary lib = load_tool_library(sample_path("samples/tools.yaml"));
    bool ball = false, flat = false, bull = false;
    for (const auto& [id, t] : lib.tools) {
      ball |= t.type == stock::EndShape::ball;
      flat |= t.type == stock::EndShape::flat;
      bull |= t.type == stock::EndShape::bull;
    }
    CHECK((ball && flat && bull));
    const Tool& t5 = find_tool(lib, "T5");
    CHECK(t5.type == stock::EndShape::ball);
    CHECK(t5.diameter_mm == 16);
    CHECK(t5.corner_radius_mm == 8);
    CHECK(t5.flutes == 2);
    CHECK(t5.helix_deg == 9);
    CHECK(t5.stickout_mm == 80);
    CHECK(t5.material.E_MPa == 207000);
    CHECK(t5.material.poisson == 0.33);
    CHECK(find_tool(lib, "T3").neck.has_value());
    CHECK_THROWS_AS(find_tool(lib, "T99"), Error);
  }

  TEST_CASE("tools: defaults and presets") {
    const ToolLibrary lib = parse_tool_library(kGood, "lib.yaml");
    const Tool& t = find_tool(lib, "A");
    CHECK(t.shank_diameter_mm == 12);
    CHECK(t.flute_diameter_ratio == 0.8);
    CHECK(t.material.name == "carbide");
    CHECK(t.material.E_MPa > 400000);
  }

  TEST_CASE("tools: errors carry file:line:col") {
    CHECK(tool_error(std::string(kGood) + "    diamter_mm: 3\n")
              .find("lib.yaml:9:5: error: unknown key 'diamter_mm'") == 0);
    std::string bad = kGood;
    bad.replace(bad.find("diameter_mm: 12"), 15, "diameter_mm: -2");
    CHECK(tool_error(bad).find("lib.yaml:4:18: error: diameter_mm must be in (0, 1000]") == 0);
    bad = kGood;
    bad.replace(bad.find("type: bull"), 10, "type: drill");
    CHECK(tool_error(bad).find("lib.yaml:3:11: error: type must be ball, flat or bull") == 0);
    bad = kGood;
    bad.replace(bad.find("corner_radius_mm: 1.5"), 21, "corner_radius_mm: 7");
    CHECK(tool_error(bad).find("lib.yaml:5:23: error: corner_radius_mm") == 0);
    bad = kGood;
    bad.replace(bad.find("carbide"), 7, "{E_MPa: 2e5, poisson: 0.7}");
    CHECK(tool_error(bad).find("error: poisson must be in (-1, 0.5)") != std::string::npos);
    bad = kGood;
    bad.replace(bad.find("    stickout_mm: 40\n"), 20, "");
    CHECK(tool_error(bad).find("lib.yaml:3:5: error: missing key 'stickout_mm'") == 0);
    CHECK(tool_error("tools:\n  A: [1, 2\n").find("lib.yaml:") == 0);
    CHECK(tool_error(kGood).empty());
    // Sizes beyond a metre (libFuzzer's input: a 5e103 mm stick-out overflowed the beam mesh count).
    bad = kGood;
    bad.replace(bad.find("stickout_mm: 40"), 15, "stickout_mm: 4e5");
    CHECK(tool_error(bad).find("lib.yaml:7:18: error: stickout_mm must be in (0, 1000]") == 0);
    const std::string found = test::read_file("tests/stiffness/data/fuzz_stickout_overflow.yaml");
    CHECK(tool_error(found).find("lib.yaml:10:18: error: stickout_mm must be") == 0);
  }

  TEST_CASE("machine: the sample profile and its units") {
    const MachineStiffness m = load_machine_stiffness(sample_path("samples/machines/mill3.yaml"));
    REQUIRE(m.holder.has_value());
    CHECK(m.holder->length_mm == 65);
    REQUIRE(m.spindle.has_value());
    CHECK(*m.spindle->radial_N_per_mm == doctest::Approx(200e3));            // 200 N/um
    CHECK(*m.spindle->rotational_Nmm_per_rad == doctest::Approx(2.0e9));     // 2e6 N m/rad
    CHECK(m.structure_mm_per_N(0, 0) == doctest::Approx(1.0 / 60e3));        // 60 N/um
    CHECK(m.structure_mm_per_N(0, 1) == 0);
  }

  TEST_CASE("machine: errors carry file:line:col") {
    CHECK(machine_error("stiffness:\n  spindle:\n    radial_N_per_um: 0\n")
              .find("m.yaml:3:22: error: radial_N_per_um must be > 0") == 0);
    CHECK(machine_error("stiffness:\n  spindel: {}\n").find("m.yaml:2:3: error: unknown key 'spindel'") == 0);
    CHECK(machine_error("stiffness:\n  structure:\n    compliance_mm_per_N: [[1, 0, 0], [0, -1, 0], [0, 0, 1]]\n")
              .find("positive semi-definite") != std::string::npos);
    CHECK(machine_error("name: x\nholder: {length_mm: 50, nose_diameter_mm: 30}\n").empty());
  }

  TEST_CASE("materials: densities of the presets and of a custom material") {
    CHECK(material_preset("carbide")->density_kg_per_m3 == 14500);
    CHECK(material_preset("hss")->density_kg_per_m3 == 8150);
    CHECK(material_preset("steel")->density_kg_per_m3 == 7850);
    std::string custom = kGood;
    custom.replace(custom.find("carbide"), 7, "{E_MPa: 2e5, poisson: 0.3, density_kg_per_m3: 7800}");
    CHECK(find_tool(parse_tool_library(custom, "lib.yaml"), "A").material.density_kg_per_m3 == 7800);
    custom = kGood;
    custom.replace(custom.find("carbide"), 7, "{E_MPa: 2e5, poisson: 0.3}");
    CHECK(find_tool(parse_tool_library(custom, "lib.yaml"), "A").material.density_kg_per_m3 == 0);  // unknown
    // g/cm^3 written as kg/m^3: located at the number.
    custom = kGood;
    custom.replace(custom.find("carbide"), 7, "{E_MPa: 2e5, poisson: 0.3, density_kg_per_m3: 7.85}");
    CHECK(tool_error(custom).find("lib.yaml:8:61: error: density_kg_per_m3 must be in [500, 25000]") == 0);
    // A holder's material is read by the same reader.
    const MachineStiffness m = parse_machine_stiffness(
        yaml::document(YAML::Load("holder: {length_mm: 50, nose_diameter_mm: 30,\n"
                                  "  material: {E_MPa: 2e5, poisson: 0.3, density_kg_per_m3: 7900}}\n")),
        "m.yaml");
    CHECK(m.holder->material.density_kg_per_m3 == 7900);
    CHECK(machine_error("holder: {length_mm: 50, nose_diameter_mm: 30,\n"
                        "  material: {E_MPa: 2e5, poisson: 0.3, density_kg_per_m3: -1}}\n")
              .find("m.yaml:2:59: error: density_kg_per_m3 must be in [500, 25000]") == 0);
  }

  TEST_CASE("machine: dynamics: damping_ratio, its default and its errors") {
    const MachineStiffness sample = load_machine_stiffness(sample_path("samples/machines/mill3.yaml"));
    CHECK(sample.dynamics.damping_given);
    CHECK(sample.dynamics.damping_ratio == 0.03);
    const MachineStiffness none = parse_machine_stiffness(yaml::document(YAML::Load("name: x\n")), "m.yaml");
    CHECK_FALSE(none.dynamics.damping_given);
    CHECK(none.dynamics.damping_ratio == 0.03);
    CHECK(machine_error("dynamics:\n  damping_ratio: 0\n").find("m.yaml:2:18: error: damping_ratio must be in (0, 1)") == 0);
    CHECK(machine_error("dynamics:\n  damping_ratio: 1.5\n").find("m.yaml:2:18: error: damping_ratio must be in (0, 1)") == 0);
    CHECK(machine_error("dynamics:\n  damping_ratio: .nan\n").find("m.yaml:2:18: error: damping_ratio must be finite") == 0);
    CHECK(machine_error("dynamics:\n  damping: 0.1\n").find("m.yaml:2:3: error: unknown key 'damping'") == 0);
  }

  TEST_CASE("shape: equivalent profile of a fluted ball end") {
    Tool t = cylinder(16, 80);
    t.type = stock::EndShape::ball;
    t.corner_radius_mm = 8;
    t.flute_length_mm = 30;
    t.flute_diameter_ratio = 0.8;
    const ToolShape s = tool_shape(t);
    CHECK(radius_at(s, 0) == doctest::Approx(0));
    CHECK(radius_at(s, 8) == doctest::Approx(6.4));
    CHECK(radius_at(s, 20) == doctest::Approx(6.4));
    CHECK(radius_at(s, 50) == doctest::Approx(8));
    // A circle (scaled radially) through the corner: r(4) = 0.8 sqrt(4 (16 - 4)).
    CHECK(radius_at(s, 4) == doctest::Approx(0.8 * std::sqrt(48.0)));
  }

  TEST_CASE("tool library: max_force_N and centre_cutting (plausibility keys)") {
    const std::string base = "tools:\n  A:\n    type: flat\n    diameter_mm: 10\n    flute_length_mm: 20\n"
                             "    stickout_mm: 40\n    material: carbide\n";
    const ToolLibrary plain = parse_tool_library(base, "lib.yaml");
    CHECK_FALSE(plain.tools.at("A").max_force_N);
    CHECK(plain.tools.at("A").centre_cutting);
    const ToolLibrary set = parse_tool_library(base + "    max_force_N: 400\n    centre_cutting: false\n", "lib.yaml");
    CHECK(*set.tools.at("A").max_force_N == 400.0);
    CHECK_FALSE(set.tools.at("A").centre_cutting);
    CHECK(tool_error(base + "    max_force_N: -1\n").find("lib.yaml:8:") == 0);
    CHECK(tool_error(base + "    centre_cutting: maybe\n").find("lib.yaml:8:") == 0);
  }
}
