// The calibration test cut as calls (`deflex testcut`, `deflex probe`): a
// program that cuts walls for the user's machine, tool and material on a
// block, with its plan (YAML), and the on-machine probing program of those
// walls (plan/testcut.hpp, plan/probe.hpp).
#pragma once
#include <iosfwd>
#include <optional>
#include <string>

#include "deflex/job/io.hpp"
#include "deflex/job/settings.hpp"
#include "deflex/plan/probe.hpp"
#include "deflex/plan/testcut.hpp"

namespace deflex::job {

struct TestCutSettings {
  ReadSettings read;          // machine (required), dialect, config
  std::string tool;           // T<n> of the library: the cutter (required)
  std::string tool_file;      // ("": config tool_file, else the installed one)
  MaterialSettings material;  // a material of the library (required)
  std::string stock;          // box:X0,Y0,Z0,X1,Y1,Z1 (required: the test block)
  std::string output;         // the program (a file: the plan names it)
  std::string plan;           // the plan ("": the output's stem + .yaml)
  std::optional<double> spindle_rpm;      // default 6000
  std::optional<double> feed_mm_per_min;  // or fz: one of them; default fz 0.05 mm
  std::optional<double> fz_mm;
  plan::TestCutOptions options;  // depths, lengths (tool number, speeds set here)
};

struct TestCutResult {
  std::string program, plan_file;
  plan::TestCutPlan plan;
  std::size_t moves = 0;
};

// Checks every setting and the block's size first, plans the walls, writes
// the program and the plan atomically (nothing written on any failure) after
// reading the program back as any program is: it must interpret without a
// diagnostic and stay in the machine's travel.
TestCutResult testcut(const TestCutSettings& s, Io& io);

// The plan file beside a program: its stem + .yaml.
std::string plan_path_for(const std::string& program);

struct ProbeSettings {
  std::string plan;            // testcut.yaml
  std::string output;          // "" or "-": the output stream
  ReadSettings read;           // the dialect ("": the plan's)
  std::string probe_tool;      // T<n> ("": the probe is in the spindle, its length offset active)
  plan::ProbeOptions options;  // ball, step, approach, feeds (probe_tool set here)
};

struct ProbeResult {
  std::string name;  // where the program went
  plan::ProbeProgram program;
  std::size_t points = 0;
};

ProbeResult probe(const ProbeSettings& s, std::ostream& out, Io& io);

}  // namespace deflex::job
