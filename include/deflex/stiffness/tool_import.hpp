// Tool libraries from what a shop has: a Fusion 360 / HSM
// tool library exported as JSON, and a LinuxCNC tool table (.tbl), converted to
// deflex's tool library YAML. `--tool-file` reads both directly (through this
// conversion, so one reader checks every library); `deflex tools import`
// writes the YAML for a person to review and complete.
//
// Fusion 360 (JSON export, {"data": [tool, ...]}): per tool `type` ("flat end
// mill", "ball end mill", "bull nose end mill"; any other type is reported by
// name and skipped), `unit` ("millimeters" or "inches"), `description`,
// `geometry` {DC diameter, RE corner radius, NOF flutes, LCF flute length, LB
// length below the holder = stick-out, OAL overall length, SFDM shank diameter,
// BMC body material}, `post-process.number` the T number. A tool without a T
// number, or with one an earlier tool of the file has, is skipped and said.
// LinuxCNC (`T1 P1 D10.0 Z+0.0 ;comment`, one tool per line): T and D; the
// other words (P, X..W offsets, I J Q) are read and left out.
//
// What a library does not give (helix angle, flute length or stick-out of a
// LinuxCNC table, the type of a LinuxCNC tool) takes a stated default, written
// as a YAML comment on its line, so the imported file says what is assumed.
#pragma once
#include <string>
#include <vector>

namespace deflex::stiffness {

struct ImportedLibrary {
  std::string format;                // "Fusion 360 JSON" or "LinuxCNC tool table"
  std::string yaml;                  // a deflex tool library, with the defaults commented
  int tools = 0;                     // tools written
  std::vector<std::string> skipped;  // one line each: which tool, why
};

// True for a path deflex reads through this conversion (.json, .tbl).
bool is_foreign_tool_library(const std::string& path);

// Reads and converts. Throws Error(ErrorKind::io) when unreadable and
// Error(ErrorKind::config, "file:line:col: error: ...") when malformed (JSON syntax
// errors at their position; a bad value in a Fusion tool named by its index,
// number and description).
ImportedLibrary import_tool_library(const std::string& path);
ImportedLibrary import_fusion_json(const std::string& text, const std::string& file);
ImportedLibrary import_linuxcnc_tbl(const std::string& text, const std::string& file);

}  // namespace deflex::stiffness
