// The job API: what `deflex compensate`, `simulate` and `compare` do, as
// calls. The command line, the Python bindings and the tests share it:
//
//   job::Settings s;                       // or job::apply_job_file(...)
//   s.program = "part.nc"; s.machine ...   // what the command line gives
//   job::Run run = job::open(s, job::Purpose::compensate, io);
//   job::CompensateResult r = job::compensate(run, out, io);
//
// Messages (notes, warnings, errors in compiler style) go to io.err as the
// run finds them; failures are thrown as deflex::Error (diag/diagnostics.hpp)
// with their kind. Nothing is written to the output, and no report file is
// left, unless the run ends well.
#pragma once
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "deflex/compensate/apply.hpp"
#include "deflex/compensate/plausibility.hpp"
#include "deflex/job/run.hpp"
#include "deflex/process/machining_time.hpp"
#include "deflex/report/compare.hpp"
#include "deflex/report/json.hpp"
#include "deflex/report/recorder.hpp"

namespace deflex::job {

// A run stopped by its observer (Observer::cancelled): nothing was written.
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("the run was cancelled; nothing written") {}
};

// What a caller sees of a run while it goes. progress() and cancelled() are
// called from the thread that called simulate() or compensate(); row() one
// call at a time, in program order, possibly from a worker thread.
class Observer {
 public:
  virtual ~Observer() = default;
  // The stage ("simulating", "compensating", ...) and the fraction of it
  // done, 0..1; the stage "" after the last one ends.
  virtual void progress(const std::string& stage, double fraction) {}
  // Polled at each progress step (every few thousand motions): true stops
  // the run with Cancelled (nothing written, no report file left).
  virtual bool cancelled() { return false; }
  // true: row() gets each reported CL point, as points.csv has it.
  virtual bool wants_rows() const { return false; }
  virtual void row(const report::PointRow& r) {}
};

// What a run used (machine, dialect, tools, material, config), found where
// the defaults led: one line for the summary, the same for summary.json.
struct Used {
  std::string text;  // "used: machine mill3 (...); T1: flat D10 mm (samples/tools.yaml); material ...; config ..."
  report::Json json;
};
Used used(const Run& r);

// The run's provenance for report.html: what a reader needs to trust or redo
// it. `command`: how the run was asked for (a command line), "" for none.
std::vector<std::pair<std::string, std::string>> provenance(const Run& r, const std::string& command);

// The prediction held against Settings::measured (measured.csv, summary.json's "measured").
struct MeasuredRow {
  compensate::V3 at_mm = compensate::V3::Zero();  // the measured surface point, work frame
  double measured_error_mm = 0;                    // e > 0: material left
  bool predicted = false;                          // false: farther than the reach from the predicted surface
  double predicted_error_mm = 0;
  std::uint32_t program_line = 0;                  // the line that generated the surface there (0: none)
  std::string feature, source;                     // the test cut's feature; "file:line" of the measurement
};
struct MeasuredComparison {
  std::vector<MeasuredRow> rows;  // one per measured point, in the file's order
  fit::Agreement agreement;       // over the rows with a prediction
  std::size_t unmatched = 0;
};

struct SimulateResult {
  report::RunFigures figures;             // the surface error, forces, cusp over the CL points
  compensate::Plausibility plausibility;  // the warnings on physically doubtful loads
  process::MachiningTime time;            // from the machine's axis limits
  Used used;
  report::Json summary;                   // summary.json
  std::optional<MeasuredComparison> measured;  // with Settings::measured
};

struct CompensateResult {
  compensate::Result result;              // counts, capped and feed-lowered lines, convergence
  compensate::WriteStats written;         // numbers changed, words and blocks inserted
  report::RunFigures figures;             // figures: compensated; figures.error_as_written: as written
  compensate::Plausibility plausibility;
  process::MachiningTime time_as_written, time_compensated;
  Used used;
  report::Json summary;                   // summary.json
  std::optional<MeasuredComparison> measured;  // with Settings::measured: the program as written against it
};

// Predicts the surface error of the opened program (against Settings::reference
// when given); with Settings::report_dir writes the report there. `command`
// goes into the report's provenance.
SimulateResult simulate(Run& r, Io& io, Observer* obs = nullptr, const std::string& command = "");

// Compensates the opened program and writes it to `out` (whole, after it is
// read back and checked: a run that fails writes nothing), or, with
// Settings::output, to that file atomically (never over the program).
CompensateResult compensate(Run& r, std::ostream& out, Io& io, Observer* obs = nullptr,
                            const std::string& command = "");

struct CompareResult {
  std::vector<report::CompareRow> rows;  // one per program, in the order given
  double tolerance_mm = 0;
};
// Simulates each program from the same stock with the same machine, tools
// and material (the first program's run builds them), the programs in
// parallel where cores allow; with Settings::report_dir writes compare.csv,
// compare.json and compare.html there.
CompareResult compare(const Settings& s, const std::vector<std::string>& programs, Io& io,
                      const std::string& command = "");

}  // namespace deflex::job
