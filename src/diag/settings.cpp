#include "deflex/diag/settings.hpp"

#include <algorithm>
#include <array>

namespace deflex {
namespace {

constexpr std::array<std::string_view, 56> kKeywords = {
    // The job's settings (include/deflex/job/settings.hpp), as Python names them.
    "program", "output", "reference", "report_dir", "dialect", "machine", "config", "max_errors", "block_delete",
    "strict", "max_blocks", "material", "material_file", "kt_N_per_mm2", "kr_N_per_mm2", "ka_N_per_mm2",
    "kte_N_per_mm", "kre_N_per_mm", "kae_N_per_mm", "part", "part_gap_mm", "fixture", "workpiece_mesh_mm",
    "workpiece_spacing_mm", "workpiece_stages", "tool_file", "tool", "stock",
    "stock_from", "tolerance_mm", "gain", "feed_limit_N", "spindle_rpm", "feed_mm_per_min", "cell_mm",
    "cl_spacing_mm", "max_iterations", "threads", "tool_only", "expand_subprograms", "measured", "probe_program",
    "measured_reach_mm",
    // Settings of the other calls: rough and the stock file (job/stock.hpp), diff (job/diff.hpp).
    "rough_tool", "pair_mm", "mesh_tolerance_mm",
    // The test cut and its probing (job/testcut.hpp).
    "fz_mm", "plan", "ball_diameter_mm", "probe_length_mm", "probe_tool", "step_mm", "approach_mm",
    "probe_feed_mm_per_min", "ae_mm", "ap_mm"};

// The keyword of the {keyword} at text[at] (at: the '{'), or "" when there is none.
std::string_view keyword_at(std::string_view text, std::size_t at) {
  const std::size_t close = text.find('}', at + 1);
  if (close == std::string_view::npos) return {};
  const std::string_view k = text.substr(at + 1, close - at - 1);
  return std::find(kKeywords.begin(), kKeywords.end(), k) != kKeywords.end() ? k : std::string_view{};
}

}  // namespace

std::span<const std::string_view> setting_keywords() { return kKeywords; }

std::string name_settings(std::string_view text, const SettingNames& names) {
  std::string out;
  out.reserve(text.size());
  std::size_t from = 0;
  for (std::size_t at = text.find('{'); at != std::string_view::npos; at = text.find('{', at + 1)) {
    const std::string_view k = keyword_at(text, at);
    if (k.empty()) continue;
    out.append(text.substr(from, at - from));
    out += names ? names(k) : std::string(k);
    from = at + k.size() + 2;
  }
  out.append(text.substr(from));
  return out;
}

std::vector<std::string> settings_named(std::string_view text) {
  std::vector<std::string> found;
  for (std::size_t at = text.find('{'); at != std::string_view::npos; at = text.find('{', at + 1)) {
    const std::string k(keyword_at(text, at));
    if (!k.empty() && std::find(found.begin(), found.end(), k) == found.end()) found.push_back(k);
  }
  return found;
}

}  // namespace deflex
