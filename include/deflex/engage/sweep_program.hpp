// The stock left by earlier operations: their motions swept
// into the Z-map in order, geometry only (no engagement, no forces), at the
// speed of the sweep kernels. Rapids sweep too: a rapid through material
// removes it on the machine as well (and the plausibility checks of that
// program's own run would have said so).
#pragma once
#include <functional>
#include <vector>

#include "deflex/engage/path.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/stock/tool.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::engage {

// Sweeps every motion through `z` with the tool `tool_of` gives it (arcs as
// chords within o.chord_tol_mm). Returns the volume removed, mm^3.
double sweep_motions(stock::ZMap& z, const std::vector<interp::Motion>& motions,
                     const std::function<stock::ToolProfile(const interp::Motion&)>& tool_of, const PathOptions& o);

}  // namespace deflex::engage
