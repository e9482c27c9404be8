// What every program-reading run resolves first: config, machine, dialect,
// the libraries, the material's coefficients; config.yaml's values.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deflex/compensate/gouge.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/force/coefficients.hpp"
#include "deflex/interp/interpreter.hpp"
#include "deflex/job/settings.hpp"
#include "deflex/profile/profile.hpp"

namespace deflex::job {

// What a run needs to interpret a program: config, machine, dialect.
struct Setup {
  profile::Config config;
  std::optional<profile::MachineProfile> machine;
  profile::Dialect dialect;
  int max_errors = 20;
  bool block_delete_switch = false;
  bool strict = false;
  std::uint64_t max_blocks = 10'000'000;
  std::string tool_file;  // the run's tool library as given ("": the config's)
  // Lines that run more than once (interp::CallStructure::repeated), once the
  // program is known; null: every move inside a subprogram stays.
  std::shared_ptr<const std::vector<std::uint8_t>> repeated_lines;
  // Interpreter options pointing into this Setup (do not outlive it). The
  // radius of a G41/G42 D register: the machine profile's tool_offsets
  // (radius + wear), else the tool library's T<n> diameter / 2 for D<n>
  // (read the first time a program asks).
  interp::Options interp() const;
};
Setup resolve(const ReadSettings& r);
// The setup of a run that needs a machine (travel, stiffness): a settings Error without one.
Setup resolve_with_machine(const ReadSettings& r);

// Lines per piece when a program is read in pieces (gcode/reader.hpp):
// DEFLEX_CHUNK_LINES if set (0: whole; the tests read in pieces of a few
// lines to show the output does not change), else gcode::kPieceLines.
std::uint32_t piece_lines();

// The coefficients the settings name; `fallback_material` (e.g. from config.yaml)
// is used when neither a material nor coefficients are given.
// `described` (may be null): the material's name, library and source, or the
// coefficients given, for a report's provenance.
force::Coefficients coefficients_of(const MaterialSettings& m, const std::string& fallback_material = "",
                                    std::string* described = nullptr);
// A library file of the installed data folder (samples/...), for defaults.
std::string default_library(const char* rel);

// config.yaml values: a string, a path (relative to config.yaml's folder; a
// "box:" spec as it is) and a number; empty / dflt when the key is absent.
std::string config_string(const profile::Config& c, const char* key);
std::string config_path(const profile::Config& c, const char* key);
double config_number(const profile::Config& c, const char* key, double dflt);

// The tool library the settings or config name (samples/tools.yaml by default).
std::string tool_library_path(const std::string& given, const profile::Config& c);
// The material library: the one given, else the config's material_file, else the installed one.
std::string material_library_path(const std::string& given, const profile::Config& c);
// The stock a run starts from: `given`, else config.yaml's; a settings Error when neither.
std::string stock_spec(const std::string& given, const profile::Config& cfg);

// A settings Error when standard output is one of the `inputs` (a file of
// "-": standard input): `deflex compensate x.nc > x.nc` finds x.nc already
// emptied by the shell, and would read nothing and write nothing over it.
// Same device and inode, as cat compares them ("input file is output file").
void refuse_output_onto_input(const std::vector<std::string>& inputs);

// The gouge check's findings as warnings at the line of the largest gap of
// each side, naming the lines (compiler style, through diags).
void report_part_gaps(const compensate::PartGaps& g, const SourceText& src, double gap_mm, Diagnostics& diags);
// The same where the program's lines are gone (read in pieces): `line_of`
// gives the text of a line.
void report_part_gaps(const compensate::PartGaps& g, const std::function<SourceText(std::uint32_t)>& line_of,
                      double gap_mm, Diagnostics& diags);

}  // namespace deflex::job
