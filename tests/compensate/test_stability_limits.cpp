// The stability limit along a program (Point::ap_limit_mm): a slot cut by a
// flat end is held against the zero-order lobes of a full slot's immersion,
// computed here from the stability module directly; a cut deeper than the
// limit is a chatter finding at its line, one shallower none; a tool whose
// material has no density is said to be unchecked.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "../support.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/compensate/plausibility.hpp"
#include "deflex/force/material.hpp"
#include "deflex/stability/frf.hpp"
#include "deflex/stability/model.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;

namespace {

constexpr double kRpm = 8000;

// A slot along +X with T1 (D10 flat end, 4 flutes) in Al7075-T6, a_p deep,
// the cut N6 on the text's eighth line.
std::string slot(double ap_mm) {
  char b[400];
  std::snprintf(b, sizeof b,
                "%%\nO0001\nN1 G21 G90 G17 G40 G49 G80 G54\nN2 T1 M06\nN3 S%.0f M03\nN4 G00 X-10. Y0. Z5.\n"
                "N5 G01 Z%.3f F600.\nN6 X90.\nN7 G00 Z5.\nN8 M30\n%%\n",
                kRpm, -ap_mm);
  return b;
}

struct Slot {
  stock::ZMap stock = stock::make_stock("box:0,-20,-20,100,20,0", {});
  compensate::Physics ph;
  compensate::Settings s;
  Slot() {
    ph.tools = stiffness::load_tool_library("samples/tools.yaml");
    ph.machine = stiffness::load_machine_stiffness("samples/machines/mill3.yaml");
    ph.k = force::find_material(force::load_material_library("samples/materials.yaml"), "Al7075-T6").k;
    ph.stock = &stock;
    s.threads = 1;
    s.gain = 0;
  }
  std::vector<compensate::Point> run(double ap_mm) const {
    const test::Interpreted in = test::interpret_text(slot(ap_mm).c_str());
    REQUIRE(in.errors == 0);
    return compensate::simulate(in.motions, {}, ph, s);
  }
  // The limit of a full slot by the lobes of its immersion, [0, pi].
  double slot_limit_mm() const {
    const stiffness::Tool& t = ph.tools.tools.at("T1");
    const stability::TipModel tip = stability::tip_model(t, ph.machine, false);
    const auto [lo, hi] = stability::rpm_range(30000);  // the profile's spindle is not in Physics here
    const stability::Cut cut = stability::cut_of(ph.k, t.flutes, {0, std::numbers::pi});
    return stability::StabilityLimit(stability::zero_order_lobes(tip.frf, cut, lo, hi), lo, hi).ap_limit_mm(kRpm);
  }
};

// The steady part of the slot: past the tool's entry, before its exit.
bool steady(const compensate::Point& p) { return !p.air && !p.plunge && p.tip_mm.x() > 10 && p.tip_mm.x() < 80; }

}  // namespace

TEST_SUITE("compensate") {

TEST_CASE("stability along a program: a slot's points are held against the lobes of a full slot within 2 %") {
  const Slot w;
  const double want = w.slot_limit_mm();
  MESSAGE("full-slot limit of T1 at 8000 rpm: " << want << " mm");
  std::size_t n = 0;
  for (const compensate::Point& p : w.run(3.0)) {
    if (!steady(p)) continue;
    ++n;
    CHECK(p.ap_mm == deflex::test::within(3.0, 1e-3));
    CHECK(p.ap_limit_mm == deflex::test::within(want, 0.02));
  }
  CHECK(n > 50);
}

TEST_CASE("stability along a program: chatter where a_p is over the limit, at its line; nothing below it") {
  const Slot w;
  const double limit = w.slot_limit_mm();
  // Depths on the slicing's grid (0.2 mm), well either side of the limit.
  const double deep = std::ceil(1.5 * limit / 0.2) * 0.2, shallow = std::floor(0.6 * limit / 0.2) * 0.2;
  REQUIRE(shallow > 0);
  REQUIRE(deep < 22);
  const auto over = compensate::plausibility(w.run(deep), w.ph.tools, w.s);
  const compensate::Finding* f = over.find("chatter");
  REQUIRE(f != nullptr);
  CHECK(f->line == 8);  // N6 X90., the eighth line of the text
  CHECK(f->tool == "T1");
  CHECK(f->worst == deflex::test::within(deep / limit, 0.03));
  CHECK(f->message.find("deflex stability --tool T1") != std::string::npos);
  CHECK(compensate::plausibility(w.run(shallow), w.ph.tools, w.s).find("chatter") == nullptr);
}

TEST_CASE("stability along a program: a tool material without density is unchecked, and said so at its first cut") {
  Slot w;
  w.ph.tools.tools.at("T1").material.density_kg_per_m3 = 0;
  const auto pts = w.run(3.0);
  for (const compensate::Point& p : pts)
    if (steady(p)) CHECK(p.ap_limit_mm == -1);
  const auto pl = compensate::plausibility(pts, w.ph.tools, w.s);
  const compensate::Finding* f = pl.find("stability_unchecked");
  REQUIRE(f != nullptr);
  CHECK(f->line == 8);  // N6: the first cut that is no plunge (a plunge is not checked)
  CHECK(f->message.find("density_kg_per_m3") != std::string::npos);
  CHECK(pl.find("chatter") == nullptr);
}

TEST_CASE("stability along a program: a tool's measured FRF (frf_file) replaces the model; the model's own FRF gives its limits") {
  Slot model, measured;
  test::TempDir dir("frf");
  const stability::TipModel tip = stability::tip_model(model.ph.tools.tools.at("T1"), model.ph.machine, false);
  test::write_file(dir / "tap_T1.csv", stability::frf_csv(tip.frf));
  measured.ph.tools.tools.at("T1").frf_file = dir / "tap_T1.csv";
  const auto a = model.run(3.0), b = measured.run(3.0);
  REQUIRE(a.size() == b.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!steady(a[i])) continue;
    ++n;
    // The measured path keys the matrix's direction in 64ths: within 3 %.
    CHECK(b[i].ap_limit_mm == deflex::test::within(a[i].ap_limit_mm, 0.03));
  }
  CHECK(n > 50);
}

TEST_CASE("stability along a program: a broken frf_file is a located error before the simulation") {
  test::TempDir dir("frf");
  test::write_file(dir / "tap.csv", "frequency_Hz,re_xx_mm_per_N,im_xx_mm_per_N,re_yy_mm_per_N,im_yy_mm_per_N\n"
                                    "100,1e-5,-1e-6,1e-5,-1e-6\n200,1e-5,oops,1e-5,-1e-6\n");
  std::string lib = test::read_file("samples/tools.yaml");
  lib += "  T9:\n    type: flat\n    diameter_mm: 10\n    flutes: 4\n    flute_length_mm: 22\n    stickout_mm: 40\n"
         "    material: carbide\n    frf_file: tap.csv\n";
  test::write_file(dir / "tools.yaml", lib);
  test::write_file(dir / "p.nc", slot(3.0));
  const test::CliResult r = test::run_cli({"simulate", dir / "p.nc", "--tool-file", dir / "tools.yaml", "--tool", "T9",
                                           "--stock", "box:0,-20,-20,100,20,0", "--material", "Al7075-T6"});
  CHECK(r.rc == 1);
  CHECK(r.err.find("tap.csv:3:") != std::string::npos);
  CHECK(r.out.empty());
}

}  // TEST_SUITE
