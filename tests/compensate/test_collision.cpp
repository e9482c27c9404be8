// The tool assembly against the stock (compensate/collision.hpp): a pocket
// deeper than the stick-out lets the holder in, found at its line with the
// depth and the stick-out that clears it; the same pocket with a longer
// stick-out is clear; the pocket an earlier program cut is what counts; the
// neck and shank begin where the force model's flutes end.
#include <doctest/doctest.h>

#include <cmath>

#include "../support.hpp"
#include "deflex/compensate/collision.hpp"
#include "deflex/force/cutter.hpp"
#include "deflex/force/tool.hpp"
#include "deflex/force/material.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/stock/sweep.hpp"

using namespace deflex;

namespace {

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
  std::vector<compensate::Collision> collisions;
  Run(const std::string& program, const stock::ZMap& z) {
    test::Interpreted in = test::interpret_text(program);
    REQUIRE(in.errors == 0);
    ph.tools = stiffness::parse_tool_library(test::kPocketTools, "lib.yaml");
    ph.machine = stiffness::load_machine_stiffness("samples/machines/mill3.yaml");
    ph.k = force::find_material(force::load_material_library("samples/materials.yaml"), "Al6082-T4").k;
    ph.stock = &z;
    s.threads = 0;
    points = compensate::simulate(in.motions, {}, ph, s);
    compensate::CollisionScan scan(ph.tools);
    for (const compensate::Point& p : points) scan.add(p, compensate::tool_id(p.tool, s));
    collisions = scan.collisions();
  }
  const compensate::Collision* find(const std::string& kind) const {
    for (const compensate::Collision& c : collisions)
      if (c.kind() == kind) return &c;
    return nullptr;
  }
};

}  // namespace

TEST_SUITE("compensate") {

TEST_CASE("collision: the assembly of the sample holder and a tool, bottom up") {
  const auto tools = stiffness::parse_tool_library(test::kPocketTools, "lib.yaml");
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
  const Run short_tool(test::pocket_floor_pass(1), z);
  const compensate::Collision* f = short_tool.find("holder_collision");
  REQUIRE(f);
  CHECK(f->first_line == 5);  // the plunge to the floor
  CHECK(f->worst_line == 5);  // the worst depth is reached at the plunge's end already
  CHECK(f->line_count == 2);  // the plunge and the cut
  CHECK(f->tool == "T1");
  // By hand: the walls stand to Z0, the holder's face at Z-55 + 40 = Z-15.
  CHECK(f->first_mm == deflex::test::within(15.0, 1e-4));
  CHECK(f->worst_mm == deflex::test::within(15.0, 1e-4));
  CHECK(f->clears_mm == deflex::test::within(55.0, 1e-4));
  CHECK(f->message().find("a stick-out of at least 55.0 mm keeps the holder clear") != std::string::npos);
  CHECK_FALSE(short_tool.find("shank_collision"));  // the shank (radius 5) stays inside the pocket
  // The same at 60 mm: the holder starts at Z5, above the stock.
  const Run long_tool(test::pocket_floor_pass(2), z);
  CHECK(long_tool.collisions.empty());
}

TEST_CASE("collision: the stock is what the earlier program left, and a shank in a narrow slot") {
  // Without the earlier pocket the tool would plunge into solid stock: the
  // plunge's shank follows in the bore its flutes cut, and the pass at Z-55
  // buries it (radius 5 from 20 mm above the tip) 35 mm deep, and the
  // holder 15 mm - where the pocket exists only the holder hits.
  const stock::ZMap solid = stock::make_stock("box:0,0,-80,100,100,0", {});
  const Run buried(test::pocket_floor_pass(1), solid);
  const compensate::Collision* shank = buried.find("shank_collision");
  REQUIRE(shank);
  CHECK(shank->worst_mm == deflex::test::within(35.0, 1e-4));
  CHECK(shank->clears_mm == deflex::test::within(55.0, 1e-4));
  CHECK(shank->message().find("reach 55.0 mm above the tip") != std::string::npos);
  const Run pocket(test::pocket_floor_pass(1), pocketed());
  CHECK_FALSE(pocket.find("shank_collision"));
  // The interference itself against the cells by hand: a tip 1 mm lower in
  // the pocket puts the holder 1 mm deeper.
  const compensate::Assembly a =
      compensate::assembly_of(pocket.ph.tools.tools.at("T1"), pocket.ph.machine.holder);
  const stock::ZMap z = pocketed();
  const auto at55 = compensate::interference({&z, {}, nullptr}, {50, 50, -55}, a),
             at56 = compensate::interference({&z, {}, nullptr}, {50, 50, -54}, a);
  CHECK(at55.part == compensate::AssemblyPart::holder);
  CHECK(at55.depth_mm - at56.depth_mm == doctest::Approx(1.0));
}

TEST_CASE("collision: a plunge deeper than the flutes: the shank follows into its bore unless it is wider") {
  // T2 (shank as wide as the flutes) plunges 55 mm into solid stock with 20
  // mm flutes: the flutes cut the bore the shank follows, so the plunge
  // (line 5) is clean and the cut along X (line 6) is the first error. T3's
  // shank is 12 mm over 10 mm flutes: its ring 5 to 6 mm from the axis meets
  // material the flutes never cut, from the plunge on: at the bottom
  // 0 - (-55 + 20) = 35 mm deep.
  const stock::ZMap solid = stock::make_stock("box:0,0,-80,100,100,0", {});
  const Run same(test::pocket_floor_pass(2), solid);
  const compensate::Collision* s2 = same.find("shank_collision");
  REQUIRE(s2);
  CHECK(s2->first_line == 6);
  const Run wide(test::pocket_floor_pass(3), solid);
  const compensate::Collision* s3 = wide.find("shank_collision");
  REQUIRE(s3);
  CHECK(s3->first_line == 5);
  CHECK(s3->worst_mm == deflex::test::within(35.0, 1e-3));
}

TEST_CASE("collision: the neck and shank begin where the force model's flutes end") {
  // The engaged edge is sliced up to the flute length and no higher
  // (force::make_slices); the non-cutting assembly starts there, neck or not.
  const auto tools = stiffness::parse_tool_library(R"(tools:
  T1: {type: flat, diameter_mm: 10, flutes: 4, flute_length_mm: 20, stickout_mm: 40, material: carbide}
  T2: {type: flat, diameter_mm: 6, flutes: 3, flute_length_mm: 9, stickout_mm: 35, shank_diameter_mm: 6,
       neck: {diameter_mm: 5.6, length_mm: 12}, material: carbide}
)", "lib.yaml");
  for (const char* id : {"T1", "T2"}) {
    const stiffness::Tool& t = tools.tools.at(id);
    const force::CutterSlices cs = force::make_slices(force::cutter_of(t), 0.2, t.flute_length_mm);
    REQUIRE_FALSE(cs.slices.empty());
    const double top = cs.dz_mm * static_cast<double>(cs.slices.size());  // slice i covers [i dz, (i+1) dz]
    const compensate::Assembly a = compensate::assembly_of(t, std::nullopt);
    REQUIRE_FALSE(a.frusta.empty());
    CHECK(a.frusta.front().z0_mm == doctest::Approx(top));
    CHECK(a.frusta.front().part == (t.neck ? compensate::AssemblyPart::neck : compensate::AssemblyPart::shank));
  }
}

}  // TEST_SUITE
