// Helpers shared by the tests: interpret a program given as text, run the CLI
// in-process, read files.
#pragma once
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "deflex/cli/command.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/gcode/program.hpp"
#include "deflex/interp/interpreter.hpp"
#include "deflex/profile/profile.hpp"

namespace deflex::test {

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

inline CliResult run_cli(const std::vector<std::string>& args, const std::string& stdin_text = "") {
  std::istringstream in(stdin_text);
  std::ostringstream out, err;
  cli::Io io{in, out, err, false};
  int rc = cli::run(args, io);
  return {rc, out.str(), err.str()};
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

}  // namespace deflex::test
