// Cusp height: the paper's checks (Mikó et al., 002_..., Eq. 1-7) and the
// per-point analysis on rasters whose step-over, slope and direction are known.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "deflex/process/cusp.hpp"

using namespace deflex;
using doctest::Approx;
using process::CuspSample;

namespace {

constexpr double kDeg = std::numbers::pi / 180;

// Passes of a ball D on the plane z = tan(slope) x (rising along +X), each
// `length` long at `spacing` between samples, `step` apart horizontally,
// zig-zag, the passes along X (`along_x`) or along Y. The tips lie on the
// plane itself: the analysis reads only their XY, the feed and the normal.
std::vector<CuspSample> raster(double d_mm, double slope_deg, bool along_x, double step, int passes,
                               double length = 20, double spacing = 0.5) {
  const double s = slope_deg * kDeg;
  const Eigen::Vector3d n(-std::sin(s), 0, std::cos(s));
  std::vector<CuspSample> v;
  for (int k = 0; k < passes; ++k) {
    const int m = static_cast<int>(length / spacing);
    const double dir = k % 2 ? -1 : 1;
    for (int i = 0; i <= m; ++i) {
      const double u = (dir > 0 ? i : m - i) * spacing, w = k * step;
      CuspSample c;
      const double x = along_x ? u : w, y = along_x ? w : u;
      c.tip_mm = {x, y, std::tan(s) * x};
      c.feed_dir = along_x ? Eigen::Vector3d(dir, 0, dir * std::tan(s)) : Eigen::Vector3d(0, dir, 0);
      c.normal = n;
      c.profile_diameter_mm = d_mm;
      c.cutting = true;
      v.push_back(c);
    }
  }
  return v;
}


// The straightforward search the kd-trees stand for: every sample of the
// blocks b - 1 .. b + 1 within D_e of a sample of block b, by the rules of
// cusp.hpp, the nearest per side (equally near: the lower sample number):
// per sample the step-over to the left and to the right.
std::vector<std::pair<double, double>> stepovers_by_scan(const std::vector<CuspSample>& v, std::size_t block) {
  auto flat = [](const Eigen::Vector3d& f) {
    const Eigen::Vector2d h(f.x(), f.y());
    return h.norm() > 1e-9 * std::max(1.0, f.norm()) ? Eigen::Vector2d(h / h.norm()) : Eigen::Vector2d::Zero();
  };
  std::vector<std::pair<double, double>> out(v.size(), {std::nan(""), std::nan("")});
  for (std::size_t i = 0; i < v.size(); ++i) {
    const CuspSample& p = v[i];
    const Eigen::Vector2d t = flat(p.feed_dir), xy = p.tip_mm.head<2>();
    if (!p.cutting || t.norm() == 0) continue;
    const double de = p.profile_diameter_mm;
    const std::size_t b = i / block, lo = b ? (b - 1) * block : 0, hi = std::min(v.size(), (b + 2) * block);
    double across_of[2] = {std::nan(""), std::nan("")}, dist_of[2] = {HUGE_VAL, HUGE_VAL};
    for (std::size_t j = lo; j < hi; ++j) {
      const CuspSample& q = v[j];
      const Eigen::Vector2d tq = flat(q.feed_dir), d = q.tip_mm.head<2>() - xy;
      if (tq.norm() == 0 || d.squaredNorm() > de * de) continue;
      if (std::fabs(tq.dot(t)) < std::cos(30 * kDeg)) continue;
      const double across = std::fabs(tq.x() * d.y() - tq.y() * d.x()), along = t.dot(d);
      if (across < 1e-3 + along * along / de || across > de) continue;
      const int side = t.x() * d.y() - t.y() * d.x() > 0;
      if (d.norm() < dist_of[side]) dist_of[side] = d.norm(), across_of[side] = across;  // j rises: ties keep the lower
    }
    out[i] = {across_of[1], across_of[0]};
  }
  return out;
}

}  // namespace

TEST_SUITE("process") {
  TEST_CASE("cusp height: the checks of Miko et al. (Eq. 1, 4, 7)") {
    CHECK(process::cusp_height_mm(12, 0.2, 0) * 1000 == Approx(0.83).epsilon(0.005));
    CHECK(process::cusp_height_mm(12, 0.8, 0) * 1000 == Approx(13.35).epsilon(0.001));
    CHECK(process::cusp_alpha3_rad(45 * kDeg, 2.9 * kDeg) / kDeg == Approx(2.05).epsilon(0.005));
    // Boundary cases of Eq. 4: along the fall line no slope across the feed;
    // along a level line the whole slope.
    CHECK(process::cusp_alpha3_rad(0, 30 * kDeg) == Approx(0));
    CHECK(process::cusp_alpha3_rad(90 * kDeg, 30 * kDeg) / kDeg == Approx(30));
    // A step-over wider than the ball leaves the whole radius.
    CHECK(process::cusp_height_mm(6, 7, 0) == Approx(3));
  }

  TEST_CASE("cusp height per point: a zig-zag raster on a 20 deg slope, across and along the slope") {
    const double d = 10, step = 0.4, slope = 20;
    // Passes along X climb the slope (A = 0): the step-over runs along a level
    // line, so alpha_3 = 0 and Ch is Eq. 1 of the horizontal step-over.
    {
      const auto v = raster(d, slope, true, step, 5);
      const auto r = process::cusp_heights(v);
      const std::size_t mid = v.size() / 2;
      CHECK(r[mid].stepover_mm == Approx(step).epsilon(1e-9));
      CHECK(r[mid].direction_deg == Approx(0).scale(1));
      CHECK(r[mid].inclination_deg == Approx(slope));
      CHECK(r[mid].alpha3_deg == Approx(0).scale(1));
      CHECK(r[mid].height_mm == Approx(process::cusp_height_mm(d, step, 0)));
    }
    // Passes along Y follow level lines (A = 90 deg): the step-over climbs the
    // slope, the distance on the surface is step / cos 20 and Ch is Eq. 2.
    {
      const auto v = raster(d, slope, false, step, 5);
      const auto r = process::cusp_heights(v);
      const std::size_t mid = v.size() / 2;
      CHECK(r[mid].stepover_mm == Approx(step).epsilon(1e-9));
      CHECK(r[mid].direction_deg == Approx(90));
      CHECK(r[mid].alpha3_deg == Approx(slope));
      // The ridge between two balls whose centres lie step / cos(20) apart on
      // the surface stands R - sqrt(R^2 - (step / (2 cos 20))^2) above it.
      const double half = step / (2 * std::cos(slope * kDeg)), R = d / 2;
      CHECK(r[mid].height_mm == Approx(R - std::sqrt(R * R - half * half)));
      CHECK(r[mid].height_mm > process::cusp_height_mm(d, step, 0));
    }
  }

  TEST_CASE("cusp height per point: uneven step-overs take the wider side; a lone pass has none") {
    auto v = raster(10, 0, true, 0.3, 3);
    // Move the third pass out to 0.9 mm from the second: the middle pass sees
    // 0.3 on one side and 0.6 on the other.
    for (auto& c : v)
      if (c.tip_mm.y() > 0.5) c.tip_mm.y() = 0.9;
    const auto r = process::cusp_heights(v);
    const std::size_t mid = v.size() / 2;
    CHECK(r[mid].stepover_mm == Approx(0.6));
    CHECK(r[mid].height_mm == Approx(process::cusp_height_mm(10, 0.6, 0)));
    CHECK(r[0].stepover_mm == Approx(0.3));  // the first pass has one neighbour
    // Right at the turn of the zig-zag, where the next pass is a short link
    // away along the path, it is still the neighbour.
    const std::size_t end0 = v.size() / 3 - 1;
    CHECK(r[end0].stepover_mm == Approx(0.3));
    const auto lone = process::cusp_heights(raster(10, 0, true, 0.3, 1));
    for (const auto& c : lone) CHECK(std::isnan(c.height_mm));
  }

  TEST_CASE("cusp height per point: concentric contour passes, the own curved pass is never the neighbour") {
    // Circles of radius 10, 10.5, 11 mm (step 0.5), sampled every 0.5 mm, ball D6.
    std::vector<CuspSample> v;
      for (int k = 0; k < 3; ++k) {
      const double rad = 10 + 0.5 * k;
      const int m = static_cast<int>(2 * std::numbers::pi * rad / 0.5);
      for (int i = 0; i < m; ++i) {
        const double a = 2 * std::numbers::pi * i / m;
        CuspSample c;
        c.tip_mm = {rad * std::cos(a), rad * std::sin(a), 0};
        c.feed_dir = {-std::sin(a), std::cos(a), 0};
        c.profile_diameter_mm = 6;
        c.cutting = true;
          v.push_back(c);
      }
    }
    const auto r = process::cusp_heights(v);
    // A point of the middle circle: 0.5 to either neighbour (to the line of the
    // neighbour's travel, within the chord sagitta of the sampling).
    const std::size_t mid = v.size() / 2;
    CHECK(r[mid].stepover_mm == Approx(0.5).epsilon(0.01));
    for (const auto& c : r) CHECK(c.stepover_mm > 0.45);
  }
}

TEST_SUITE("process") {
  TEST_CASE("cusp in a window of blocks: the neighbours a search over the whole program finds, pass for pass") {
    // 30 passes of 41 samples: a block of 100 samples holds about 2.4 passes,
    // so each pass's neighbours lie in its block or the next or the one before.
    const std::vector<CuspSample> v = raster(10, 20, true, 0.4, 30);
    const auto whole = process::cusp_heights(v, v.size() * 2);
    const auto windowed = process::cusp_heights(v, 100);
    REQUIRE(windowed.size() == whole.size());
    int with_cusp = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
      CAPTURE(i);
      CHECK(windowed[i].stepover_mm == Approx(whole[i].stepover_mm));
      CHECK(windowed[i].height_mm == Approx(whole[i].height_mm));
      with_cusp += !std::isnan(whole[i].height_mm);
    }
    CHECK(with_cusp == static_cast<int>(v.size()));
    // Streamed: a block's results come once the block after it is whole.
    process::CuspStream cs(100);
    for (std::size_t i = 0; i < 250; ++i) cs.add(v[i]);
    CHECK(cs.ready() == 100);
    cs.forget_before(50);
    CHECK_THROWS(cs.result(49));
    CHECK(cs.result(50).height_mm == Approx(whole[50].height_mm));
    // A window too small for a pass (20 samples, half a pass) misses a
    // neighbour that the whole search finds: the window is what decides.
    const auto tiny = process::cusp_heights(v, 10);
    int missing = 0;
    for (std::size_t i = 0; i < v.size(); ++i) missing += std::isnan(tiny[i].height_mm) && !std::isnan(whole[i].height_mm);
    CHECK(missing > 0);
  }
  TEST_CASE("cusp in a window of blocks: the kd-trees of the blocks find what a scan of the window finds, ties too") {
    // Passes along X whose samples line up across the passes, and passes
    // with a turned raster on top: a sample's two neighbours on the next pass,
    // either side of the foot of the perpendicular, lie equally far from it,
    // one to each side of a block boundary at some block sizes, and passes of
    // different step-over overlap at the pass ends.
    std::vector<CuspSample> v = raster(10, 0, true, 0.5, 14, 6, 0.25);
    for (CuspSample c : raster(10, 10, false, 0.3, 9, 7, 0.5)) {
      c.tip_mm.x() += 0.125;  // half a sample of the first raster: equal distances to its samples
      v.push_back(c);
    }
    // Equally near samples of two passes at different distances across: from
    // a sample of the pass at y = 20, one of the pass at y = 21.25 straight
    // across and two of the pass at y = 21 half a sample along lie 1.25 mm
    // away (0.75^2 + 1^2 = 1.25^2, exactly), 1.25 and 1 across.
    for (auto [y, x0] : {std::pair{20.0, 0.0}, std::pair{21.25, 0.0}, std::pair{21.0, 0.75}})
      for (CuspSample c : raster(10, 0, true, 0, 1, 12, 1.5)) {
        c.tip_mm += Eigen::Vector3d(x0, y, 0);
        v.push_back(c);
      }
    for (std::size_t block : {5u, 17u, 24u, 25u, 64u, 1000u}) {
      CAPTURE(block);
      const auto got = process::cusp_heights(v, block);
      const auto sides = stepovers_by_scan(v, block);
      int found = 0;
      for (std::size_t i = 0; i < v.size(); ++i) {
        CAPTURE(i);
        // The side whose cusp is the higher (the left where they are equal), as cusp_heights() picks it.
        double want = std::nan(""), height = std::nan("");
        for (double ae : {sides[i].first, sides[i].second}) {
          if (std::isnan(ae)) continue;
          const double c = process::cusp_height_mm(v[i].profile_diameter_mm, ae, got[i].alpha3_deg * kDeg);
          if (std::isnan(height) || c > height) height = c, want = ae;
        }
        if (std::isnan(want)) {
          CHECK(std::isnan(got[i].stepover_mm));
        } else {
          CHECK(got[i].stepover_mm == want);  // exactly: the same sample found
          ++found;
        }
      }
      CHECK(found > (block >= 64 ? static_cast<int>(v.size()) / 2 : 0));
    }
  }
}
