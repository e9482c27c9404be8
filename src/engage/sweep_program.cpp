#include "deflex/engage/sweep_program.hpp"

#include "deflex/stock/sweep.hpp"

namespace deflex::engage {

double sweep_motions(stock::ZMap& z, const std::vector<interp::Motion>& motions,
                     const std::function<stock::ToolProfile(const interp::Motion&)>& tool_of, const PathOptions& o) {
  double removed = 0;
  for (const interp::Motion& m : motions) {
    const std::vector<Point3> v = motion_vertices(m, o);
    removed += stock::sweep_polyline(z, tool_of(m), v);
  }
  return removed;
}

}  // namespace deflex::engage
