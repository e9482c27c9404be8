// The command line's names for the settings the library's messages name
// (diag/settings.hpp): each keyword as the option that gives it.
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "deflex/cli/command.hpp"

namespace deflex::cli {

std::string flag_of(std::string_view keyword) {
  static constexpr std::pair<std::string_view, std::string_view> kFlags[] = {
      {"program", "FILE"}, {"output", "-o"}, {"reference", "--reference"}, {"report_dir", "--report"},
      {"dialect", "--dialect"}, {"machine", "--machine"}, {"config", "--config"}, {"max_errors", "--max-errors"},
      {"block_delete", "--block-delete"}, {"strict", "--strict"}, {"max_blocks", "--max-blocks"},
      {"material", "--material"}, {"material_file", "--material-file"}, {"kt_N_per_mm2", "--kt"},
      {"kr_N_per_mm2", "--kr"}, {"ka_N_per_mm2", "--ka"}, {"kte_N_per_mm", "--kte"}, {"kre_N_per_mm", "--kre"},
      {"kae_N_per_mm", "--kae"}, {"part", "--part"}, {"part_gap_mm", "--part-gap"}, {"fixture", "--fixture"},
      {"workpiece_mesh_mm", "--workpiece-mesh"}, {"workpiece_spacing_mm", "--workpiece-spacing"}, {"workpiece_stages", "--workpiece-stages"}, {"tool_file", "--tool-file"},
      {"tool", "--tool"}, {"stock", "--stock"}, {"stock_from", "--stock-from"}, {"tolerance_mm", "--tolerance"},
      {"gain", "--gain"}, {"feed_limit_N", "--feed-limit"}, {"spindle_rpm", "--spindle"},
      {"feed_mm_per_min", "--feed"}, {"cell_mm", "--cell-mm"}, {"cl_spacing_mm", "--cl-spacing"},
      {"max_iterations", "--max-iterations"}, {"threads", "--threads"}, {"tool_only", "--tool-only"},
      {"expand_subprograms", "--expand-subprograms"}, {"measured", "--measured"}, {"probe_program", "--probe-program"},
      {"measured_reach_mm", "--measured-reach"}, {"rough_tool", "--rough-tool"}, {"pair_mm", "--pair-mm"},
      {"mesh_tolerance_mm", "--mesh-tolerance"}, {"fz_mm", "--fz"}, {"plan", "--plan"},
      {"ball_diameter_mm", "--ball-diameter"}, {"probe_length_mm", "--probe-length"}, {"probe_tool", "--probe-tool"},
      {"step_mm", "--step"}, {"approach_mm", "--approach"}, {"probe_feed_mm_per_min", "--probe-feed"},
      {"ae_mm", "--ae"}, {"ap_mm", "--ap"}};
  for (const auto& [k, flag] : kFlags)
    if (k == keyword) return std::string(flag);
  // A keyword added to the library's vocabulary without a flag here: named
  // as the keyword (tests/cli/test_flags.cpp fails on it).
  return std::string(keyword);
}

}  // namespace deflex::cli
