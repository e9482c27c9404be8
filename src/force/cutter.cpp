#include "deflex/force/cutter.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::force {

void validate(const Cutter& c) {
  auto bad = [](const std::string& m) { throw Error(ErrorKind::config, "cutter: " + m); };
  if (!(c.diameter_mm > 0)) bad("diameter_mm must be > 0");
  if (c.flutes < 1 || c.flutes > 64) bad("flutes must be between 1 and 64");
  if (!(c.helix_deg >= 0 && c.helix_deg < 80)) bad("helix_deg must be in [0, 80)");
  if (!(c.flute_length_mm > 0)) bad("flute_length_mm must be > 0");
  if (c.type == stock::EndShape::bull &&
      !(c.corner_radius_mm > 0 && c.corner_radius_mm <= c.diameter_mm / 2))
    bad("a bull-nose corner_radius_mm must be in (0, D/2]");
}

double corner_radius_of(const Cutter& c) {
  return stock::corner_radius_mm(c.type, c.diameter_mm / 2, c.corner_radius_mm);
}

EdgePoint edge_point(const Cutter& c, double z_mm) {
  const double R0 = c.diameter_mm / 2;
  const double rc = corner_radius_of(c);
  EdgePoint p;
  // Constant-lead flute: Lee & Altintas 1996 Eq. 1 (ball), Engin & Altintas 2001
  // (other segments). The local helix angle on the corner follows from it.
  p.lag = z_mm * std::tan(c.helix_deg * std::numbers::pi / 180) / R0;
  if (z_mm >= rc) {  // cylinder
    p.r_mm = R0;
    p.sin_kappa = 1;
    p.cos_kappa = 0;
    return p;
  }
  // Corner arc of radius rc centred at (R0 - rc, rc): kappa is the angle between
  // the axis (pointing down) and the outward normal, 0 at the lowest point.
  const double zc = std::max(z_mm, 0.0);
  const double cos_k = (rc - zc) / rc;
  const double sin_k = std::sqrt(std::max(0.0, 1 - cos_k * cos_k));
  p.r_mm = R0 - rc + rc * sin_k;
  p.sin_kappa = sin_k;
  p.cos_kappa = cos_k;
  return p;
}

double CutterSlices::pitch() const { return 2 * std::numbers::pi / cutter.flutes; }

CutterSlices make_slices(const Cutter& c, double dz_mm, double length_mm) {
  validate(c);
  if (!(dz_mm > 0) || !(length_mm > 0))
    throw Error(ErrorKind::internal, "make_slices: dz and length must be > 0");
  const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(length_mm / dz_mm - 1e-9)));
  CutterSlices out;
  out.cutter = c;
  out.dz_mm = length_mm / static_cast<double>(n);
  out.slices.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double z = (static_cast<double>(i) + 0.5) * out.dz_mm;
    const EdgePoint p = edge_point(c, z);
    Slice s;
    s.z_mm = z;
    s.r_mm = p.r_mm;
    s.sin_kappa = p.sin_kappa;
    s.cos_kappa = p.cos_kappa;
    s.lag = p.lag;
    // Lee & Altintas 1996: chip width db = dz / sin(kappa), so h db = f sin(phi) dz,
    // which is also Smaoui 2011 Eq. 2 (f sin(beta) dz).
    s.width_mm = out.dz_mm / p.sin_kappa;
    // Edge forces act per unit of edge in contact. We take the profile length db
    // rather than the helical length (db / cos i) of Engin & Altintas 2001, so that
    // on the cylinder K_te is per mm of axial depth, exactly as the slot-test
    // calibration of Altintas 2012 ch. 2 measures it.
    s.edge_mm = s.width_mm;
    out.slices.push_back(s);
  }
  return out;
}

}  // namespace deflex::force
