// Cutting-force coefficients of a tool/material pair.
#pragma once
#include <string>

namespace deflex::force {

// Linear-edge mechanistic model (Altintas 2012 ch. 2; Lee & Altintas 1996):
//   dF_t = K_tc h db + K_te dS,  dF_r = K_rc h db + K_re dS,  dF_a = K_ac h db + K_ae dS.
// Cutting coefficients in N/mm², edge coefficients in N/mm. Positive K_ac pulls a
// right-hand helical cutter down (-Z) on the cylinder (Engin & Altintas 2001 transform).
struct Coefficients {
  double Ktc_N_per_mm2 = 0, Krc_N_per_mm2 = 0, Kac_N_per_mm2 = 0;
  double Kte_N_per_mm = 0, Kre_N_per_mm = 0, Kae_N_per_mm = 0;
};

// How a coefficient set was identified; both forms run through the same model.
enum class ModelForm {
  mechanistic,  // K_tc..K_ae (Altintas)
  // Smaoui 2011 Eq. 2-5: dF_{R,T,A} = K_{R,T,A} f_z sin(beta) dz with the
  // transform of Eq. 5 (that of Engin & Altintas 2001, beta = phi, eta = kappa).
  // Since h db = f_z sin(phi) sin(kappa) dz / sin(kappa) = f_z sin(phi) dz, it is
  // the mechanistic model with K_tc = K_T, K_rc = K_R, K_ac = K_A and no edge terms.
  smaoui_krta
};

const char* to_string(ModelForm f);

// Every coefficient times `factor` (the forces scale with them).
Coefficients scaled(const Coefficients& k, double factor);

// Smaoui 2011 Eq. 2 coefficients as a mechanistic set (see ModelForm::smaoui_krta).
Coefficients from_smaoui(double KT_N_per_mm2, double KR_N_per_mm2, double KA_N_per_mm2);

}  // namespace deflex::force
