// Zero-order stability lobes (lobes.hpp; Altintas & Budak 1995).
#include "deflex/stability/lobes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::stability {
namespace {

using cd = std::complex<double>;
constexpr double kPi = std::numbers::pi;
// The most lobes traced: beyond it a speed range reaching so low for so high
// a chatter frequency is past what the zero-order method is for.
constexpr double kMaxLobes = 2000;

using Root = ChatterRoot;

struct Sample {
  double f_Hz = 0;
  std::array<cd, 2> lambda;  // the eigenvalues of alpha Phi, one per branch
  std::array<Root, 2> root;
};

void check_cut(const Cut& c) {
  if (c.flutes < 1) throw Error(ErrorKind::settings, "a cut needs at least one tooth");
  if (!(c.Kt_N_per_mm2 > 0) || !std::isfinite(c.Kt_N_per_mm2))
    throw Error(ErrorKind::settings, "a cut needs a cutting coefficient K_t > 0");
  if (!std::isfinite(c.Kr_ratio)) throw Error(ErrorKind::settings, "a cut needs a finite K_r");
  if (!(c.phi_start_rad >= 0 && c.phi_start_rad < c.phi_exit_rad && c.phi_exit_rad <= kPi + 1e-9))
    throw Error(ErrorKind::settings, "a cut's immersion must be 0 <= start < exit <= pi rad");
}

// The teeth and K_t of a cut: what turns an eigenvalue into a depth.
struct Teeth {
  int flutes;
  double Kt_N_per_mm2;
};

// The root of one eigenvalue lambda of alpha Phi: Lambda = -1 / lambda, then
// a_lim, kappa, psi, eps (lobes.hpp).
Root root_of(cd lambda, const Teeth& c) {
  if (std::abs(lambda) == 0) return {};
  const cd L = -1.0 / lambda;
  if (L.real() == 0) return {};
  const double kappa = L.imag() / L.real();
  Root r;
  r.ap_mm = -2 * kPi * L.real() * (1 + kappa * kappa) / (c.flutes * c.Kt_N_per_mm2);
  r.eps_rad = kPi - 2 * std::atan(kappa);
  r.ok = r.ap_mm > 0 && std::isfinite(r.ap_mm);
  return r;
}

// Eigenvalues of alpha Phi in closed form: lambda^2 - tr lambda + det = 0
// (Altintas & Budak's a0 Lambda^2 + a1 Lambda + 1 = 0 for Lambda = -1/lambda,
// the cross terms of Phi included). The larger root without cancellation, the
// smaller as det / larger (Vieta), so that a singular alpha Phi (a tool tip
// flexible in one direction only) has an exact zero, not round-off that
// would read as a chatter depth of 10^17 mm.
Sample sample_at(const Eigen::Matrix2cd& alpha, const Frf2& phi, double f_Hz, const Teeth& c) {
  const Eigen::Matrix2cd m = alpha * phi;
  const cd tr = m.trace(), det = m.determinant();
  cd disc = std::sqrt(tr * tr - 4.0 * det);
  if (std::abs(tr - disc) > std::abs(tr + disc)) disc = -disc;
  const cd big = 0.5 * (tr + disc);
  Sample s;
  s.f_Hz = f_Hz;
  s.lambda = {big, std::abs(big) > 0 ? det / big : cd(0)};
  for (int b = 0; b < 2; ++b) s.root[b] = root_of(s.lambda[b], c);
  return s;
}

// Keeps each branch continuous: the square root's sign may flip between samples.
void follow(const Sample& prev, Sample& s) {
  const double same = std::abs(s.lambda[0] - prev.lambda[0]) + std::abs(s.lambda[1] - prev.lambda[1]);
  const double swapped = std::abs(s.lambda[0] - prev.lambda[1]) + std::abs(s.lambda[1] - prev.lambda[0]);
  if (swapped < same) std::swap(s.lambda[0], s.lambda[1]), std::swap(s.root[0], s.root[1]);
}

// How many pieces the interval between two samples needs so that a_lim moves
// by under 1 % and eps by under 0.02 rad from one to the next (eps sets the
// speed: lobe 0's n varies as 1 / eps); a change of validity: 16, to find the edge.
int pieces(const Sample& a, const Sample& b) {
  double n = 1;
  for (int k = 0; k < 2; ++k) {
    const Root &ra = a.root[k], &rb = b.root[k];
    if (ra.ok != rb.ok) n = std::max(n, 16.0);
    if (!ra.ok || !rb.ok) continue;
    n = std::max(n, std::abs(rb.ap_mm - ra.ap_mm) / (0.01 * std::min(ra.ap_mm, rb.ap_mm)));
    n = std::max(n, std::abs(rb.eps_rad - ra.eps_rad) / 0.02);
  }
  return static_cast<int>(std::min(64.0, std::ceil(n)));
}

// Every chatter frequency: the FRF's samples, refined by pieces().
std::vector<Sample> sweep(const Frf& frf, const Eigen::Matrix2cd& alpha, const Teeth& c) {
  std::vector<Sample> out;
  for (std::size_t i = 0; i < frf.frequency_Hz.size(); ++i) {
    Sample s = sample_at(alpha, frf.h_mm_per_N[i], frf.frequency_Hz[i], c);
    if (!out.empty()) {
      follow(out.back(), s);
      const Sample a = out.back();
      const int n = pieces(a, s);
      for (int j = 1; j < n; ++j) {
        const double f = a.f_Hz + (s.f_Hz - a.f_Hz) * j / n;
        out.push_back(sample_at(alpha, frf.at(f), f, c));
        follow(out[out.size() - 2], out.back());
      }
      follow(out.back(), s);
    }
    out.push_back(s);
  }
  return out;
}

double rpm_of(const ChatterSample& s, int b, int k, int flutes) {
  return 60 * 2 * kPi * s.f_Hz / (flutes * (s.root[b].eps_rad + 2 * kPi * k));
}

// The pieces of a traced curve inside [rpm_min, rpm_max], each with the point
// just outside at either end (so the range's edges interpolate), to out.
void add_clipped(const Lobe& curve, double rpm_min, double rpm_max, std::vector<Lobe>& out) {
  const std::vector<LobePoint>& p = curve.points;
  auto in = [&](std::size_t i) { return i < p.size() && p[i].rpm >= rpm_min && p[i].rpm <= rpm_max; };
  Lobe piece{curve.k, {}};
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (in(i) || in(i + 1) || (i > 0 && in(i - 1))) {
      piece.points.push_back(p[i]);
      continue;
    }
    if (piece.points.size() > 1) out.push_back(piece);
    piece.points.clear();
  }
  if (piece.points.size() > 1) out.push_back(piece);
}

// The curves of lobe k: each branch split where it has no root.
void add_lobe_curves(const std::vector<ChatterSample>& sw, int k, const Teeth& c, double rpm_min, double rpm_max,
                     std::vector<Lobe>& out) {
  for (int b = 0; b < 2; ++b) {
    Lobe cur{k, {}};
    for (const ChatterSample& s : sw) {
      if (s.root[b].ok) {
        cur.points.push_back({rpm_of(s, b, k, c.flutes), s.root[b].ap_mm, s.f_Hz});
        continue;
      }
      add_clipped(cur, rpm_min, rpm_max, out);
      cur.points.clear();
    }
    add_clipped(cur, rpm_min, rpm_max, out);
  }
}

// The last lobe number that reaches rpm_min at every chatter frequency whose
// a_lim is within 10 times the minimum: eps < 2 pi puts lobe k at frequency f
// above 60 f / (N (k + 1)). Missing lobes would leave the envelope too high
// (unsafe), so every lobe that can set it there is traced.
int lobes_needed(const std::vector<ChatterSample>& sw, double ap_min_mm, int flutes, double rpm_min) {
  double f_top = 0;
  for (const ChatterSample& s : sw)
    for (const Root& r : s.root)
      if (r.ok && r.ap_mm <= 10 * ap_min_mm) f_top = std::max(f_top, s.f_Hz);
  return static_cast<int>(std::min(kMaxLobes, std::ceil(60 * f_top / (flutes * rpm_min))));
}

}  // namespace

Cut cut_of(const force::Coefficients& k, int flutes, force::AngleInterval immersion) {
  const double Kr = k.Ktc_N_per_mm2 != 0 ? k.Krc_N_per_mm2 / k.Ktc_N_per_mm2 : 0;
  return {flutes, k.Ktc_N_per_mm2, Kr, immersion.start, immersion.end};
}

Eigen::Matrix2d directional_coefficients(const Cut& c) {
  const double Kr = c.Kr_ratio;
  // The antiderivatives of Altintas & Budak's averaged terms, at phi.
  auto at = [Kr](double p) {
    const double s = std::sin(2 * p), co = std::cos(2 * p);
    Eigen::Matrix2d m;
    m << co - 2 * Kr * p + Kr * s, -s - 2 * p + Kr * co,  //
        -s + 2 * p + Kr * co, -co - 2 * Kr * p - Kr * s;
    return m;
  };
  return 0.5 * (at(c.phi_exit_rad) - at(c.phi_start_rad));
}

Lobes zero_order_lobes(const Frf& frf, const Cut& cut, double rpm_min, double rpm_max, int max_lobes) {
  check_cut(cut);
  return zero_order_lobes(frf, directional_coefficients(cut).cast<cd>(), cut.flutes, cut.Kt_N_per_mm2, rpm_min, rpm_max,
                          max_lobes);
}

Lobes zero_order_lobes(const Frf& frf, const Eigen::Matrix2cd& alpha, int flutes, double Kt_N_per_mm2, double rpm_min,
                       double rpm_max, int max_lobes) {
  if (flutes < 1 || !(Kt_N_per_mm2 > 0) || !std::isfinite(Kt_N_per_mm2))
    throw Error(ErrorKind::settings, "a cut needs at least one tooth and a cutting coefficient K_t > 0");
  if (!(rpm_min > 0 && rpm_max > rpm_min) || !std::isfinite(rpm_max))
    throw Error(ErrorKind::settings, "the speed range must be 0 < rpm_min < rpm_max");
  if (frf.frequency_Hz.size() < 2) throw Error(ErrorKind::settings, "an FRF needs at least 2 frequencies");
  const Teeth cut{flutes, Kt_N_per_mm2};
  const ChatterSweep all = chatter_sweep(frf, alpha, flutes, Kt_N_per_mm2);
  const std::vector<ChatterSample>& sw = all.samples;
  Lobes out;
  out.ap_min_mm = all.ap_min_mm;
  out.ap_min_chatter_Hz = all.ap_min_chatter_Hz;
  const int last_k = max_lobes > 0 ? max_lobes - 1 : lobes_needed(sw, out.ap_min_mm, cut.flutes, rpm_min);
  for (int k = 0; k <= last_k; ++k) {
    // eps > 0: lobe k lies below 60 f / (N k); past rpm_min it and every later one are out of range.
    if (k > 0 && 60 * frf.frequency_Hz.back() / (cut.flutes * k) < rpm_min) break;
    add_lobe_curves(sw, k, cut, rpm_min, rpm_max, out.lobes);
  }
  return out;
}

ChatterSweep chatter_sweep(const Frf& frf, const Eigen::Matrix2cd& alpha, int flutes, double Kt_N_per_mm2) {
  if (flutes < 1 || !(Kt_N_per_mm2 > 0) || !std::isfinite(Kt_N_per_mm2))
    throw Error(ErrorKind::settings, "a cut needs at least one tooth and a cutting coefficient K_t > 0");
  if (frf.frequency_Hz.size() < 2) throw Error(ErrorKind::settings, "an FRF needs at least 2 frequencies");
  ChatterSweep out;
  out.flutes = flutes;
  for (const Sample& s : sweep(frf, alpha, {flutes, Kt_N_per_mm2})) {
    out.samples.push_back({s.f_Hz, s.root});
    for (const Root& r : s.root)
      if (r.ok && r.ap_mm < out.ap_min_mm) out.ap_min_mm = r.ap_mm, out.ap_min_chatter_Hz = s.f_Hz;
  }
  return out;
}

double ap_limit_at(const ChatterSweep& sw, double rpm) {
  // Lobe k passes speed n at chatter frequency f where eps + 2 pi k =
  // 2 pi 60 f / (N n): between two neighbouring samples of a branch whose
  // real lobe number k(f) = 60 f / (N n) - eps / (2 pi) straddles an integer,
  // a lobe crosses n; a_lim there is interpolated like the lobe's curve.
  double best = std::numeric_limits<double>::infinity();
  const double per_Hz = 60 / (sw.flutes * rpm);
  for (int b = 0; b < 2; ++b)
    for (std::size_t j = 1; j < sw.samples.size(); ++j) {
      const ChatterSample &p = sw.samples[j - 1], &q = sw.samples[j];
      const Root &rp = p.root[b], &rq = q.root[b];
      if (!rp.ok || !rq.ok) continue;
      const double kp = p.f_Hz * per_Hz - rp.eps_rad / (2 * kPi), kq = q.f_Hz * per_Hz - rq.eps_rad / (2 * kPi);
      const double lo = std::min(kp, kq), hi = std::max(kp, kq);
      for (double k = std::max(0.0, std::ceil(lo)); k <= hi; ++k) {
        const double t = hi > lo ? (k - kp) / (kq - kp) : 0;
        best = std::min(best, rp.ap_mm + t * (rq.ap_mm - rp.ap_mm));
      }
    }
  return std::isfinite(best) ? best : sw.ap_min_mm;
}

}  // namespace deflex::stability
