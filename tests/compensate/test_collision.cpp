// The tool assembly against the stock (compensate/collision.hpp): a pocket
// deeper than the stick-out lets the holder in, found at its line with the
// depth and the stick-out that clears it; the same pocket with a longer
// stick-out is clear; the pocket an earlier program cut is what counts.
#include <doctest/doctest.h>

#include <cmath>

#include "../support.hpp"
#include "deflex/compensate/collision.hpp"
#include "deflex/compensate/plausibility.hpp"
#include "deflex/force/material.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/stock/sweep.hpp"

using namespace deflex;

namespace {

// T1: D10 flat, flutes 20 mm, stick-out 40 mm; T2 the same at 60 mm.
const char* kTools = R"(tools:
  T1: {type: flat, diameter_mm: 10, flutes: 4, flute_length_mm: 20, stickout_mm: 40, material: carbide}
  T2: {type: flat, diameter_mm: 10, flutes: 4, flute_length_mm: 20, stickout_mm: 60, material: carbide}
)";

// A finishing pass on the floor of the pocket X40..60 Y40..60, 55.5 mm deep:
// 0.5 mm off the floor at Z-55, across the middle: line 5 the plunge to it, line 6 the cut.
std::string floor_pass(int tool) {
  return "G21 G90 G17\nT" + std::to_string(tool) + " M6\nS8000 M3\nG0 X45. Y50. Z5.\nG1 Z-55. F300\nX55.\nG0 Z5.\nM30\n";
}

// The box 0..100 x 0..100, Z-80..0, with the pocket cut into it by an earlier
// program (a D10 flat end at Z-55.5 over X45..55 Y45..55, 1 mm apart).
stock::ZMap pocketed() {
  stock::ZMap z = stock::make_stock("box:0,0,-80,100,100,0", {});
  const stock::ToolProfile mill{stock::EndShape::flat, 5.0, 0.0};
  for (double y = 45; y <= 55; y += 1) stock::sweep_line(z, mill, {45, y, -55.5}, {55, y, -55.5});
  return z;
}

struct Run {
  compensate::Physics ph;
  compensate::Settings s;
  std::vector<compensate::Point> points;
  compensate::Plausibility pl;
  Run(const std::string& program, const stock::ZMap& z) {
    test::Interpreted in = test::interpret_text(program);
    REQUIRE(in.errors == 0);
    ph.tools = stiffness::parse_tool_library(kTools, "lib.yaml");
    ph.machine = stiffness::load_machine_stiffness("samples/machines/mill3.yaml");
    ph.k = force::find_material(force::load_material_library("samples/materials.yaml"), "Al6082-T4").k;
    ph.stock = &z;
    s.threads = 0;
    points = compensate::simulate(in.motions, {}, ph, s);
    pl = compensate::plausibility(points, ph.tools, s);
  }
};

}  // namespace

TEST_SUITE("compensate") {

TEST_CASE("collision: the assembly of the sample holder and a tool, bottom up") {
  const auto tools = stiffness::parse_tool_library(kTools, "lib.yaml");
  const auto machine = stiffness::load_machine_stiffness("samples/machines/mill3.yaml");
  REQUIRE(machine.holder);
  const compensate::Assembly a = compensate::assembly_of(tools.tools.at("T1"), machine.holder);
  REQUIRE(a.frusta.size() == 2);
  CHECK(a.frusta[0].part == compensate::AssemblyPart::shank);
  CHECK(a.frusta[0].z0_mm == 20);
  CHECK(a.frusta[0].z1_mm == 40);
  CHECK(a.frusta[1].part == compensate::AssemblyPart::holder);
  CHECK(a.frusta[1].z0_mm == 40);
  CHECK(a.frusta[1].z1_mm == 40 + machine.holder->length_mm);
  CHECK(a.frusta[1].r0_mm == machine.holder->nose_diameter_mm / 2);
  CHECK(a.frusta[1].r1_mm == machine.holder->base_diameter_mm / 2);
}

TEST_CASE("collision: a pocket deeper than the stick-out lets the holder in, a longer stick-out clears it") {
  const stock::ZMap z = pocketed();
  // The holder's nose (radius 16 mm) reaches the pocket's walls (10 mm from the
  // path's middle) at 40 mm above the tip, Z-15: the walls stand to Z0.
  const Run short_tool(floor_pass(1), z);
  const compensate::Finding* f = short_tool.pl.find("holder_collision");
  REQUIRE(f);
  CHECK(f->line == 5);  // the worst depth is reached at the plunge's end already
  CHECK(f->lines == std::vector<std::uint32_t>{5, 6});
  CHECK(f->tool == "T1");
  CHECK(f->worst == doctest::Approx(15.0).epsilon(1e-4));
  CHECK(f->message.find("a stick-out of at least 55.0 mm keeps the holder clear") != std::string::npos);
  CHECK_FALSE(short_tool.pl.find("shank_collision"));  // the shank (radius 5) stays inside the pocket
  // The same at 60 mm: the holder starts at Z5, above the stock.
  const Run long_tool(floor_pass(2), z);
  CHECK_FALSE(long_tool.pl.find("holder_collision"));
  CHECK_FALSE(long_tool.pl.find("shank_collision"));
}

TEST_CASE("collision: the stock is what the earlier program left, and a shank in a narrow slot") {
  // Without the earlier pocket the tool would plunge into solid stock: the
  // pass at Z-55 buries the shank (radius 5 from 20 mm above the tip), 35 mm
  // deep, and the holder, 15 mm - where the pocket exists only the holder hits.
  const stock::ZMap solid = stock::make_stock("box:0,0,-80,100,100,0", {});
  const Run buried(floor_pass(1), solid);
  const compensate::Finding* shank = buried.pl.find("shank_collision");
  REQUIRE(shank);
  CHECK(shank->worst == doctest::Approx(35.0).epsilon(1e-4));
  CHECK(shank->message.find("reach 55.0 mm above the tip") != std::string::npos);
  const Run pocket(floor_pass(1), pocketed());
  CHECK_FALSE(pocket.pl.find("shank_collision"));
  // The interference itself against the cells by hand: a tip 1 mm lower in
  // the pocket puts the holder 1 mm deeper.
  const compensate::Assembly a =
      compensate::assembly_of(pocket.ph.tools.tools.at("T1"), pocket.ph.machine.holder);
  const stock::ZMap z = pocketed();
  const auto at55 = compensate::interference(z, {50, 50, -55}, a), at56 = compensate::interference(z, {50, 50, -54}, a);
  CHECK(at55.part == compensate::AssemblyPart::holder);
  CHECK(at55.depth_mm - at56.depth_mm == doctest::Approx(1.0));
}

}  // TEST_SUITE
