// The test cut the plan tests share: T1 of samples/tools.yaml (flat D10,
// 4 flutes, helix 30, 22 mm of flutes) on a 200 x 200 x 30 mm block.
#pragma once
#include "deflex/plan/testcut.hpp"

namespace deflex::test {

inline plan::TestCutter flat10() {
  plan::TestCutter t;
  t.id = "T1";
  t.diameter_mm = 10;
  t.flutes = 4;
  t.helix_deg = 30;
  t.flute_length_mm = 22;
  return t;
}

inline const plan::TestBlock kTestBlock{0, 0, -30, 200, 200, 0};

}  // namespace deflex::test
