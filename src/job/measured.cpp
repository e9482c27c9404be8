// The prediction held against measured points (job.hpp MeasuredComparison):
// the rows of measured.csv, the agreement in summary.json, the message.
#include <cmath>
#include <filesystem>
#include <ostream>

#include "deflex/diag/plural.hpp"
#include "internal.hpp"

namespace deflex::job::detail {

namespace fs = std::filesystem;

std::unique_ptr<fit::Nearest> nearest_of(const Run& j) {
  if (j.measured.empty()) return nullptr;
  return std::make_unique<fit::Nearest>(j.measured, j.given.measured_reach_mm, tool_of(j));
}

MeasuredComparison held_against(const Run& j, const fit::Nearest& n) {
  MeasuredComparison m;
  std::vector<double> pred, meas;
  for (std::size_t i = 0; i < j.measured.size(); ++i) {
    const fit::Observation& o = j.measured[i];
    const fit::Nearest::Found& f = n.found()[i];
    MeasuredRow r;
    r.at_mm = o.measured_mm;
    r.feature = o.feature;
    r.source = o.source;
    if (f.found) {
      r.predicted = true;
      r.predicted_error_mm = f.predicted_error_mm;
      r.measured_error_mm = fit::measured_error(o, f.sample, j.part.get());
      r.program_line = f.sample.line;
      pred.push_back(r.predicted_error_mm);
      meas.push_back(r.measured_error_mm);
    } else {
      ++m.unmatched;
      // Without a predicted surface the error needs the part model, or the probe log's.
      if (o.error_mm) r.measured_error_mm = *o.error_mm;
      else if (j.part) r.measured_error_mm = fit::measured_error(o, fit::SurfaceSample{}, j.part.get());
      else r.measured_error_mm = std::nan("");
    }
    m.rows.push_back(std::move(r));
  }
  m.agreement = fit::agreement(pred, meas, j.settings.tolerance_mm);
  return m;
}

namespace {

std::string num(double v) { return std::isfinite(v) ? fixed_decimals(v, 6) : ""; }

}  // namespace

void write_measured_csv(const std::string& dir, const MeasuredComparison& m) {
  writer::write_file_atomically((fs::path(dir) / "measured.csv").string(), "", [&](std::ostream& o) {
    o << "x_mm,y_mm,z_mm,measured_error_mm,predicted_error_mm,program_line,feature\n";
    for (const MeasuredRow& r : m.rows)
      o << num(r.at_mm.x()) << ',' << num(r.at_mm.y()) << ',' << num(r.at_mm.z()) << ',' << num(r.measured_error_mm)
        << ',' << (r.predicted ? num(r.predicted_error_mm) : "") << ',' << (r.program_line ? std::to_string(r.program_line) : "")
        << ',' << r.feature << '\n';
  });
}

report::Json measured_json(const MeasuredComparison& m, const Run& j) {
  const fit::Agreement& a = m.agreement;
  auto mm = [](double v) { return std::isfinite(v) ? report::Json(report::fixed(v, 6)) : report::Json(); };
  return report::Json{{"file", j.given.measured},
                      {"probe_program", j.given.probe_program.empty() ? report::Json() : report::Json(j.given.probe_program)},
                      {"points", m.rows.size()},
                      {"compared", a.points},
                      {"without_prediction", m.unmatched},
                      {"difference_rms_mm", mm(a.rms_difference_mm)},
                      {"difference_max_mm", mm(a.max_difference_mm)},
                      {"correlation", std::isfinite(a.correlation) ? report::Json(report::fixed(a.correlation, 4)) : report::Json()},
                      {"within_tolerance_share", report::fixed(a.within_tolerance_share, 4)},
                      {"measured_rms_mm", mm(a.rms_measured_mm)},
                      {"measured_max_mm", mm(a.max_measured_mm)}};
}

void print_measured(const Run& j, const MeasuredComparison& m, Io& io) {
  const fit::Agreement& a = m.agreement;
  if (m.unmatched)
    io.err << j.given.measured << ": warning: " << plural(m.unmatched, "measured point") << " of " << m.rows.size()
           << " lie farther than " << fixed_decimals(j.given.measured_reach_mm, 3) << " mm from the surface "
           << j.prog.source().name() << " cuts: no prediction there (is the work offset, or the program, the one measured?)\n";
  if (!a.points) return;
  io.info() << j.given.measured << ": predicted against measured over " << plural(a.points, "point")
            << ": difference rms " << fixed_decimals(a.rms_difference_mm * 1000, 2) << " um, max "
            << fixed_decimals(a.max_difference_mm * 1000, 2) << " um; measured error rms "
            << fixed_decimals(a.rms_measured_mm * 1000, 2) << " um; "
            << (std::isfinite(a.correlation) ? "correlation " + fixed_decimals(a.correlation, 3) : std::string("no correlation"))
            << "; " << fixed_decimals(a.within_tolerance_share * 100, 1) << " % agree within the tolerance "
            << fixed_decimals(j.settings.tolerance_mm * 1000, 1) << " um\n";
}

}  // namespace deflex::job::detail
