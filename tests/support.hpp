// Helpers shared by the tests: interpret a program given as text, run the CLI
// in-process, read files.
#pragma once
#include <stdlib.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include <limits>

#include "deflex/cli/command.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/gcode/program.hpp"
#include "deflex/interp/interpreter.hpp"
#include "deflex/profile/profile.hpp"

namespace deflex::test {

// A new folder of its own under the temporary folder (mkdtemp: no two tests,
// nor two runs at once, share one), removed with everything in it at the end.
struct TempDir {
  std::filesystem::path p;
  explicit TempDir(const std::string& what = "test") {
    std::string t = (std::filesystem::temp_directory_path() / ("deflex-" + what + "-XXXXXX")).string();
    if (!::mkdtemp(t.data())) throw std::runtime_error("mkdtemp failed: " + t);
    p = t;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(p, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string operator/(const std::string& name) const { return (p / name).string(); }
};

// DEFLEX_CHUNK_LINES for the scope of one run ("0": read whole).
struct PieceLines {
  explicit PieceLines(const std::string& n) { ::setenv("DEFLEX_CHUNK_LINES", n.c_str(), 1); }
  ~PieceLines() { ::unsetenv("DEFLEX_CHUNK_LINES"); }
  PieceLines(const PieceLines&) = delete;
  PieceLines& operator=(const PieceLines&) = delete;
};

struct Interpreted {
  std::vector<interp::Motion> motions;
  interp::Stats stats;
  std::string diagnostics;  // as printed
  int errors = 0;
  int warnings = 0;
};

struct Collect : interp::MotionSink {
  std::vector<interp::Motion>* out;
  void motion(const interp::Motion& m) override { out->push_back(m); }
};

inline Interpreted interpret_text(const std::string& text, const std::string& dialect = "fanuc",
                                  const profile::MachineProfile* machine = nullptr, bool block_delete = false,
                                  double cutter_radius_mm = 5.0) {
  gcode::Program prog(SourceText("t.nc", text));
  std::ostringstream err;
  Diagnostics d(&err, 0);
  interp::Options o;
  o.dialect = profile::load_dialect(dialect);
  o.machine = machine;
  o.block_delete_switch = block_delete;
  o.cutter_radius_mm = [cutter_radius_mm](int) { return std::optional<double>(cutter_radius_mm); };  // every D register
  Interpreted r;
  Collect c;
  c.out = &r.motions;
  r.stats = interp::interpret(prog, o, d, c);
  r.diagnostics = err.str();
  r.errors = d.errors();
  r.warnings = d.warnings();
  return r;
}

// A compensable G1 from a to b (mm) at `feed_mm_per_min`.
// `expected` within a fraction `rel` of itself. doctest::Approx(x).epsilon(e)
// is not that: it allows e * (1 + max(|a|, |x|)), so at the mm/N of a
// compliance (1e-3) it allows e in absolute terms, far more than x itself.
// (The scale: the least positive double, so that 0 is within any fraction of 0.)
inline doctest::Approx within(double expected, double rel) {
  return doctest::Approx(expected).epsilon(rel).scale(std::numeric_limits<double>::min());
}

inline interp::Motion linear_motion(interp::Vec3 a, interp::Vec3 b, double feed_mm_per_min = 1000) {
  interp::Motion m;
  m.kind = interp::MotionKind::linear;
  m.fixed = interp::Fixed::no;
  m.start_mm = a;
  m.end_mm = b;
  m.feed_mm_per_min = feed_mm_per_min;
  return m;
}

// Entry and exit immersion angles (rad) of a flat end mill of diameter D at
// radial depth a_e, feed along +X, angles from +Y' (the up-milling side) in the
// cutting sense: up milling [0, acos(1 - 2 a_e / D)], down milling
// [pi - acos(1 - 2 a_e / D), pi] (Altintas, Manufacturing Automation, 2nd ed.
// 2012, Sec. 2.3; Morelli 2021 Eq. 1); a_e >= D is a slot, [0, pi].
inline std::pair<double, double> textbook_immersion(double D_mm, double ae_mm, bool up_milling) {
  const double pi = std::numbers::pi;
  const double swept = ae_mm >= D_mm ? pi : std::acos(1 - 2 * ae_mm / D_mm);
  return up_milling ? std::pair{0.0, swept} : std::pair{pi - swept, pi};
}

struct CliResult {
  int rc;
  std::string out, err;
};

// Runs f, expects deflex::Error of kind `kind` (a doctest check), returns its
// message; "" (and a failed check) when nothing is thrown.
template <class F>
std::string error_of(F f, ErrorKind kind) {
  try {
    f();
  } catch (const Error& e) {
    CHECK(e.kind() == kind);
    return e.what();
  }
  FAIL_CHECK("no error thrown");
  return {};
}

inline CliResult run_cli(const std::vector<std::string>& args, const std::string& stdin_text = "") {
  std::istringstream in(stdin_text);
  std::ostringstream out, err;
  cli::Io io{{in, out, err}};
  int rc = cli::run(args, io);
  return {rc, out.str(), err.str()};
}

std::string read_file(const std::string& path);

// Runs a shell `script` in `dir` (build/deflex is DEFLEX_BINARY there): its
// exit code and what it wrote to stdout and stderr (a redirection in the
// script wins). For what only a process shows: file descriptors, the folder.
inline CliResult run_shell(const std::string& script, const std::string& dir) {
  const std::string out = dir + "/.run_shell.out", err = dir + "/.run_shell.err";
  const std::string cmd = "cd '" + dir + "' && { " + script + " ; } > '" + out + "' 2> '" + err + "'";
  const int status = std::system(cmd.c_str());
  CliResult r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_file(out), read_file(err)};
  std::remove(out.c_str());
  std::remove(err.c_str());
  return r;
}

inline std::string read_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

inline void write_file(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
}

// Two programs for diff whose every line is `G1X..Y..`: all skeletons are
// equal, so only positions can place the inserted block. B moves line 4 by
// 0.01 mm and inserts a split of the move to line 4 (a point on it) before it.
inline const char* const kDiffSplitA = "G21G90G0X0Y0Z0\nG1X1.F100\nG1X2.\nG1X3.\nG1X3.1\nG1X3.2\nG1X3.3\nG1X3.4\n";
inline const char* const kDiffSplitB =
    "G21G90G0X0Y0Z0\nG1X1.F100\nG1X2.\nG1 X2.5 Y0 Z0\nG1X3.Y0.01\nG1X3.1Y0\nG1X3.2\nG1X3.3\nG1X3.4\n";

// The holder and shank check's pocket (tests/*/test_collision.cpp). T1: D10
// flat, flutes 20 mm, stick-out 40 mm; T2 the same at 60 mm (the sample
// machine mill3's holder above them, nose diameter 32 mm).
inline const char* kPocketTools = R"(tools:
  T1: {type: flat, diameter_mm: 10, flutes: 4, flute_length_mm: 20, stickout_mm: 40, material: carbide}
  T2: {type: flat, diameter_mm: 10, flutes: 4, flute_length_mm: 20, stickout_mm: 60, material: carbide}
  T3: {type: flat, diameter_mm: 10, flutes: 4, flute_length_mm: 20, stickout_mm: 60, shank_diameter_mm: 12, material: carbide}
)";
// The pocket X40..60 Y40..60, 55.5 mm deep, as an earlier program: T2 at
// Z-55.5 over X45..55 Y45..55, 1 mm apart.
inline std::string pocket_roughing() {
  std::string p = "G21 G90 G17\nT2 M6\nS8000 M3\nG0 X45. Y45. Z5.\nG1 Z-55.5 F300\n";
  for (int y = 45; y <= 55; ++y) p += "G1 X45. Y" + std::to_string(y) + ". F300\nX55.\n";
  return p + "G0 Z5.\nM30\n";
}
// A pass 0.5 mm above the pocket's floor with T`tool`, across its middle:
// line 5 the plunge to Z-55, line 6 the cut.
inline std::string pocket_floor_pass(int tool) {
  return "G21 G90 G17\nT" + std::to_string(tool) + " M6\nS8000 M3\nG0 X45. Y50. Z5.\nG1 Z-55. F300\nX55.\nG0 Z5.\nM30\n";
}

// A copy of the file `source` as `name` in `dir` with the first `from`
// replaced by `to` (which must be there); its path.
inline std::string edited_copy(const TempDir& dir, const std::string& source, const std::string& name,
                               const std::string& from, const std::string& to) {
  std::string text = read_file(source);
  REQUIRE_MESSAGE(text.find(from) != std::string::npos, from);
  text.replace(text.find(from), from.size(), to);
  write_file(dir / name, text);
  return dir / name;
}

// A CSV file with a header row (points.csv of --report): cells by column name.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  // The number in `column` of row i (throws std::out_of_range on an unknown column).
  double num(std::size_t i, const std::string& column) const { return std::stod(rows.at(i).at(col(column))); }
  // The index of `column` (throws std::out_of_range on an unknown one).
  std::size_t col(const std::string& column) const {
    for (std::size_t c = 0; c < header.size(); ++c)
      if (header[c] == column) return c;
    throw std::out_of_range("no column " + column);
  }
};

inline std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> cells;
  std::istringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

inline Csv read_csv(const std::string& path) {
  Csv t;
  std::istringstream in(read_file(path));
  std::string line;
  if (std::getline(in, line)) t.header = split_commas(line);
  while (std::getline(in, line)) t.rows.push_back(split_commas(line));
  return t;
}

// What every row of a points.csv must show whatever the numbers, so a wrong
// physics change fails even where a figure is pinned as a regression snapshot:
// the deflection has a positive component along the force (a compliance is
// positive definite: F.C.F > 0); beyond `tolerance_mm`, the error as written
// is an undercut (positive) where the tool bends out of the material (d.n > 0)
// and an overcut where it bends in; the mirror's offset (along n) has the
// error's opposite sign, moving the point into the material for an undercut.
inline void check_deflection_physics(const Csv& pts, double tolerance_mm) {
  REQUIRE(!pts.rows.empty());
  for (std::size_t i = 0; i < pts.rows.size(); ++i) {
    CAPTURE(pts.num(i, "line"));
    CAPTURE(pts.num(i, "x_mm"));
    const double F[3] = {pts.num(i, "Fx_N"), pts.num(i, "Fy_N"), pts.num(i, "Fz_N")};
    const double d[3] = {pts.num(i, "dx_mm"), pts.num(i, "dy_mm"), pts.num(i, "dz_mm")};
    const double n[3] = {pts.num(i, "nx"), pts.num(i, "ny"), pts.num(i, "nz")};
    const double F_dot_d = F[0] * d[0] + F[1] * d[1] + F[2] * d[2], d_dot_n = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
    if (std::hypot(F[0], F[1], F[2]) > 1) CHECK(F_dot_d > 0);
    const double e = pts.num(i, "surface_error_as_written_mm");
    if (std::fabs(e) > tolerance_mm) CHECK((e > 0) == (d_dot_n > 0));
    CHECK(pts.num(i, "offset_mm") * e <= 0);
  }
}

}  // namespace deflex::test
