// What simulate, compensate and compare share inside src/job: the report
// folder's files, the progress with cancellation, the messages on findings.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "deflex/compensate/collision.hpp"
#include "deflex/compensate/pipeline.hpp"
#include "deflex/job/job.hpp"
#include "deflex/report/recorder.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::job::detail {

// What the pipeline in pieces (compensate/pipeline.hpp) needs of a run read in pieces.
compensate::PipelineInput pipeline_input(Run& j, const compensate::Progress& progress);

// The recorder of a run's points and, with Settings::report_dir, the report
// folder's files it streams: points.csv and flank_profile.csv, each renamed
// into place when the run ends well (flank_profile.csv only when a flank
// point has a profile). The folder gets summary.json and report.html at the
// end (finish). An observer that wants rows gets each points.csv row.
struct Recording {
  Recording(const Run& j, bool as_written, Observer* obs);
  // points.csv and flank_profile.csv into place; summary.json and report.html.
  // `measured` (may be null): the measured points beside their predictions.
  void finish(const Run& j, const report::RunFigures& f, const report::Json& summary,
              std::vector<std::vector<std::string>> facts, const char* what, const std::string& command,
              const MeasuredComparison* measured = nullptr);

  std::string dir;
  std::unique_ptr<writer::AtomicFile> points, flank;
  std::unique_ptr<report::Recorder> rec;
};

// The observer's progress, polling its cancellation (null without an observer).
compensate::Progress progress_of(Observer* obs);
// After the last stage: the stage "" (a progress line is cleared).
void end_progress(const compensate::Progress& p);

// Plausibility warnings (compensate::PlausibilityScan), compiler style at the
// line of the worst point, and their summary.json array.
void print_plausibility(const Run& j, const compensate::Plausibility& pl, Io& io);
// summary.json's "spindle": the run's peak power and torque, and the rating
// they are held against (null without one in the machine profile).
report::Json spindle_json(const report::RunFigures& f, const profile::SpindleRating& r);
// summary.json's "stability": the points whose a_p was held against the
// stability limit, how many were above it, and the largest a_p over it.
report::Json stability_json(const report::RunFigures& f);
report::Json warnings_json(const compensate::Plausibility& pl);

// The tool assembly in the stock (compensate/collision.hpp): each collision
// an error at its first line, column 1 (the block).
void report_collisions(const Run& j, const std::vector<compensate::Collision>& c, Diagnostics& diags);
// The same from a run's scan, then the run's input Error ("...; " + nothing)
// when there is one: the run goes no further and writes nothing.
void refuse_collisions(const Run& j, const compensate::CollisionScan& scan, Io& io, const std::string& nothing);
// The program swept through the stock alone (compensate::Settings::
// geometry_only: the simulation's samples, batches and stock, no forces):
// the collisions simulate and compensate would refuse.
std::vector<compensate::Collision> sweep_collisions(Run& j, const compensate::Progress& progress);

// The cutting moves a compensation leaves as written, once per reason with
// a count and the first line (a note); and the points they leave outside the
// tolerance (a warning at the first such line): "N points compensated" is
// never silently smaller than the points outside the tolerance.
void print_left_alone(const Run& j, const report::RunFigures& f, Io& io);
report::Json left_alone_json(const report::RunFigures& f);
// The warnings and notes of the mirror pass: lowered feeds, plausibility,
// capped offsets, linearised and non-uniform arcs, convergence.
void print_compensation(const Run& j, const compensate::Result& r, const compensate::Plausibility& pl, Io& io);

// Settings::measured read as observations (measure/measured.hpp): a CSV or a
// point cloud as points of the machined surface, a probe log joined with its
// probe program as errors along the intended normals. Located errors.
std::vector<fit::Observation> read_observations(const Settings& s);

// The prediction of a run held against its measured points, as the points
// come (fit::Nearest): made when the run has measured points, null otherwise.
std::unique_ptr<fit::Nearest> nearest_of(const Run& j);
MeasuredComparison held_against(const Run& j, const fit::Nearest& n);
// measured.csv into the report folder; the summary's "measured"; the message.
void write_measured_csv(const std::string& dir, const MeasuredComparison& m);
report::Json measured_json(const MeasuredComparison& m, const Run& j);
void print_measured(const Run& j, const MeasuredComparison& m, Io& io);

}  // namespace deflex::job::detail
