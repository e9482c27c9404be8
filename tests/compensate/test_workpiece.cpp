// The workpiece's compliance in the cut (compensate/workpiece.hpp): a compliant
// part adds its displacement under the force on it to the tool's, the surface
// error is the relative displacement along the normal, and the mirror
// compensates that. Closed-form compliance fields stand in for the FEM.
#include <doctest/doctest.h>

#include <cmath>

#include "../sample_physics.hpp"
#include "../support.hpp"
#include "deflex/compensate/apply.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/compensate/contact.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;
using compensate::V3;

namespace {

// A wall that gives way in Y more the farther along X the point lies (a plate
// clamped at X = 0, say), and a little in Z everywhere: mm/N.
struct Field : compensate::WorkpieceCompliance {
  Eigen::Matrix3d at(const Eigen::Vector3d& p, const Eigen::Vector3d&, std::size_t) const override {
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    c(1, 1) = 1e-5 * std::max(0.0, p.x());
    c(2, 2) = 1e-5;
    c(0, 1) = c(1, 0) = 5e-7 * std::max(0.0, p.x());
    return c;
  }
};

// Side milling of a wall along +X (T1, flat D10, a_e 2, a_p 10: a flank cut),
// then a slot along X (a_e = D: not a flank cut, the floor's normal).
const char* kProgram =
    "G21 G90 G17\nT1 M6\nS8000 M3\nG0 X-10. Y-3. Z5.\nG1 Z-10. F800.\nX110.\nG0 Z5.\n"
    "G0 X-10. Y10. Z5.\nG1 Z-2. F800.\nX110.\nG0 Z5.\nM30\n";

struct Run {
  test::Interpreted in = test::interpret_text(kProgram);
  stock::ZMap stock = stock::make_stock("box:0,0,-20,100,40,0", {});
  Field field;
  compensate::Physics ph = test::sample_physics("Al6082-T4");
  compensate::Settings s;
  Run() {
    REQUIRE(in.errors == 0);
    ph.stock = &stock;
    s.threads = 1;
    s.tolerance_mm = 0.005;
  }
};

}  // namespace

TEST_SUITE("compensate") {

TEST_CASE("workpiece: its displacement under -F at the contact adds to the tool's along the normal") {
  Run r;
  const std::vector<compensate::Point> rigid = compensate::simulate(r.in.motions, {}, r.ph, r.s);
  r.ph.workpiece = &r.field;
  const std::vector<compensate::Point> soft = compensate::simulate(r.in.motions, {}, r.ph, r.s);
  REQUIRE(rigid.size() == soft.size());
  const stiffness::Tool& t1 = r.ph.tools.tools.at("T1");
  int flank = 0, floor = 0;
  for (std::size_t i = 0; i < soft.size(); ++i) {
    const compensate::Point &a = rigid[i], &b = soft[i];
    if (b.air || b.plunge) continue;
    // The tool's side is the same: forces, deflection, normal.
    CHECK(b.force_N == a.force_N);
    CHECK(b.delta_mm == a.delta_mm);
    CHECK(b.normal == a.normal);
    CHECK(a.workpiece_delta_mm == V3::Zero());
    // Where the force acts on the part: the wall at the resultant's height for
    // a flank cut, else the contact.
    const V3 at = b.flank ? compensate::flank_point(b, t1, b.height_mm) : compensate::contact_point(b, t1);
    const V3 w = r.field.at(at, b.normal, b.motion) * V3(-b.force_N);
    CHECK((b.workpiece_delta_mm - w).norm() < 1e-15);
    const double shift = -w.dot(b.normal);
    CHECK(b.error_mm == deflex::test::within(a.error_mm + shift, 1e-12));
    if (b.flank) {
      ++flank;
      CHECK(b.flank_min_mm == deflex::test::within(a.flank_min_mm + shift, 1e-12));
      CHECK(b.flank_max_mm == deflex::test::within(a.flank_max_mm + shift, 1e-12));
      // The wall gives way from the tool (the force on it pushes it into the
      // material): it leaves the surface proud, more the farther along X.
      CHECK(shift * a.error_mm >= 0);
    } else {
      ++floor;
    }
  }
  CHECK(flank > 50);
  CHECK(floor > 50);
}

TEST_CASE("workpiece: the mirror compensates the relative displacement, judged with the same workpiece") {
  Run r;
  r.ph.workpiece = &r.field;
  // As the CLI runs it: a long move is split where its error changes along it.
  const gcode::Program prog{SourceText("t.nc", kProgram)};
  const std::vector<bool> split = compensate::splittable(prog, r.in.motions);
  const compensate::Result c = compensate::compensate(r.in.motions, r.ph, r.s, {}, &split);
  CHECK(c.converged);
  // As written the wall's far end leaves the tolerance; the output, simulated
  // afresh with the same compliant part, lands inside it everywhere.
  int outside_before = 0, outside_after = 0, cutting = 0;
  for (const compensate::Point& p : c.nominal)
    if (!p.air && !p.plunge) outside_before += std::fabs(p.error_mm) > r.s.tolerance_mm;
  for (const compensate::Point& p : compensate::simulate(c.motions, c.offsets, r.ph, r.s)) {
    if (p.air || p.plunge) continue;
    ++cutting;
    const V3 end = c.offsets[p.motion], start = p.motion ? c.offsets[p.motion - 1] : V3(V3::Zero());
    const double u = p.count ? static_cast<double>(p.index) / p.count : 1.0;
    const double e = compensate::landing_error(p, start + u * (end - start));
    outside_after += std::fabs(e) > 1.01 * r.s.tolerance_mm;
  }
  INFO(outside_before << " of " << cutting << " points outside as written, " << outside_after << " after");
  CHECK(outside_before > cutting / 10);
  CHECK(outside_after == 0);
  // Without the workpiece the same program compensates less: the part's share
  // is what moved the points further.
  Run rigid;
  const compensate::Result c0 = compensate::compensate(rigid.in.motions, rigid.ph, rigid.s, {}, &split);
  double moved = 0, moved0 = 0;
  for (const V3& o : c.offsets) moved = std::max(moved, o.norm());
  for (const V3& o : c0.offsets) moved0 = std::max(moved0, o.norm());
  CHECK(moved > moved0 + 0.005);
}

}  // TEST_SUITE
