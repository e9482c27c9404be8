// The report folder of a run, its progress and its plausibility messages (internal.hpp).
#include <filesystem>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/report/html.hpp"
#include "deflex/report/summary.hpp"
#include "internal.hpp"

namespace deflex::job::detail {
namespace fs = std::filesystem;

Recording::Recording(const Run& j, bool as_written, Observer* obs) : dir(j.given.report_dir) {
  report::RecorderOptions o;
  o.tolerance_mm = j.settings.tolerance_mm;
  o.as_written = as_written;
  o.tool_of = tool_of(j);
  o.spindle = &j.physics.spindle;
  o.workpiece = j.physics.workpiece != nullptr;
  // The summary's percentiles of |e| and its cusp heights always, report or
  // not: a summary is the same document whoever asks for it (the |e| go to a
  // spill file in the temporary folder, 8 bytes a point).
  o.percentiles = true;
  o.cusp = true;
  if (obs && obs->wants_rows()) o.rows = [obs](const report::PointRow& r) { obs->row(r); };
  if (!dir.empty()) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw Error(ErrorKind::io, dir + ": error: cannot create the report folder: " + ec.message());
    points = std::make_unique<writer::AtomicFile>((fs::path(dir) / "points.csv").string(), "");
    flank = std::make_unique<writer::AtomicFile>((fs::path(dir) / "flank_profile.csv").string(), "");
    o.points_csv = &points->stream();
    o.flank_csv = &flank->stream();
    o.page = true;
    o.spill_dir = dir;
  }
  rec = std::make_unique<report::Recorder>(std::move(o));
}

void Recording::finish(const Run& j, const report::RunFigures& f, const report::Json& summary,
                     std::vector<std::vector<std::string>> facts, const char* what, const std::string& command,
                     const MeasuredComparison* measured) {
  points->commit();
  if (f.flank_rows) flank->commit();
  const fs::path d(dir);
  writer::write_file_atomically((d / "summary.json").string(), "",
                                [&](std::ostream& o) { o << report::document(summary); });
  const report::Page page = rec->page();
  report::HtmlInput h;
  h.title = fs::path(j.prog.source().name()).filename().string() + ": deflex " + what;
  h.provenance = provenance(j, command);
  h.summary = summary;
  h.page = &page;
  std::vector<std::uint32_t> lines;
  for (const auto& row : page.worst["rows"]) lines.push_back(row["line"].get<std::uint32_t>());
  for (const auto& [l, text] : lines_of_file(j, lines)) h.line_text[l] = std::string(text.line_text(l));
  h.tolerance_mm = j.settings.tolerance_mm;
  h.facts = std::move(facts);
  if (measured)
    for (const MeasuredRow& r : measured->rows)
      h.measured.push_back({r.at_mm.x(), r.at_mm.y(), r.at_mm.z(), r.measured_error_mm, r.predicted, r.predicted_error_mm});
  writer::write_file_atomically((d / "report.html").string(), "", [&](std::ostream& o) { o << report::report_html(h); });
}

compensate::Progress progress_of(Observer* obs) {
  if (!obs) return {};
  return [obs](const std::string& stage, double fraction) {
    // Every progress step comes from the caller's thread between points: the
    // run stops there, and its temporary files go with the exception.
    if (!stage.empty() && obs->cancelled()) throw Cancelled();
    obs->progress(stage, fraction);
  };
}

void end_progress(const compensate::Progress& p) {
  if (p) p("", 1.0);
}

}  // namespace deflex::job::detail
