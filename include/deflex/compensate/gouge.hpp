// The gouge check: the cutter as programmed against the part model (the design
// surface), without simulating the cut. At every CL sample of every cutting
// move the signed gap between the cutter's surface and the part is found
// (part::PartModel::contact, from below and from the four sides for flat and
// bull-nose ends; the smallest counts). A gap below -gap_mm cuts into the part
// (a gouge); a gap above gap_mm, within reach_mm, on a face of the part (not
// where the cutter rolls off an edge, as at the end of a pass) stands off it and
// leaves material. Farther than reach_mm the tool is not at the part surface
// (approach, a pass over air).
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "deflex/engage/path.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/part/part.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::compensate {

struct GapSide {
  std::size_t points = 0;            // CL samples beyond the gap
  std::vector<std::uint32_t> lines;  // their lines, each once, in program order
  double worst_mm = 0;               // largest |gap| among them
  bool worst_at_least = false;       // worst_mm bounds the depth from below (part::Contact::depth_at_least)
  std::uint32_t worst_line = 0;
};

struct PartGaps {
  std::size_t points = 0;  // CL samples checked
  GapSide overcut, standoff;
};

PartGaps part_gaps(const std::vector<interp::Motion>& motions, const part::PartModel& part,
                   const stiffness::ToolLibrary& tools, const std::function<std::string(const interp::Motion&)>& tool_of,
                   const engage::PathOptions& path, double gap_mm, double reach_mm);

// The gaps of a program checked in pieces: `piece`'s (the next motions in
// program order) added to `into`, as part_gaps gives them on the whole.
void merge(PartGaps& into, const PartGaps& piece);

}  // namespace deflex::compensate
