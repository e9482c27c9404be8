// Shared plumbing of the subcommands: settings resolution, program loading,
// option descriptions. Only src/cli/ includes Boost.Program_options.
#pragma once
#include <boost/program_options.hpp>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deflex/cli/command.hpp"
#include "deflex/cli/exit.hpp"
#include "deflex/compensate/gouge.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/force/coefficients.hpp"
#include "deflex/gcode/program.hpp"
#include "deflex/interp/interpreter.hpp"
#include "deflex/profile/profile.hpp"

namespace deflex::cli {
namespace po = boost::program_options;

// Options every program-reading command takes.
struct ReadOptions {
  std::string dialect;
  std::string machine;
  std::string config;
  int max_errors = -1;
  std::string block_delete = "off";
  bool strict = false;  // the decimal-point warning is an error
  std::uint64_t max_blocks = 10'000'000;  // see interp::Options::max_blocks
};
void add_read_options(po::options_description& d, ReadOptions& r, bool with_machine = true);

// Lines per piece when a program is read in pieces (gcode/reader.hpp):
// DEFLEX_CHUNK_LINES if set (0: whole; the tests read in pieces of a few
// lines to show the output does not change), else gcode::kPieceLines.
std::uint32_t piece_lines();

// What a command needs to interpret a program: config, machine, dialect.
struct Setup {
  profile::Config config;
  std::optional<profile::MachineProfile> machine;
  profile::Dialect dialect;
  int max_errors = 20;
  bool block_delete_switch = false;
  bool strict = false;
  std::uint64_t max_blocks = 10'000'000;
  std::string tool_file;  // --tool-file, if the command has it (else the config's)
  // Lines that run more than once (interp::CallStructure::repeated), once the
  // program is known; null: every move inside a subprogram stays.
  std::shared_ptr<const std::vector<std::uint8_t>> repeated_lines;
  // Interpreter options pointing into this Setup (do not outlive it). The
  // radius of a G41/G42 D register: the machine profile's tool_offsets
  // (radius + wear), else the tool library's T<n> diameter / 2 for D<n>
  // (read the first time a program asks).
  interp::Options interp() const;
};
Setup resolve(const ReadOptions& r);

// Parses args against `desc` with `pos` positionals; throws Error(usage).
po::variables_map parse(const std::vector<std::string>& args, const po::options_description& desc,
                        const po::positional_options_description& pos);

// Work-material options shared by forces, compensate and simulate:
// --material M [--material-file F] or --kt --kr --ka [--kte --kre --kae].
struct MaterialOptions {
  std::string material, material_file;
  std::optional<double> kt, kr, ka, kte, kre, kae;
};
void add_material_options(po::options_description& d, MaterialOptions& m);
// The coefficients the options name; `fallback_material` (e.g. from config.yaml)
// is used when neither a material nor coefficients are given. Throws Error(usage/config).
// `described` (may be null): the material's name, library and source, or the
// coefficients given, for a report's provenance.
force::Coefficients coefficients_of(const MaterialOptions& m, const std::string& fallback_material = "",
                                    std::string* described = nullptr);
// A library file given relative to the source tree (samples/...), for defaults.
std::string default_library(const char* rel);

// config.yaml values: a string, a path (relative to config.yaml's folder; a
// "box:" spec as it is) and a number; empty / dflt when the key is absent.
std::string config_string(const profile::Config& c, const char* key);
std::string config_path(const profile::Config& c, const char* key);
double config_number(const profile::Config& c, const char* key, double dflt);

// The part model (design surface) options of compensate, simulate and check:
// --part FILE (config part:), --part-gap MM (config part_gap_mm, default 0.02).
struct PartOptions {
  std::string part;
  std::optional<double> gap_mm;
};
void add_part_options(po::options_description& d, PartOptions& p);
// The tool library the options or config name (samples/tools.yaml by default).
std::string tool_library_path(const std::string& option, const profile::Config& c);
// The material library: the option, else the config's material_file, else the installed one.
std::string material_library_path(const std::string& option, const profile::Config& c);

// Parses args whose positional words are program files (up to max_files of
// them) into `files`; the named options go to `desc`. Throws Error(usage).
// Unless `words` (list's positionals are no files), refuses, before anything
// is computed, input files that are standard output (refuse_output_onto_input).
void parse_with_files(const std::vector<std::string>& args, const po::options_description& desc,
                      std::vector<std::string>& files, int max_files, bool words = false);

// Throws Error(usage) when standard output is one of the `inputs` (a file of
// "-": standard input): `deflex compensate x.nc > x.nc` finds x.nc already
// emptied by the shell, and would read nothing and write nothing over it.
// Same device and inode, as cat compares them ("input file is output file").
void refuse_output_onto_input(const std::vector<std::string>& inputs);

// Prints the subcommand's help: usage line, explanation, options.
void print_help(std::ostream& out, const std::string& usage, const std::string& text,
                const po::options_description& desc);

// The gouge check's findings as warnings at the line of the largest gap of
// each side, naming the lines (compiler style, through diags).
void report_part_gaps(const compensate::PartGaps& g, const SourceText& src, double gap_mm, Diagnostics& diags);
// The same where the program's lines are gone (read in pieces): `line_of`
// gives the text of a line.
void report_part_gaps(const compensate::PartGaps& g, const std::function<SourceText(std::uint32_t)>& line_of,
                      double gap_mm, Diagnostics& diags);

}  // namespace deflex::cli
