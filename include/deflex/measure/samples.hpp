// Measurements of a machined part as the measuring device gives them: points in
// the work frame, mm. Four forms: a CMM's CSV export, LinuxCNC's probe log, the
// DPRNT output of a Fanuc control, a scanner's point cloud (PLY or STL).
//
// Every reader is strict: a malformed file is an Error(ErrorKind::input) whose
// text reads like a compiler's, `file:line:col: error: message`, then the
// source line and a caret under the column (binary files: `file: error: vertex
// 12 at byte 345: ...`). Nothing is guessed: no NaN, no infinity, no missing or
// extra field, no unit that is not millimetres passes.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace deflex::measure {

// One measured sample as its file gives it.
struct Sample {
  Eigen::Vector3d p_mm = Eigen::Vector3d::Zero();  // work frame, mm
  int id = -1;             // the probe point's id where the format carries one (>= 1), else -1
  std::uint32_t line = 0;  // 1-based line in its file; 0: none (a binary file)
};

// CSV of points on the machined surface, work frame, mm, stylus radius already
// removed (as CMM software exports them). Comment lines ('#' first) and blank
// lines are skipped. The first other line is the header: columns x_mm, y_mm,
// z_mm in any order (names compared without case), any other columns ignored,
// an optional `id` column of positive integers (each once). A header in inches
// (x_in) or without a unit (x) is an error that says so: a unit slip would
// otherwise pass as a 25.4x error. At least one data row.
std::vector<Sample> read_points_csv(const std::string& text, const std::string& file);

// LinuxCNC's probe log: what a program writes between (PROBEOPEN file) and
// (PROBECLOSE), one line per straight probe, nine numbers X Y Z A B C U V W
// (src/measure/probe_log.cpp says where the format comes from). The position is
// in the program's units (G20: inches) and in the coordinate system in effect
// at the probe, tool length offset removed. Samples in probe order, no ids.
std::vector<Sample> read_linuxcnc_probe_log(const std::string& text, const std::string& file);

// What a Fanuc control writes for deflex's probe program, whose DPRNT per point
//   DPRNT[PT12*X#5061[44]*Y#5062[44]*Z#5063[44]]
// a line "PT12 X  12.3450 Y  -5.0000 Z  -2.2500": blanks and leading zeros may
// pad the numbers (src/measure/probe_log.cpp). Lines holding only '%' (POPEN
// and PCLOS write them) and blank lines are skipped. Each sample gets the id
// after PT; an id given twice is an error.
std::vector<Sample> read_dprnt(const std::string& text, const std::string& file);

// A scanner's point cloud, mm, by extension (any case): .ply (ascii,
// binary_little_endian, binary_big_endian; the vertex element's x, y, z of any
// PLY number type, every other property and element read past) or .stl (ascii
// or binary: the distinct corners of its triangles, by stock::read_stl).
// Samples have no id; a binary file's have no line.
std::vector<Sample> read_point_cloud(const std::string& path);

// A PLY file's bytes (read_point_cloud's .ply reader). Binary errors name the
// element by its index counting from 0, as a PLY face's vertex indices do.
std::vector<Sample> parse_ply(const std::string& bytes, const std::string& file);

}  // namespace deflex::measure
