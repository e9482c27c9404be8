#include "deflex/force/morelli.hpp"

#include <cmath>
#include <numbers>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::force {

namespace {
constexpr double pi = std::numbers::pi;
}

MorelliAngles morelli_angles(const MorelliInput& in) {
  if (!(in.diameter_mm > 0) || in.flutes < 1 || !(in.ar_mm > 0) || in.ar_mm > in.diameter_mm ||
      !(in.ap_mm > 0) || !(in.helix_deg > 0 && in.helix_deg < 90) || !(in.Krc_N_per_mm2 > 0) ||
      !(in.Ktc_N_per_mm2 > 0))
    throw Error(ErrorKind::settings,
                "shape code: needs D > 0, 0 < a_r <= D, a_p > 0, 0 < helix < 90 deg, K_tc, K_rc > 0");
  MorelliAngles a;
  const double D = in.diameter_mm;
  a.alpha_en = std::acos(1 - 2 * in.ar_mm / D);                  // Eq. 1
  a.k_b = 2 * std::tan(in.helix_deg * pi / 180) / D;             // Eq. 3
  a.alpha_sw = a.k_b * in.ap_mm;                                 // Eq. 2
  a.phi_z = 2 * pi / in.flutes;
  a.phi_out = pi;
  // Eq. 6 as printed lacks the arctangent; the peak of F_y(theta) =
  // integral over [theta - alpha_sw, theta] of (K_tc sin^2 - K_rc sin cos) is where
  // both ends carry equal load, which gives
  // phi_max = pi + alpha_sw / 2 - atan((sqrt(K_tc^2 + K_rc^2) + K_tc) / K_rc).
  const double Kt = in.Ktc_N_per_mm2, Kr = in.Krc_N_per_mm2;
  a.phi_max = pi + a.alpha_sw / 2 - std::atan((std::hypot(Kt, Kr) + Kt) / Kr);
  a.alpha_enc = a.alpha_sw + a.phi_out - a.phi_max;
  a.ap_c = a.alpha_en / a.k_b;
  // Eq. 4; beyond a half turn the whole width is sub-critical.
  a.ar_c = a.alpha_enc >= pi ? D : D / 2 * (1 - std::cos(a.alpha_enc));
  return a;
}

int morelli_type(const MorelliInput& in, const MorelliAngles& a) {
  if (in.ar_mm >= a.ar_c) return 3;
  return in.ap_mm < a.ap_c ? 1 : 2;
}

char morelli_overlap(int type, const MorelliAngles& a, int i) {
  const double ip = i * a.phi_z;
  const double en = a.alpha_en, sw = a.alpha_sw;
  if (en + sw < ip) return '\0';  // flute i starts after flute 1 has left the cut
  switch (type) {
    case 1:  // Table 1, Type I (alpha_sw < alpha_en)
      if (en < ip) return 'L';
      return sw < ip ? 'M' : 'H';
    case 2:  // Table 1, Type II
      if (sw < ip) return 'L';
      if (sw < ip + en) return en < ip ? 'M' : 'H';
      return en < ip ? 'm' : 'h';
    default: {  // Table 1, Type III
      // The table leaves alpha_enc < i phi_z with alpha_sw + alpha_en - alpha_enc >=
      // i phi_z open; flute i then starts after the peak of flute 1: we call it L.
      if (a.alpha_enc < ip) return 'L';
      return a.alpha_sw + (en - a.alpha_enc) < ip ? 'M' : 'H';
    }
  }
}

std::string morelli_shape_code(const MorelliInput& in) {
  const MorelliAngles a = morelli_angles(in);
  const int type = morelli_type(in, a);
  std::string code(static_cast<std::size_t>(type), 'I');
  for (int i = 1; i < in.flutes; ++i) {
    const char c = morelli_overlap(type, a, i);
    if (c == '\0') break;
    code += c;
  }
  return code;
}

std::vector<MorelliKeyPoint> morelli_key_points(const MorelliInput& in) {
  const MorelliAngles a = morelli_angles(in);
  const int type = morelli_type(in, a);
  const double kb = a.k_b, en = a.alpha_en, sw = a.alpha_sw, ap = in.ap_mm;
  std::vector<MorelliKeyPoint> out;
  auto put = [&](std::string name, int i, double z) {
    out.push_back({std::move(name) + "^" + std::to_string(i), z});
  };
  const double z3 = ap - en / kb;  // Table 2, Type II
  if (type == 2) out.push_back({"z_3", z3});
  for (int i = 1; i < in.flutes; ++i) {
    const char c = morelli_overlap(type, a, i);
    if (c == '\0') break;
    const double ip = i * a.phi_z;
    const double zL = (ip - en) / kb, zM = (sw + ip - en) / kb;  // Type I
    if (type == 1) {
      if (c == 'L') put("z_L", i, zL);
      else put("z_M", i, zM);
    } else if (type == 2) {
      const double zMi = ap - ip / kb, zH = z3 + ip / kb, zm = ip / kb, z2m = z3 - ip / kb;
      switch (c) {
        case 'L': put("z_L", i, zL); break;
        case 'M': put("z_L", i, zL); put("z_M", i, zMi); break;
        case 'H': put("z_H", i, zH); put("z_m", i, zm); break;
        case 'm': put("z_L", i, zL); put("z_m", i, zm); put("z_M", i, zMi); put("z_2m", i, z2m); break;
        case 'h': put("z_m", i, zm); put("z_H", i, zH); put("z_2m", i, z2m); break;
      }
    } else {
      put("z_2L", i, (ip + sw - en) / kb);
      if (c == 'L') put("z_L", i, zL);
      else put("z_max", i, (ip + sw - a.alpha_enc) / kb);
    }
  }
  return out;
}

}  // namespace deflex::force
