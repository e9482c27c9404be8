// The settings of a deflex job as plain data: what the command line and a job
// file give. Every value left empty or unset takes the default of config.yaml
// (or of the machine profile), as the command line's options do; the checks of
// each value run in job::open() before anything is read or computed.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace deflex::job {

// How a program is read: config, machine, dialect, error limits.
struct ReadSettings {
  std::string dialect;  // a built-in name or a dialect .yaml ("": config, else the machine's, else fanuc)
  std::string machine;  // a machine profile: a name or a .yaml file ("": config's)
  std::string config;   // config.yaml ("": searched, profile/search.hpp)
  int max_errors = -1;  // stop after so many errors (0: no limit; -1: config's, 20)
  std::string block_delete = "off";  // off executes '/' blocks, on skips them
  bool strict = false;  // the decimal-point warning, a stock out of reach: errors, not warnings
  std::uint64_t max_blocks = 10'000'000;  // see interp::Options::max_blocks
};

// The work material: a name in the material library, or the coefficients.
struct MaterialSettings {
  std::string material, material_file;
  std::optional<double> kt, kr, ka;     // K_tc, K_rc, K_ac, N/mm^2
  std::optional<double> kte, kre, kae;  // K_te, K_re, K_ae, N/mm (default 0)
};

// The part model (design surface) and the gouge check's gap.
struct PartSettings {
  std::string part;               // STL, STEP or IGES ("": config part, else none)
  std::optional<double> gap_mm;   // default: config part_gap_mm, else 0.02
};

// How the workpiece is held, for its own compliance in the cut
// (stiffness/workpiece.hpp): none, a rigid workpiece (the tool's deflection
// alone). With fixtures the part model and a material with elastic constants
// are required.
struct Workholding {
  std::vector<std::string> fixtures;  // box:X0,Y0,Z0,X1,Y1,Z1 each, mm: the part's surface inside is held
  double mesh_mm = 0;                 // the part's element size (0: half its thinnest wall)
  double spacing_mm = 0;              // between the nodes of the compliance field (0: the coarsest of
                                      // 4, 2 and 1 x kDefaultFieldSpacingMm whose field holds against the FEM)
  int stages = 0;                     // the in-process stock meshed at this many moments (0: the finished part)
};
inline constexpr int kMaxWorkpieceStages = 100;
inline constexpr double kDefaultFieldSpacingMm = 3;

// An earlier program swept into the stock, and its tool library ("": the job's).
struct EarlierOp {
  std::string program, tool_file;
};

struct Settings {
  std::string program;     // the program's file, "-" for the input stream
  std::string output;      // compensate: the compensated program's file ("" or "-": the output stream)
  std::string reference;   // simulate: judge against this program's path (the design intent)
  std::string report_dir;  // report.html, points.csv, flank_profile.csv, summary.json into this folder
  // Measurements of the part this program cut (measure/measured.hpp): a CSV
  // of points x_mm,y_mm,z_mm, a point cloud (.ply, .stl) or a probe log with
  // the probe program that wrote it. simulate and compensate hold their
  // prediction against them (measured.csv in the report); fit fits to them.
  std::string measured, probe_program;
  double measured_reach_mm = 0.5;  // a measured point farther than this from the predicted surface has no prediction
  ReadSettings read;
  MaterialSettings material;
  PartSettings part;
  Workholding workholding;
  std::string tool_file;   // the tool library ("": config tool_file, else the installed samples/tools.yaml)
  std::string tool;        // one tool for every cut ("": the program's T words, as T<n>)
  std::string stock;       // box:X0,Y0,Z0,X1,Y1,Z1, a solid, a .zmap or auto[:MARGIN] ("": config stock)
  std::vector<EarlierOp> stock_from;  // earlier operations swept into the stock, in the order they ran
  std::optional<double> tolerance_mm;  // default: config tolerance_mm, else 0.01
  std::optional<double> gain;          // mirror gain, default: config gain, else 1
  double feed_limit_N = 0;             // > 0: lower F where the peak force would exceed it
  std::optional<double> spindle_rpm, feed_mm_per_min;  // for cutting moves the program gives no S, F
  double cell_mm = 0.05;        // Z-map cell
  double cl_spacing_mm = 0.5;   // largest distance between CL points along a move
  int max_iterations = 8;       // mirror updates per point at most
  int threads = 0;              // worker threads (0: all cores)
  bool tool_only = false;       // leave holder, spindle and machine out of the compliance
  bool expand_subprograms = false;  // compensate: each M98 call written inline
};

// Fills what `s` leaves out from the job file `file` (YAML: program, machine,
// dialect, tool_file, tool, material, material_file, stock, stock_from, part,
// fixture, workpiece_mesh_mm, workpiece_spacing_mm, workpiece_stages, tolerance_mm, gain,
// output, report, measured, probe_program). Paths in it are relative to its folder.
// `programs` gets the job's program when it holds none. Throws a config Error
// at line:col of a bad key or value.
void apply_job_file(const std::string& file, Settings& s, std::vector<std::string>& programs);

// Every file a job reads (programs, stock, part, libraries), for the check
// that standard output is none of them.
std::vector<std::string> input_files(const Settings& s, const std::vector<std::string>& programs);

}  // namespace deflex::job
