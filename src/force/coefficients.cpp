#include "deflex/force/coefficients.hpp"

namespace deflex::force {

const char* to_string(ModelForm f) {
  switch (f) {
    case ModelForm::mechanistic: return "mechanistic";
    case ModelForm::smaoui_krta: return "smaoui_krta";
  }
  return "?";
}

Coefficients from_smaoui(double KT_N_per_mm2, double KR_N_per_mm2, double KA_N_per_mm2) {
  Coefficients k;
  k.Ktc_N_per_mm2 = KT_N_per_mm2;
  k.Krc_N_per_mm2 = KR_N_per_mm2;
  k.Kac_N_per_mm2 = KA_N_per_mm2;
  return k;
}

Coefficients scaled(const Coefficients& k, double f) {
  return {k.Ktc_N_per_mm2 * f, k.Krc_N_per_mm2 * f, k.Kac_N_per_mm2 * f,
          k.Kte_N_per_mm * f,  k.Kre_N_per_mm * f,  k.Kae_N_per_mm * f};
}

}  // namespace deflex::force
