// The machine's travel: every motion of the tool tip (arcs by their extent),
// in machine coordinates (work offsets from the profile; tool length not
// included), against the machine profile's limits.
#pragma once
#include "deflex/diag/diagnostics.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/profile/profile.hpp"

namespace deflex::interp {

// Reports an error at the motion's line for each axis that leaves the travel
// (nothing when the profile sets no travel). Returns whether it stayed inside.
bool check_travel(const Motion& m, const profile::Travel& t, const SourceText& src, Diagnostics& d);

}  // namespace deflex::interp
