// Material library, and the cutting geometry the force model takes from a tool-library entry.
#include <doctest/doctest.h>

#include <string>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/force/material.hpp"
#include "deflex/force/tool.hpp"
#include "deflex/stiffness/tool.hpp"
#include "../support.hpp"

using namespace deflex::force;
using deflex::Error;
using deflex::ErrorKind;

namespace {
const std::string src = DEFLEX_SOURCE_DIR;

using deflex::test::error_of;
}  // namespace

TEST_SUITE("force") {

TEST_CASE("samples/materials.yaml: the paper sets, each entry with its source") {
  const MaterialLibrary lib = load_material_library(src + "/samples/materials.yaml");
  const MaterialEntry& c35 = find_material(lib, "xc38");  // alias, any case
  CHECK(c35.name == "C35");
  CHECK(c35.form == ModelForm::smaoui_krta);
  CHECK(c35.k.Ktc_N_per_mm2 == 3600);  // Smaoui 2011 Eq. 7
  CHECK(c35.k.Krc_N_per_mm2 == 3400);  // Eq. 8
  CHECK(c35.k.Kac_N_per_mm2 == 500);   // Eq. 6
  CHECK(c35.k.Kte_N_per_mm == 0);
  CHECK(c35.source.find("Smaoui") != std::string::npos);
  const MaterialEntry& al = find_material(lib, "Al 6082-T4");
  CHECK(al.k.Ktc_N_per_mm2 == 752.9);  // Morelli 2021 §3.1
  CHECK(al.k.Krc_N_per_mm2 == 200.5);
  CHECK(al.source.find("Morelli") != std::string::npos);
  for (const char* name : {"Al7075-T6", "42CrMo4"}) {
    const MaterialEntry& m = find_material(lib, name);
    CHECK(m.k.Ktc_N_per_mm2 > 0);
    CHECK(!m.source.empty());
  }
  for (const auto& m : lib.entries) CHECK(!m.source.empty());
  CHECK(error_of([&] { find_material(lib, "unobtainium"); }, ErrorKind::settings).find("C35") != std::string::npos);
}

TEST_CASE("elastic: a material's elastic constants, read, written back, located when malformed") {
  const MaterialLibrary lib = load_material_library(src + "/samples/materials.yaml");
  for (const auto& e : lib.entries) CHECK(e.elastic.has_value());
  const MaterialEntry& al = find_material(lib, "Al7075-T6");
  CHECK(al.elastic->E_MPa == 71700);
  CHECK(al.elastic->poisson == 0.33);
  const MaterialLibrary back = parse_material_library(to_yaml(al), "back.yaml");
  CHECK(back.entries[0].elastic->E_MPa == 71700);
  CHECK(back.entries[0].elastic->poisson == 0.33);

  const std::string head = "materials:\n  X:\n    model: mechanistic\n    K_tc_N_per_mm2: 700\n    K_rc_N_per_mm2: 200\n"
                           "    source: test\n";
  std::string m = error_of([&] { parse_material_library(head + "    elastic: {E_MPa: 0, poisson: 0.3}\n", "m.yaml"); },
                           ErrorKind::config);
  CHECK(m.rfind("m.yaml:7:", 0) == 0);
  CHECK(m.find("error: ") != std::string::npos);
  m = error_of([&] { parse_material_library(head + "    elastic: {E_MPa: 70000, poisson: 0.5}\n", "m.yaml"); },
               ErrorKind::config);
  CHECK(m.rfind("m.yaml:7:", 0) == 0);
  CHECK(m.find("poisson must be in (-1, 0.5)") != std::string::npos);
  m = error_of([&] { parse_material_library(head + "    elastic: 70000\n", "m.yaml"); }, ErrorKind::config);
  CHECK(m.find("elastic must be a map") != std::string::npos);
}

TEST_CASE("material YAML errors are file:line:col diagnostics of class config") {
  const std::string bad_syntax = "materials:\n  X:\n    model: [mechanistic\n";
  const std::string m1 = error_of([&] { parse_material_library(bad_syntax, "m.yaml"); }, ErrorKind::config);
  CHECK(m1.rfind("m.yaml:", 0) == 0);
  CHECK(m1.find(": error: ") != std::string::npos);

  const std::string typo =
      "materials:\n  X:\n    model: mechanistic\n    K_tc_N_per_mm2: 700\n"
      "    K_rcc_N_per_mm2: 200\n    source: test\n";
  const std::string m2 = error_of([&] { parse_material_library(typo, "m.yaml"); }, ErrorKind::config);
  CHECK(m2.rfind("m.yaml:5:5: error: unknown key 'K_rcc_N_per_mm2'", 0) == 0);

  const std::string nan_value =
      "materials:\n  X:\n    model: mechanistic\n    K_tc_N_per_mm2: lots\n"
      "    K_rc_N_per_mm2: 200\n    source: test\n";
  const std::string m3 = error_of([&] { parse_material_library(nan_value, "m.yaml"); }, ErrorKind::config);
  CHECK(m3.rfind("m.yaml:4:21: error: K_tc_N_per_mm2 must be a number", 0) == 0);

  const std::string no_source = "materials:\n  X:\n    model: smaoui_krta\n    K_T_N_per_mm2: 1\n"
                                "    K_R_N_per_mm2: 1\n    K_A_N_per_mm2: 1\n";
  CHECK(error_of([&] { parse_material_library(no_source, "m.yaml"); }, ErrorKind::config)
            .find("missing key 'source'") != std::string::npos);
  CHECK(error_of([&] { load_material_library("/nonexistent/m.yaml"); }, ErrorKind::io).size() > 0);
}

TEST_CASE("a material entry written by to_yaml reads back the same") {
  MaterialEntry m;
  m.name = "Fit \"A\"";
  m.aliases = {"alias one"};
  m.k.Ktc_N_per_mm2 = 812.5;
  m.k.Krc_N_per_mm2 = 201.25;
  m.k.Kac_N_per_mm2 = -33;
  m.k.Kte_N_per_mm = 24.5;
  m.k.Kre_N_per_mm = 31;
  m.k.Kae_N_per_mm = 1.5;
  m.source = "deflex calibrate slots.csv";
  m.conditions = "D 12, 4 flutes";
  const MaterialLibrary lib = parse_material_library(to_yaml(m), "out.yaml");
  REQUIRE(lib.entries.size() == 1);
  const MaterialEntry& r = lib.entries[0];
  CHECK(r.name == m.name);
  CHECK(&find_material(lib, "alias-one") == &r);
  CHECK(r.k.Ktc_N_per_mm2 == m.k.Ktc_N_per_mm2);
  CHECK(r.k.Kac_N_per_mm2 == m.k.Kac_N_per_mm2);
  CHECK(r.k.Kae_N_per_mm == m.k.Kae_N_per_mm);
  CHECK(r.source == m.source);
  CHECK(r.conditions == m.conditions);
}

TEST_CASE("a tool-library entry gives the force model its cutting geometry") {
  const auto lib = deflex::stiffness::load_tool_library(src + "/tests/force/data/tools.yaml");
  const Cutter f = cutter_of(deflex::stiffness::find_tool(lib, "F12"));
  CHECK(f.type == deflex::stock::EndShape::flat);
  CHECK(f.diameter_mm == 12);
  CHECK(f.corner_radius_mm == 0);
  CHECK(f.flutes == 4);
  CHECK(f.helix_deg == 45);
  CHECK(f.flute_length_mm == 26);
  const Cutter r = cutter_of(deflex::stiffness::find_tool(lib, "R12"));
  CHECK(r.type == deflex::stock::EndShape::bull);
  CHECK(r.corner_radius_mm == 1.5);
  const Cutter b = cutter_of(deflex::stiffness::find_tool(lib, "B10"));
  CHECK(b.type == deflex::stock::EndShape::ball);
  CHECK(b.corner_radius_mm == 0);  // the force model takes a ball's from D
  CHECK(error_of([&] { deflex::stiffness::find_tool(lib, "T99"); }, ErrorKind::settings).find("B10") != std::string::npos);
}

}  // TEST_SUITE
