// A coefficient set with all six terms non-zero (arbitrary but realistic for
// aluminium): what the force tests use where the edge forces must show.
#pragma once
#include "deflex/force/coefficients.hpp"

namespace deflex::test {

inline force::Coefficients al_like() {
  force::Coefficients k;
  k.Ktc_N_per_mm2 = 800;
  k.Krc_N_per_mm2 = 300;
  k.Kac_N_per_mm2 = 150;
  k.Kte_N_per_mm = 25;
  k.Kre_N_per_mm = 30;
  k.Kae_N_per_mm = 2;
  return k;
}

}  // namespace deflex::test
