// job::compare() (job.hpp): several programs for one part simulated on the
// same stock, one row of figures each (report/compare.hpp).
#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <thread>

#include "deflex/report/html.hpp"
#include "deflex/report/summary.hpp"
#include "internal.hpp"

namespace deflex::job {
namespace {

namespace fs = std::filesystem;
using compensate::V3;

struct Outcome {
  report::CompareRow row;
  std::exception_ptr failed;
};

// Simulates run `j` alone (one thread when others run beside it).
Outcome run_one(const Run& j, int threads) {
  Outcome o;
  try {
    compensate::Settings s = j.settings;
    s.threads = threads;
    report::RecorderOptions ro;
    ro.tolerance_mm = s.tolerance_mm;
    ro.percentiles = true;
    ro.tool_of = tool_of(j);
    report::Recorder rec(ro);
    compensate::simulate(j.motions, {}, j.physics, s, [&rec](const compensate::Point& p) { rec.point(p, V3::Zero(), 0); });
    const process::MachiningTime tm = process::machining_time(j.motions, j.setup.machine->axis_limits);
    o.row = report::compare_row(j.prog.source().name(), rec.finish(), tm);
  } catch (...) {
    o.failed = std::current_exception();
  }
  return o;
}

// The runs in parallel, a program per core, each on one thread.
std::vector<report::CompareRow> run_all(const std::vector<Run>& runs, int threads) {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const unsigned workers = std::min<unsigned>(cores, static_cast<unsigned>(runs.size()));
  std::vector<Outcome> out(runs.size());
  std::atomic<std::size_t> next{0};
  std::vector<std::thread> pool;
  for (unsigned w = 0; w < workers; ++w)
    pool.emplace_back([&] {
      for (std::size_t i; (i = next++) < runs.size();) out[i] = run_one(runs[i], workers > 1 ? 1 : threads);
    });
  for (std::thread& t : pool) t.join();
  std::vector<report::CompareRow> rows;
  for (const Outcome& o : out) {
    if (o.failed) std::rethrow_exception(o.failed);
    rows.push_back(o.row);
  }
  return rows;
}

// compare.csv, compare.json and compare.html into the report folder.
void write_report(const std::vector<Run>& runs, const CompareResult& c, const std::string& dir,
                  const std::string& command) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error(ErrorKind::io, dir + ": error: cannot create the report folder: " + ec.message());
  const fs::path d(dir);
  writer::write_file_atomically((d / "compare.csv").string(), "", [&](std::ostream& o) { o << report::compare_csv(c.rows); });
  writer::write_file_atomically((d / "compare.json").string(), "",
                                [&](std::ostream& o) { o << report::document(report::compare_json(c.rows, c.tolerance_mm)); });
  // Every program with its checksum, then what they share (the first run's
  // provenance without its own program rows).
  std::vector<std::pair<std::string, std::string>> prov;
  for (const Run& j : runs)
    prov.emplace_back("program", j.prog.source().name() + "  (SHA-256 " + report::sha256_hex(j.prog.source().bytes()) + ")");
  for (auto& row : provenance(runs.front(), command))
    if (row.first != "program" && row.first != "program SHA-256") prov.push_back(std::move(row));
  writer::write_file_atomically((d / "compare.html").string(), "",
                                [&](std::ostream& o) { o << report::compare_html(c.rows, c.tolerance_mm, prov); });
}

}  // namespace

CompareResult compare(const Settings& s, const std::vector<std::string>& programs, Io& io, const std::string& command) {
  if (programs.size() < 2) throw Error(ErrorKind::settings, "compare: give two or more programs");
  if (!s.reference.empty()) throw Error(ErrorKind::settings, "compare: a reference is for simulate");
  if (std::count(programs.begin(), programs.end(), "-") > 1)
    throw Error(ErrorKind::settings, "compare: standard input (-) can be read once");
  if (!s.report_dir.empty()) writer::check_output_folder(s.report_dir);
  // Every program read and checked before anything is simulated; the first
  // builds the stock and part model, the others share them.
  std::vector<Run> runs;
  runs.reserve(programs.size());
  for (const std::string& f : programs) {
    Settings one = s;
    one.program = f;
    runs.push_back(open(one, Purpose::compare, io, nullptr, runs.empty() ? nullptr : &runs.front()));
  }
  CompareResult c;
  c.rows = run_all(runs, s.threads);
  c.tolerance_mm = runs.front().settings.tolerance_mm;
  if (!s.report_dir.empty()) write_report(runs, c, s.report_dir, command);
  return c;
}

}  // namespace deflex::job
