// The slope patches of a ball end mill's test cut (testcut_slope.cpp), for
// plan/testcut.cpp only.
#pragma once
#include "deflex/plan/testcut.hpp"

namespace deflex::plan {

// The smallest block (X, Y, Z lengths, mm) the patches of `o.slopes_deg` fit.
Vec3 smallest_slope_block_mm(const TestCutter& t, const TestCutOptions& o);
// Throws Error(settings) on inclinations out of range or depths given.
void check_slopes(const TestCutter& t, const TestCutOptions& o);
// One patch per inclination along the front face, from X0.
void add_slopes(TestCutPlan& p, const TestBlock& b, const TestCutter& t, const TestCutOptions& o);

}  // namespace deflex::plan
