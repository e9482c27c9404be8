// The earlier operations a stock is swept from (Settings::stock_from), each
// with the tool library its T words name: a roughing programmed
// against the shop's roughing library keeps it, beside a finish of another.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "deflex/job/io.hpp"
#include "deflex/job/settings.hpp"
#include "deflex/job/setup.hpp"
#include "deflex/interp/motion.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::job {

// An earlier operation read and checked, with its own library where it has one.
struct EarlierRun {
  std::vector<interp::Motion> motions;
  std::optional<stiffness::ToolLibrary> own_tools;
  const stiffness::ToolLibrary& tools(const stiffness::ToolLibrary& run_tools) const {
    return own_tools ? *own_tools : run_tools;
  }
};

// Every earlier operation read and checked (read_earlier) before any stock is
// built: a tool its library lacks is an error at its line naming that library.
std::vector<EarlierRun> read_earlier_all(const std::vector<EarlierOp>& ops, const Setup& setup,
                                         const stiffness::ToolLibrary& run_tools, Io& io);
// Sweeps them into `z` in order, each with its own tools.
void sweep_earlier_all(const std::vector<EarlierRun>& runs, stock::ZMap& z, const stiffness::ToolLibrary& run_tools,
                       double cl_spacing_mm);
// "rough.nc", or "rough.nc (tools: rough_tools.yaml)" (the report's provenance).
std::string earlier_text(const EarlierOp& op);

// An earlier operation (--stock-from): read and interpreted under `setup`,
// its diagnostics naming its own file, checked (travel, every cutting motion's
// tool in `lib`, or `tool_override` for every cut) before anything is
// swept. Throws on any error.
std::vector<interp::Motion> read_earlier(const std::string& file, const Setup& setup, const stiffness::ToolLibrary& lib,
                                         Io& io, const std::string& tool_override = "");
// Sweeps its motions into `z` with their own tools (or `tool_override`), geometry only.
void sweep_earlier(const std::vector<interp::Motion>& motions, stock::ZMap& z, const stiffness::ToolLibrary& lib,
                   double cl_spacing_mm, const std::string& tool_override = "");

}  // namespace deflex::job
