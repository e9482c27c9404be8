// deflex compare A.nc B.nc ...: several programs for the same part (strategies)
// simulated on the same stock, one row of figures each (report/compare.hpp).
#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <thread>

#include "common.hpp"
#include "deflex/report/compare.hpp"
#include "deflex/report/html.hpp"
#include "deflex/report/recorder.hpp"
#include "deflex/report/summary.hpp"
#include "deflex/writer/writer.hpp"
#include "job.hpp"

namespace deflex::cli {
namespace {
namespace fs = std::filesystem;
using compensate::V3;

const char* kCompareHelp =
    "Simulates each program from the same stock with the same machine, tool library and\n"
    "material - as `deflex simulate` does one - and prints one row per program: surface\n"
    "error against its own path (max, rms, p95, share outside the tolerance), peak and\n"
    "mean cutting force, peak deflection, peak material removal rate, mean effective\n"
    "diameter and engaged area, cusp height between passes (max, mean; ball ends),\n"
    "cutting path length and machining time from the machine's axis limits. Use it to\n"
    "choose a finishing strategy (zig-zag direction, contour-parallel, ...) before\n"
    "compensating the chosen one. The programs run in parallel where cores allow; the\n"
    "figures do not depend on it.\n"
    "--format csv|json prints the table in that form; --report DIR writes compare.csv,\n"
    "compare.json and compare.html (the table with bars) into DIR.\n";

struct Outcome {
  report::CompareRow row;
  std::exception_ptr failed;
};

// Simulates job `j` alone (one thread when others run beside it).
Outcome run_one(const Job& j, int threads) {
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

}  // namespace

int cmd_compare(const std::vector<std::string>& args, Io& io) {
  Args a;
  po::options_description desc("options");
  describe(desc, a, false);
  std::string format = "text";
  desc.add_options()("format", po::value(&format)->default_value("text"), "text, csv or json");
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1000);
  apply_job(a, files);
  if (a.help) {
    print_help(io.out, "deflex compare A.nc B.nc ... [--format text|csv|json] [--report DIR] (options as deflex simulate)",
               kCompareHelp, desc);
    return 0;
  }
  if (files.size() < 2) throw Error(ErrorKind::settings, "compare: give two or more programs");
  if (!a.reference.empty()) throw Error(ErrorKind::settings, "compare: --reference is for simulate");
  if (format != "text" && format != "csv" && format != "json")
    throw Error(ErrorKind::settings, "--format must be text, csv or json");
  if (std::count(files.begin(), files.end(), "-") > 1) throw Error(ErrorKind::settings, "compare: standard input (-) can be read once");
  if (!a.report.empty()) writer::check_output_folder(a.report);
  // Every program read and checked before anything is simulated; the first
  // builds the stock and part model, the others share them.
  std::vector<Job> jobs;
  jobs.reserve(files.size());
  for (const std::string& f : files) {
    Args ai = a;
    ai.file = f;
    jobs.push_back(prepare(ai, io, false, jobs.empty() ? nullptr : &jobs.front()));
  }
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const unsigned workers = std::min<unsigned>(cores, static_cast<unsigned>(jobs.size()));
  std::vector<Outcome> out(jobs.size());
  std::atomic<std::size_t> next{0};
  std::vector<std::thread> pool;
  for (unsigned w = 0; w < workers; ++w)
    pool.emplace_back([&] {
      for (std::size_t i; (i = next++) < jobs.size();) out[i] = run_one(jobs[i], workers > 1 ? 1 : a.threads);
    });
  for (std::thread& t : pool) t.join();
  std::vector<report::CompareRow> rows;
  for (const Outcome& o : out) {
    if (o.failed) std::rethrow_exception(o.failed);
    rows.push_back(o.row);
  }
  const double tol = jobs.front().settings.tolerance_mm;
  if (format == "csv") io.out << report::compare_csv(rows);
  else if (format == "json") io.out << report::line(report::compare_json(rows, tol));
  else io.out << report::compare_text(rows, tol);
  if (!a.report.empty()) {
    std::error_code ec;
    fs::create_directories(a.report, ec);
    if (ec) throw Error(ErrorKind::io, a.report + ": error: cannot create the report folder: " + ec.message());
    const fs::path d(a.report);
    writer::write_file_atomically((d / "compare.csv").string(), "", [&](std::ostream& o) { o << report::compare_csv(rows); });
    writer::write_file_atomically((d / "compare.json").string(), "",
                                  [&](std::ostream& o) { o << report::document(report::compare_json(rows, tol)); });
    // Every program with its checksum, then what they share (the first job's
    // provenance without its own program rows).
    std::vector<std::pair<std::string, std::string>> prov;
    for (const Job& j : jobs)
      prov.emplace_back("program", j.prog.source().name() + "  (SHA-256 " + report::sha256_hex(j.prog.source().bytes()) + ")");
    for (auto& row : provenance(jobs.front(), command_of("compare", args), ""))
      if (row.first != "program" && row.first != "program SHA-256") prov.push_back(std::move(row));
    writer::write_file_atomically((d / "compare.html").string(), "",
                                  [&](std::ostream& o) { o << report::compare_html(rows, tol, prov); });
  }
  return 0;
}

}  // namespace deflex::cli
