// Helpers shared by the tests: interpret a program given as text, run the CLI
// in-process, read files.
#pragma once
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
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

}  // namespace deflex::test
