// `deflex path` and `deflex rewrite` as calls: a program read (in pieces where
// it is long), checked and interpreted as the control would; then its motions
// handed to the caller, or its bytes written back through deflex's writer.
#pragma once
#include <functional>
#include <string>

#include "deflex/interp/interpreter.hpp"
#include "deflex/job/io.hpp"
#include "deflex/job/settings.hpp"

namespace deflex::job {

struct PathSettings {
  std::string program;    // a file, "-" for the input stream
  ReadSettings read;
  std::string tool_file;  // the tool library of G41/G42 radii ("": config tool_file, else the installed one)
};

struct PathResult {
  std::string name;       // the program's
  interp::Stats stats;    // of the pass that checked it
  int errors = 0, warnings = 0;
  bool handed = false;    // the motions went to the sink (the program has no error)
};

// Every diagnostic goes to io.err. Only a program with no error (more
// executed blocks than read.max_blocks is one) hands its motions to `sink`,
// in order and all of them: a pass for the diagnostics comes first, so a
// program that fails halfway hands over nothing rather than a path cut off at
// the error.
PathResult path(const PathSettings& s, interp::MotionSink& sink, Io& io);

struct RewriteSettings {
  std::string program;   // a file, "-" for the input stream
  ReadSettings read;
  std::string output;    // a file written atomically; "" or "-": io.out
};

// The program written back with no change: the output is byte for byte the
// input. Its diagnostics go to io.err; a program with errors is not written
// (an input Error), and an output that is the input is refused before it is
// read (writer::check_output_path). `writing`, when given, is called once,
// just before the first byte goes to io.out (the CLI tells its signal handler
// that standard output is then cut short by a signal).
void rewrite(const RewriteSettings& s, Io& io, const std::function<void()>& writing = {});

}  // namespace deflex::job
