// The programmed contour under G41/G42 that makes the control's offset of
// it run through the compensated centre points (apply.cpp writes it).
// Private to src/compensate/.
#pragma once
#include <vector>

#include "deflex/compensate/compensate.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/profile/profile.hpp"

namespace deflex::compensate::detail {

// Per motion of `ms`: where its block's X/Y/Z go (meaningful where m.comp and
// not m.corner; elsewhere its end plus its offset).
std::vector<interp::Vec3> contour_targets(const std::vector<interp::Motion>& ms, const std::vector<V3>& offsets,
                                          const profile::Dialect& d);

}  // namespace deflex::compensate::detail
