// deflex compare A.nc B.nc ...: several programs for the same part (strategies)
// simulated on the same stock (job::compare), one row of figures each.
#include "common.hpp"
#include "deflex/job/job.hpp"
#include "deflex/report/summary.hpp"

namespace deflex::cli {
namespace {

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

}  // namespace

int cmd_compare(const std::vector<std::string>& args, Io& io) {
  job::Settings s;
  bool help = false;
  std::string job_file;
  po::options_description desc("options");
  describe(desc, s, help, job_file, false);
  std::string format = "text";
  desc.add_options()("format", po::value(&format)->default_value("text"), "text, csv or json");
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1000);
  if (!job_file.empty()) job::apply_job_file(job_file, s, files);
  if (help) {
    print_help(io.out, "deflex compare A.nc B.nc ... [--format text|csv|json] [--report DIR] (options as deflex simulate)",
               kCompareHelp, desc);
    return 0;
  }
  if (format != "text" && format != "csv" && format != "json")
    throw Error(ErrorKind::settings, "--format must be text, csv or json");
  const job::CompareResult c = job::compare(s, files, io, command_of("compare", args));
  if (format == "csv") io.out << report::compare_csv(c.rows);
  else if (format == "json") io.out << report::line(report::compare_json(c.rows, c.tolerance_mm));
  else io.out << report::compare_text(c.rows, c.tolerance_mm);
  return 0;
}

}  // namespace deflex::cli
