#include "deflex/force/mechanistic.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::force {

namespace {

constexpr double two_pi = 2 * std::numbers::pi;

// Per-slice constants of the element force, so the inner loop only multiplies:
// with h db = f_z sin(phi) sin(kappa) db every local force is A sin(phi) + B.
struct SliceLoad {
  double At, Bt;  // tangential force = At sin(phi) + Bt
  double Ar, Br;  // in-plane push toward the axis = Ar sin(phi) + Br
  double Az, Bz;  // Fz = Az sin(phi) + Bz
};

SliceLoad slice_load(const Slice& s, const Coefficients& k, double fz_mm) {
  const double hc = fz_mm * s.sin_kappa * s.width_mm;  // h db per unit sin(phi)
  const double e = s.edge_mm;
  const double sk = s.sin_kappa, ck = s.cos_kappa;
  SliceLoad L;
  L.At = k.Ktc_N_per_mm2 * hc;
  L.Bt = k.Kte_N_per_mm * e;
  L.Ar = (k.Krc_N_per_mm2 * sk + k.Kac_N_per_mm2 * ck) * hc;
  L.Br = (k.Kre_N_per_mm * sk + k.Kae_N_per_mm * ck) * e;
  L.Az = (k.Krc_N_per_mm2 * ck - k.Kac_N_per_mm2 * sk) * hc;
  L.Bz = (k.Kre_N_per_mm * ck - k.Kae_N_per_mm * sk) * e;
  return L;
}

// Element force on the tool, weight w:
//   dFx = -dFr sin(k) sin(phi) - dFt cos(phi) - dFa cos(k) sin(phi)
//   dFy = -dFr sin(k) cos(phi) + dFt sin(phi) - dFa cos(k) cos(phi)
//   dFz =  dFr cos(k) - dFa sin(k)
inline void add_element(const SliceLoad& L, double s_phi, double c_phi, double w, Vec3& acc) {
  // h = f sin(phi) sin(kappa) <= 0: the edge is not in the chip. An edge exactly at
  // phi = 0 or pi (where the surface-generating force is sampled) carries no
  // cutting load and, being a boundary point of the cut, no edge load either; the
  // tolerance keeps rounding of the angle from switching its edge force on.
  if (s_phi <= 1e-12) return;
  const double ft = L.At * s_phi + L.Bt;
  const double radial = L.Ar * s_phi + L.Br;
  acc.x() += w * (-radial * s_phi - ft * c_phi);
  acc.y() += w * (-radial * c_phi + ft * s_phi);
  acc.z() += w * (L.Az * s_phi + L.Bz);
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
  if (steps < 1) throw Error(ErrorKind::internal, "make_angle_grid: steps must be >= 1");
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
    const SliceLoad L = slice_load(cs.slices[i], k, fz_mm);
    const double base = theta - cs.slices[i].lag;
    for (int t = 0; t < cs.cutter.flutes; ++t) {
      const double x = base + t * pitch;
      const double phi = x - two_pi * std::floor(x / two_pi);
      if (inside(ivs, phi)) add_element(L, std::sin(phi), std::cos(phi), 1.0, f);
    }
  }
  return f;
}

void revolution_forces(const CutterSlices& cs, const AngleGrid& grid, const Coefficients& k,
                       double fz_mm, const Engagement& eng, std::span<Vec3> out_N) {
  const int N = grid.steps;
  if (static_cast<int>(out_N.size()) != N)
    throw Error(ErrorKind::internal, "revolution_forces: output size differs from the grid");
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
    const SliceLoad L = slice_load(cs.slices[i], k, fz_mm);
    for (int t = 0; t < teeth; ++t) {
      // phi of cell j = j d + c, the cell spanning [phi - d/2, phi + d/2].
      const double c = t * pitch - cs.slices[i].lag;
      const double sc = std::sin(c), cc = std::cos(c);
      for (const AngleInterval& iv : ivs) {
        const long j0 = static_cast<long>(std::ceil((iv.start - c) / d - 0.5));
        const long j1 = static_cast<long>(std::floor((iv.end - c) / d + 0.5));
        // A cell touching an interval end counts for the covered part of it, at
        // the middle of that part; interior cells use the sine table rotated by c.
        auto partial = [&](long j) {
          const double lo = std::max(j * d + c - d / 2, iv.start);
          const double hi = std::min(j * d + c + d / 2, iv.end);
          if (hi <= lo) return;
          const int jj = wrap(j, N);
          const double m = 0.5 * (lo + hi);
          add_element(L, std::sin(m), std::cos(m), (hi - lo) / d, out_N[periodic ? jj % M : jj]);
        };
        partial(j0);
        if (j1 <= j0) continue;
        // Grid and output indices advance with j; wrapped by compare, not division.
        int jj = wrap(j0 + 1, N);
        int jo = periodic ? jj % M : jj;
        for (long j = j0 + 1; j < j1; ++j) {
          const double s = grid.sin_t[jj] * cc + grid.cos_t[jj] * sc;
          const double co = grid.cos_t[jj] * cc - grid.sin_t[jj] * sc;
          add_element(L, s, co, 1.0, out_N[jo]);
          if (++jj == N) jj = 0;
          if (++jo == M) jo = 0;
        }
        partial(j1);
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

MeanTorque mean_torque(const CutterSlices& cs, const Coefficients& k, double fz_mm, const Engagement& eng) {
  MeanTorque m;
  const std::size_t n = std::min(cs.slices.size(), eng.slices.size());
  // An interval's part where the chip is cut (h > 0: sin(phi) > 0), in [0, 4 pi):
  // (0, pi) and (2 pi, 3 pi); sin and cos are periodic, so the integral needs
  // no wrapping.
  auto cut_part = [](double a, double b, double lo, double hi, double& from, double& to) {
    from = std::max(a, lo);
    to = std::min(b, hi);
    return to > from;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Slice& sl = cs.slices[i];
    const SliceLoad L = slice_load(sl, k, fz_mm);
    double cos_sum = 0, angle = 0;  // sum of (cos a - cos b) and of (b - a) over the cut parts
    for (const AngleInterval& iv : eng.slices[i])
      for (const double lo : {0.0, two_pi}) {
        double a, b;
        if (!cut_part(iv.start, iv.end, lo, lo + std::numbers::pi, a, b)) continue;
        cos_sum += std::cos(a) - std::cos(b);
        angle += b - a;
      }
    // N mm per tooth and revolution, over 2 pi.
    const double w = cs.cutter.flutes * sl.r_mm / two_pi / 1000.0;
    m.cutting_Nm += w * L.At * cos_sum;
    m.edge_Nm += w * L.Bt * angle;
  }
  return m;
}

double peak_feed_share(std::span<const Vec3> total_N, std::span<const Vec3> edge_N, double limit_N) {
  if (total_N.size() != edge_N.size()) throw Error(ErrorKind::internal, "peak_feed_share: grids differ");
  double s = 1;
  const double L2 = limit_N * limit_N;
  for (std::size_t j = 0; j < total_N.size(); ++j) {
    const Vec3 fc = total_N[j] - edge_N[j];
    const double a = fc.squaredNorm(), b = 2 * fc.dot(edge_N[j]), c = edge_N[j].squaredNorm() - L2;
    if (c > 0) return 0;
    if (a == 0) continue;
    // q(s) = a s^2 + b s + c with q(0) = c <= 0: q <= 0 up to its larger root,
    // in the form without cancellation for either sign of b.
    const double d = std::sqrt(b * b - 4 * a * c);
    const double root = b >= 0 ? (b + d > 0 ? -2 * c / (b + d) : 0.0) : (-b + d) / (2 * a);
    s = std::min(s, root);
  }
  return std::max(s, 0.0);
}

namespace {

// The tables behind the surface-generating forces. Tooth 0's edge at z_i is at
// normal_phi when theta_i = normal_phi + psi_i (the other teeth give the same
// force: periodic in the pitch). At theta_i, tooth t's edge at slice m sits at
// phi = (normal_phi + psi_i) + (t pitch - psi_m); the sines of both parts are
// tabled so the double loop needs no trigonometry.
struct Part {
  std::size_t slice;
  double angle, s, c;
};
struct GeneratingParts {
  std::vector<Part> a;            // per engaged slice
  std::vector<Part> b;            // per engaged slice and tooth
  std::vector<SliceLoad> loads;   // per engaged slice
};

void generating_parts(const CutterSlices& cs, const Coefficients& k, double fz_mm,
                      const Engagement& eng, double normal_phi, GeneratingParts& p) {
  p.a.clear();
  p.b.clear();
  p.loads.clear();
  const std::size_t n = std::min(cs.slices.size(), eng.slices.size());
  const int flutes = cs.cutter.flutes;
  for (std::size_t i = 0; i < n; ++i) {
    if (eng.slices[i].empty()) continue;
    const double x = normal_phi + cs.slices[i].lag;
    p.a.push_back({i, x, std::sin(x), std::cos(x)});
    for (int t = 0; t < flutes; ++t) {
      const double y = t * cs.pitch() - cs.slices[i].lag;
      p.b.push_back({i, y, std::sin(y), std::cos(y)});
    }
  }
  for (const Part& q : p.a) p.loads.push_back(slice_load(cs.slices[q.slice], k, fz_mm));
}

// Adds to acc the force engaged slice m (index into p.a) carries at the instant
// the edge at `ai` passes normal_phi: all its teeth in the cut.
inline void add_slice_at_instant(const GeneratingParts& p, const Part& ai, std::size_t m,
                                 int flutes, const Engagement& eng, Vec3& acc) {
  const auto& ivs = eng.slices[p.a[m].slice];
  for (int t = 0; t < flutes; ++t) {
    const Part& bm = p.b[m * flutes + t];
    const double x = ai.angle + bm.angle;
    if (!inside(ivs, x - two_pi * std::floor(x / two_pi))) continue;
    add_element(p.loads[m], ai.s * bm.c + ai.c * bm.s, ai.c * bm.c - ai.s * bm.s, 1.0, acc);
  }
}

}  // namespace

void surface_generating_forces(const CutterSlices& cs, const Coefficients& k, double fz_mm,
                               const Engagement& eng, double normal_phi,
                               std::vector<SurfaceForce>& out) {
  out.clear();
  GeneratingParts p;
  generating_parts(cs, k, fz_mm, eng, normal_phi, p);
  const int flutes = cs.cutter.flutes;
  for (const Part& ai : p.a) {
    Vec3 f = Vec3::Zero();
    for (std::size_t m = 0; m < p.a.size(); ++m) add_slice_at_instant(p, ai, m, flutes, eng, f);
    out.push_back({cs.slices[ai.slice].z_mm, f});
  }
}

void surface_generating_loads(const CutterSlices& cs, const Coefficients& k, double fz_mm,
                              const Engagement& eng, double normal_phi, GeneratingLoads& out) {
  GeneratingParts p;
  generating_parts(cs, k, fz_mm, eng, normal_phi, p);
  const std::size_t n = p.a.size();
  const int flutes = cs.cutter.flutes;
  out.slice.resize(n);
  out.z_mm.resize(n);
  out.force_N.assign(n * n, Vec3::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    out.slice[i] = p.a[i].slice;
    out.z_mm[i] = cs.slices[p.a[i].slice].z_mm;
    for (std::size_t m = 0; m < n; ++m)
      add_slice_at_instant(p, p.a[i], m, flutes, eng, out.force_N[i * n + m]);
  }
}

std::vector<SurfaceForce> surface_generating_forces(const CutterSlices& cs, const Coefficients& k,
                                                    double fz_mm, const Engagement& eng,
                                                    double normal_phi) {
  std::vector<SurfaceForce> out;
  surface_generating_forces(cs, k, fz_mm, eng, normal_phi, out);
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
