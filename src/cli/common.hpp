// Shared plumbing of the subcommands: option descriptions and parsing, and
// the printing every command does. Only src/cli/ includes
// Boost.Program_options; what a run resolves (config, machine, libraries)
// is the job API's (deflex/job/).
#pragma once
#include <boost/program_options.hpp>
#include <string>
#include <vector>

#include "deflex/cli/command.hpp"
#include "deflex/cli/exit.hpp"
#include "deflex/compensate/compensate.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/job/job.hpp"
#include "deflex/job/settings.hpp"
#include "deflex/job/setup.hpp"
#include "deflex/process/machining_time.hpp"

namespace deflex::cli {
namespace po = boost::program_options;

// The job API's names the commands use every day.
using job::coefficients_of;
using job::config_number;
using job::config_path;
using job::config_string;
using job::default_library;
using job::EarlierOp;
using job::material_library_path;
using job::piece_lines;
using job::refuse_output_onto_input;
using job::report_part_gaps;
using job::resolve;
using job::resolve_with_machine;
using job::Setup;
using job::stock_spec;
using job::tool_library_path;
using ReadOptions = job::ReadSettings;
using MaterialOptions = job::MaterialSettings;
using PartOptions = job::PartSettings;

// Options every program-reading command takes.
void add_read_options(po::options_description& d, ReadOptions& r, bool with_machine = true);
// Work-material options shared by forces, compensate and simulate:
// --material M [--material-file F] or --kt --kr --ka [--kte --kre --kae].
void add_material_options(po::options_description& d, MaterialOptions& m);
// The part model (design surface) options of compensate, simulate and check:
// --part FILE (config part:), --part-gap MM (config part_gap_mm, default 0.02).
void add_part_options(po::options_description& d, PartOptions& p);
// --stock-from FILE, repeatable, each optionally followed by --stock-from-tools
// LIB (the library of that program's tools), appended to `ops` in the order given.
void add_stock_from_options(po::options_description& d, std::vector<EarlierOp>& ops);
// The options of compensate (compensating) or simulate/compare, into the
// job's settings; --help into `help`, --job into `job_file`.
void describe(po::options_description& d, job::Settings& s, bool& help, std::string& job_file, bool compensating);

// Parses args against `desc` with `pos` positionals; throws Error(usage).
po::variables_map parse(const std::vector<std::string>& args, const po::options_description& desc,
                        const po::positional_options_description& pos);

// Parses args whose positional words are program files (up to max_files of
// them) into `files`; the named options go to `desc`. Throws Error(usage).
// Unless `words` (list's positionals are no files), refuses, before anything
// is computed, input files that are standard output (refuse_output_onto_input).
void parse_with_files(const std::vector<std::string>& args, const po::options_description& desc,
                      std::vector<std::string>& files, int max_files, bool words = false);

// Prints the subcommand's help: usage line, explanation, options.
void print_help(std::ostream& out, const std::string& usage, const std::string& text,
                const po::options_description& desc);

// The progress line (--progress: on a terminal by default) with the stage,
// percentage, elapsed time and what is left at the rate so far; with
// --verbose each stage's time when it ends. Null when nothing is shown.
compensate::Progress progress_for(Io& io);
// The progress line as a job's observer.
class ProgressLine : public job::Observer {
 public:
  explicit ProgressLine(Io& io) : line_(progress_for(io)) {}
  void progress(const std::string& stage, double fraction) override {
    if (line_) line_(stage, fraction);
  }

 private:
  compensate::Progress line_;
};
// Machining time from the machine's axis limits, one line on stderr.
void time_line(Io& io, const process::MachiningTime& before, const process::MachiningTime& after);
// The command line as a shell would take it back (for the provenance).
std::string command_of(const char* cmd, const std::vector<std::string>& args);

// "1,2.5,5" as numbers; a settings Error naming `flag` on anything else.
std::vector<double> numbers_of(const std::string& list, const char* flag);

}  // namespace deflex::cli
