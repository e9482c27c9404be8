// Control dialects (postproc/*.yaml), machine profiles (samples/machines/*.yaml)
// and config.yaml. Every YAML error is a deflex::Error(ErrorKind::config) whose text
// starts with `file:line:col: error:`.
#pragma once
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "deflex/profile/axis_limits.hpp"
#include "deflex/profile/spindle.hpp"
#include "deflex/profile/document.hpp"

namespace deflex::profile {

enum class DecimalRule { least_input_increment, calculator };
enum class CommentStyle { paren, semicolon };
// N words of inserted blocks: none; increment (the free numbers of the gap,
// none where there is no room); required (refuse where there is no room).
enum class NPolicy { none, increment, required };
enum class ExtendedOffsets { none, g54_1, g154, g59_x };

// How a control reads numbers and how deflex writes blocks for it.
struct Dialect {
  std::string name;
  DecimalRule decimal_rule = DecimalRule::least_input_increment;
  double lii_mm = 0.001;     // least input increment in G21
  double lii_inch = 0.0001;  // in G20 (inch)
  int decimals_mm = 4;
  int decimals_inch = 5;
  bool trailing_zeros = false;
  bool leading_zero = true;
  int max_line_length = 0;  // 0: no limit
  NPolicy n_policy = NPolicy::none;
  CommentStyle comment_style = CommentStyle::paren;
  double arc_radius_tolerance_mm = 0.01;
  char cycle_repeat_word = 'K';
  double peck_retract_mm = 1.0;
  std::string fine_boring_shift;  // "+X", "-Y", ... or empty: G76/G87 refused
  bool cycle_positions_before_raise = true;
  ExtendedOffsets extended_offsets = ExtendedOffsets::g54_1;
  // G41/G42 (interp/cutter_comp.hpp): an outside corner goes round an arc of
  // the tool radius (LinuxCNC) or to the intersection of the offset elements
  // (Fanuc cutter compensation C); the start-up move offsets its own line
  // (LinuxCNC) or ends perpendicular to the next move (Fanuc type A start-up).
  enum class CompCorner { arc, intersection } comp_corner = CompCorner::intersection;
  enum class CompStartup { offset_line, perpendicular_next } comp_startup = CompStartup::perpendicular_next;
};

// Names of the built-in dialects (postproc/*.yaml compiled in).
std::vector<std::string> dialect_names();
// A built-in dialect by name, or a dialect file by path (contains '/' or ends .yaml).
Dialect load_dialect(const std::string& name_or_path);

// Travel limits of the tool tip in machine coordinates, mm.
struct Travel {
  std::array<double, 3> min_mm{-1e300, -1e300, -1e300};
  std::array<double, 3> max_mm{1e300, 1e300, 1e300};
  bool set = false;
};

struct MachineProfile {
  std::string name;
  std::string file;  // where it was read from
  std::string dialect = "fanuc";
  Travel travel;
  // Work offsets (machine coordinates of each work zero), mm. Keys: "G54".."G59",
  // "G54.1P1".. — absent ones are zero.
  std::map<std::string, std::array<double, 3>> work_offsets_mm;
  // G28/G30 reference points in machine coordinates, mm; 1 = G28.
  std::map<int, std::array<double, 3>> reference_points_mm;
  double max_offset_mm = 0.1;  // largest compensation offset
  // Multiplies the material's force coefficients on this machine (what a fit
  // to a measured cut found: edge preparation, wear and the machine's own
  // dynamics make a shop's forces differ from the table's; `deflex fit`).
  double force_scale = 1.0;
  // G41/G42 radius registers (tool_offsets: in the profile), by D number:
  // the radius (geometry) and its wear, mm; the control offsets by their sum.
  struct ToolOffset { double radius_mm = 0, wear_mm = 0; };
  std::map<int, ToolOffset> tool_offsets;
  AxisLimits axis_limits;      // for the machining time (defaults when the section is absent)
  SpindleRating spindle;       // power and torque against speed (set: false when the section is absent)
  yaml::Document root;         // the whole document (stiffness, holder ... sections)
};

// A machine profile by path, or by name (profile/search.hpp: find_machine).
MachineProfile load_machine(const std::string& name_or_path);

struct Config {
  std::string file;
  std::string machine;      // default machine profile name
  std::string dialect;      // overrides the machine's dialect when set
  int max_errors = 20;
  yaml::Document root;
};

// The config file `path` (--config), else the first found in the search order
// (profile/search.hpp: find_config), else the built-in defaults.
Config load_config(const std::string& path = "");

}  // namespace deflex::profile
