// Force-shape classification of flat end mills in down-milling (Morelli et al.
// 2021; docs/physics.md): single-flute F_y shape Type I/II/III and the overlap degree
// of each following flute (L, M, H, m, h), e.g. "IIML"; and the key axial
// positions of the surface-generating force (Table 2).
#pragma once
#include <string>
#include <vector>

namespace deflex::force {

struct MorelliInput {
  double diameter_mm = 12;
  double helix_deg = 45;
  int flutes = 4;
  double ar_mm = 2.5;  // radial depth of cut
  double ap_mm = 12;   // axial depth of cut
  double Ktc_N_per_mm2 = 752.9;
  double Krc_N_per_mm2 = 200.5;
};

// The angles of Morelli 2021 §2.1-2.2 (rad; k_b in rad/mm; depths in mm).
struct MorelliAngles {
  double alpha_en = 0;   // Eq. 1: acos(1 - 2 a_r / D)
  double k_b = 0;        // Eq. 3: 2 tan(helix) / D
  double alpha_sw = 0;   // Eq. 2: k_b a_p
  double phi_z = 0;      // tooth pitch 2 pi / N
  double phi_out = 0;    // exit angle, pi in down-milling
  double phi_max = 0;    // Eq. 6: peak of F_y in a slot
  double alpha_enc = 0;  // alpha_sw + phi_out - phi_max
  double ap_c = 0;       // critical axial depth: alpha_sw(ap_c) = alpha_en
  double ar_c = 0;       // Eq. 4: critical radial depth
};
MorelliAngles morelli_angles(const MorelliInput& in);

// 1, 2 or 3 (Type I, II, III of §2.1).
int morelli_type(const MorelliInput& in, const MorelliAngles& a);

// Overlap letter of the i-th following flute (i >= 1) per Table 1, or '\0' when
// that flute is not in the cut (alpha_en + alpha_sw < i phi_z).
char morelli_overlap(int type, const MorelliAngles& a, int i);

// The whole code: "I"/"II"/"III" followed by one letter per following flute in
// the cut. Throws deflex::Error(ErrorKind::settings) on impossible input.
std::string morelli_shape_code(const MorelliInput& in);

// Key axial positions of Table 2 (mm above the tool tip, as printed: some may be
// negative or above a_p and then play no part in the surface error).
struct MorelliKeyPoint {
  std::string name;  // e.g. "z_L^1", "z_3"
  double z_mm = 0;
};
std::vector<MorelliKeyPoint> morelli_key_points(const MorelliInput& in);

}  // namespace deflex::force
