// `deflex path` and `deflex rewrite` as calls: a program read (in pieces where
// it is long), checked and interpreted as the control would; then its motions
// handed to the caller, or its bytes written back through deflex's writer.
#pragma once
#include <cstddef>
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
  // With a HoldingSink: 1, the text checks run before the interpretation;
  // otherwise beside it, on a second thread, with up to `held_messages` of the
  // interpretation's messages held until the checks' have come out.
  int threads = 0;
  std::size_t held_messages = 4096;
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

// A sink that holds what it makes of the motions (the text of `deflex path`)
// until it is told whether they stand.
class HoldingSink : public interp::MotionSink {
 public:
  // Once, at the end: true, the program has no error and what was held goes
  // out; false, it is dropped.
  virtual void finish(bool no_error) = 0;
};

// The same in one pass: the motions go to `sink` as they are interpreted and
// the pass reports the diagnostics; then sink.finish(handed). Interpreting
// twice (lexing every line again) cost 30% of `deflex path` on the 1M-block
// raster; the sink holding its text costs a copy of it at most. The messages,
// counts and motions are those of the two passes (and with any s.threads).
PathResult path(const PathSettings& s, HoldingSink& sink, Io& io);

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
