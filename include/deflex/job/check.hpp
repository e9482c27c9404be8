// `deflex check` as a call: a program read and interpreted as the control
// would, its diagnostics, the machine's travel, with a part model the
// gouge check (the programmed cutter against the design surface), and with a
// stock the holder and shank check (the program swept through the stock, the
// earlier programs' rest stock included, by the simulation's sweep alone: no
// engagement, no forces; the same errors simulate and compensate give).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/gcode/reader.hpp"
#include "deflex/interp/decimal.hpp"
#include "deflex/interp/interpreter.hpp"
#include "deflex/interp/shape.hpp"
#include "deflex/job/io.hpp"
#include "deflex/job/settings.hpp"
#include "deflex/job/setup.hpp"

namespace deflex::job {

struct CheckSettings {
  std::string program;   // a file, "-" for the input stream
  ReadSettings read;
  PartSettings part;     // the gouge check where a part model is given (or config part)
  std::string tool_file; // the tool library of the gouge check and of G41/G42 radii
  std::string tool;      // the gouge check's tool for every cut ("": the program's T words)
  bool keep_diagnostics = false;  // CheckResult::diagnostics (a text run may report millions)
  // The holder and shank check where a stock is given (as compensate takes
  // it: box, solid, .zmap or auto; "": none, the check as before), with the
  // earlier operations swept into it first.
  std::string stock;
  std::vector<EarlierOp> stock_from;
  double cell_mm = 0.05;         // its Z-map cell
  double cl_spacing_mm = 0.5;    // the samples along a move, as simulate's
  int threads = 0;               // 0: all cores
};

struct CheckResult {
  std::string name;      // the program's
  std::string dialect, machine;
  interp::Stats stats;
  int errors = 0, warnings = 0;
  std::vector<Diagnostic> diagnostics;  // with keep_diagnostics
};

// Every diagnostic goes to io.err as it is found; the result counts them.
CheckResult check(const CheckSettings& s, Io& io);

// The checks of a program's text (its shape, its decimal points): a pass of
// their own over the pieces, so their findings come first, as on the whole
// file; `also` (may be null) sees each piece in the same pass.
void check_text(gcode::ProgramPasses& src, const Setup& s, Diagnostics& diags,
                const std::function<void(const gcode::Program&)>& also = {});

// check_text() in two steps: read() the pieces (no message yet; it may run
// on a thread of its own), then finish() reports what the checks found.
class TextChecks {
 public:
  explicit TextChecks(const Setup& s) : s_(s), dec_(s.dialect) {}
  void read(gcode::ProgramPasses& src, const std::function<void(const gcode::Program&)>& also = {});
  void finish(Diagnostics& diags);

 private:
  const Setup& s_;
  interp::ShapeCheck shape_;
  interp::DecimalCheck dec_;
};

// The gouge check's gap: the one given, else config part_gap_mm, else 0.02 mm;
// a settings Error when it is not > 0.
double part_gap_mm(const PartSettings& p, const profile::Config& cfg);

}  // namespace deflex::job
