#include "deflex/force/mechanistic.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::force {

namespace {

constexpr double two_pi = 2 * std::numbers::pi;

// Per-slice constants of the element force, so the inner loop only multiplies.
struct SliceLoad {
  double s_k, c_k;      // sin, cos kappa
  double hc;            // f_z sin(kappa) db: cutting term per unit sin(phi)
  double edge;          // dS
};

SliceLoad slice_load(const Slice& s, double fz_mm) {
  return {s.sin_kappa, s.cos_kappa, fz_mm * s.sin_kappa * s.width_mm, s.edge_mm};
}

// Element force on the tool (Engin & Altintas 2001; Smaoui 2011 Eq. 4-5), weight w.
inline void add_element(const SliceLoad& L, const Coefficients& k, double s_phi, double c_phi,
                        double w, Vec3& acc) {
  if (s_phi <= 0) return;  // h = f sin(phi) sin(kappa) <= 0: the edge is not in the chip
  const double chip = L.hc * s_phi;  // h db
  const double ft = k.Ktc_N_per_mm2 * chip + k.Kte_N_per_mm * L.edge;
  const double fr = k.Krc_N_per_mm2 * chip + k.Kre_N_per_mm * L.edge;
  const double fa = k.Kac_N_per_mm2 * chip + k.Kae_N_per_mm * L.edge;
  const double radial = fr * L.s_k + fa * L.c_k;  // in-plane push toward the axis
  acc.x() += w * (-radial * s_phi - ft * c_phi);
  acc.y() += w * (-radial * c_phi + ft * s_phi);
  acc.z() += w * (fr * L.c_k - fa * L.s_k);
}

inline bool inside(const std::vector<AngleInterval>& ivs, double phi) {
  for (const AngleInterval& iv : ivs)
    if ((phi >= iv.start && phi <= iv.end) || (phi + two_pi >= iv.start && phi + two_pi <= iv.end))
      return true;
  return false;
}

inline int wrap(long j, int n) {
  long m = j % n;
  return static_cast<int>(m < 0 ? m + n : m);
}

}  // namespace

AngleGrid make_angle_grid(int steps) {
  if (steps < 1) throw Error(Exit::internal, "make_angle_grid: steps must be >= 1");
  AngleGrid g;
  g.steps = steps;
  g.sin_t.resize(steps);
  g.cos_t.resize(steps);
  for (int j = 0; j < steps; ++j) {
    const double t = two_pi * j / steps;
    g.sin_t[j] = std::sin(t);
    g.cos_t[j] = std::cos(t);
  }
  return g;
}

Vec3 force_at_angle(const CutterSlices& cs, const Coefficients& k, double fz_mm,
                    const Engagement& eng, double theta) {
  Vec3 f = Vec3::Zero();
  const double pitch = cs.pitch();
  const std::size_t n = std::min(cs.slices.size(), eng.slices.size());
  for (std::size_t i = 0; i < n; ++i) {
    const auto& ivs = eng.slices[i];
    if (ivs.empty()) continue;
    const SliceLoad L = slice_load(cs.slices[i], fz_mm);
    for (int t = 0; t < cs.cutter.flutes; ++t) {
      double phi = std::fmod(theta + t * pitch - cs.slices[i].lag, two_pi);
      if (phi < 0) phi += two_pi;
      if (inside(ivs, phi)) add_element(L, k, std::sin(phi), std::cos(phi), 1.0, f);
    }
  }
  return f;
}

void revolution_forces(const CutterSlices& cs, const AngleGrid& grid, const Coefficients& k,
                       double fz_mm, const Engagement& eng, std::span<Vec3> out_N) {
  const int N = grid.steps;
  if (static_cast<int>(out_N.size()) != N)
    throw Error(Exit::internal, "revolution_forces: output size differs from the grid");
  const int flutes = cs.cutter.flutes;
  const bool periodic = N % flutes == 0;
  // With the shortcut every grid cell J of the revolution belongs to tooth 0 at
  // rotation J, i.e. to tooth J / M at rotation J mod M (M = N / flutes).
  const int M = periodic ? N / flutes : N;
  const int teeth = periodic ? 1 : flutes;
  const double d = two_pi / N;
  const double pitch = cs.pitch();
  std::fill(out_N.begin(), out_N.begin() + M, Vec3::Zero());

  const std::size_t n = std::min(cs.slices.size(), eng.slices.size());
  for (std::size_t i = 0; i < n; ++i) {
    const auto& ivs = eng.slices[i];
    if (ivs.empty()) continue;
    const SliceLoad L = slice_load(cs.slices[i], fz_mm);
    for (int t = 0; t < teeth; ++t) {
      // phi of cell j = j d + c, the cell spanning [phi - d/2, phi + d/2].
      const double c = t * pitch - cs.slices[i].lag;
      const double sc = std::sin(c), cc = std::cos(c);
      for (const AngleInterval& iv : ivs) {
        const long j0 = static_cast<long>(std::ceil((iv.start - c) / d - 0.5));
        const long j1 = static_cast<long>(std::floor((iv.end - c) / d + 0.5));
        for (long j = j0; j <= j1; ++j) {
          const double lo = std::max(j * d + c - d / 2, iv.start);
          const double hi = std::min(j * d + c + d / 2, iv.end);
          const double w = (hi - lo) / d;
          if (w <= 0) continue;
          const int jj = wrap(j, N);
          Vec3& acc = out_N[periodic ? jj % M : jj];
          if (j == j0 || j == j1) {  // partial cell: its covered part at its middle
            const double m = 0.5 * (lo + hi);
            add_element(L, k, std::sin(m), std::cos(m), w, acc);
          } else {
            const double s = grid.sin_t[jj] * cc + grid.cos_t[jj] * sc;
            const double co = grid.cos_t[jj] * cc - grid.sin_t[jj] * sc;
            add_element(L, k, s, co, 1.0, acc);
          }
        }
      }
    }
  }
  if (periodic)
    for (int j = M; j < N; ++j) out_N[j] = out_N[j % M];
}

std::vector<Vec3> revolution_forces(const CutterSlices& cs, const Coefficients& k, double fz_mm,
                                    const Engagement& eng, int steps) {
  const AngleGrid g = make_angle_grid(steps);
  std::vector<Vec3> out(steps, Vec3::Zero());
  revolution_forces(cs, g, k, fz_mm, eng, out);
  return out;
}

ForceSummary summarize(std::span<const Vec3> forces_N) {
  ForceSummary s;
  if (forces_N.empty()) return s;
  for (const Vec3& f : forces_N) {
    s.mean_N += f;
    s.peak_abs_N = s.peak_abs_N.cwiseMax(f.cwiseAbs());
  }
  s.mean_N /= static_cast<double>(forces_N.size());
  return s;
}

std::vector<SurfaceForce> surface_generating_forces(const CutterSlices& cs, const Coefficients& k,
                                                    double fz_mm, const Engagement& eng,
                                                    double normal_phi) {
  std::vector<SurfaceForce> out;
  const std::size_t n = std::min(cs.slices.size(), eng.slices.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (eng.slices[i].empty()) continue;
    // Tooth 0's edge at z_i is at normal_phi when theta = normal_phi + psi(z_i);
    // the other teeth give the same force (periodic in the pitch).
    const double theta = normal_phi + cs.slices[i].lag;
    out.push_back({cs.slices[i].z_mm, force_at_angle(cs, k, fz_mm, eng, theta)});
  }
  return out;
}

SurfaceForcePeak peak_normal(std::span<const SurfaceForce> sf, double normal_phi) {
  const Vec3 nrm(std::sin(normal_phi), std::cos(normal_phi), 0.0);
  SurfaceForcePeak p;
  for (const SurfaceForce& s : sf) {
    const double fn = s.force_N.dot(nrm);
    if (std::abs(fn) > std::abs(p.normal_N)) p = {fn, s.z_mm};
  }
  return p;
}

}  // namespace deflex::force
