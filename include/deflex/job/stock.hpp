// What a shop without the stock model needs before a compensation, as calls:
// the stock after earlier programs (`deflex stock`), and a roughing that
// leaves an allowance over what a finishing program cuts (`deflex rough`).
#pragma once
#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "deflex/job/io.hpp"
#include "deflex/job/settings.hpp"
#include "deflex/plan/roughing.hpp"
#include "deflex/process/machining_time.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::job {

struct StockSettings {
  ReadSettings read;
  std::string stock;                  // the start: box, solid or .zmap ("": config stock)
  std::string tool_file;              // ("": config tool_file, else the installed one)
  std::vector<EarlierOp> stock_from;  // swept into it in order, each with its own tools
  double cell_mm = 0.05;
  double cl_spacing_mm = 0.5;
};

// The stock after the earlier programs (each read and checked before any is
// swept). `spec` (may be null) gets the start's spec as resolved.
stock::ZMap rest_stock(const StockSettings& s, Io& io, std::string* spec = nullptr);

struct StockFile {
  std::string spec;          // the start, as resolved
  stock::GridSpec grid;      // the Z-map's cells
  bool zmap = false;         // a .zmap (every height as computed), else a binary STL
  std::size_t triangles = 0;  // the STL's
};

// rest_stock() written atomically to `output`: FILE.zmap, the Z-map itself
// (stock/zmap_file.hpp), any other name a closed binary STL whose surface is
// within `mesh_tolerance_mm` of every cell's height (stock/mesh_out.hpp). The
// output and the tolerance are checked before anything is read.
StockFile write_rest_stock(const StockSettings& s, const std::string& output, double mesh_tolerance_mm, Io& io);

struct RoughSettings {
  std::string finish_program;  // a file (it is read twice)
  std::string output;          // "" or "-": the output stream
  ReadSettings read;
  std::string stock, tool_file;
  std::string rough_tool;      // T<n> of the library: the generated program's cutter
  std::string finish_tool;     // the finishing program's tool for every cut ("": its T words)
  plan::RoughingOptions plan;  // allowance, sample, spindle, feed (tool, stepdown and stepover set here)
  std::optional<double> stepdown_mm, stepover_mm;  // default: half the diameter, 40 % of it
  double cell_mm = 0.1;        // the target surface's Z-map cell
  double cl_spacing_mm = 0.5;
};

struct RoughResult {
  std::string name;            // where the program went ("<stdout>" or the file)
  plan::RoughingPlan plan;
  double line_spacing_mm = 0;  // the stepover spread evenly over the stock
  std::size_t moves = 0;
  process::MachiningTime time;
};

// Plans the roughing and writes it (to `out`, or atomically to
// RoughSettings::output), after reading it back as any program is: it must
// interpret without a diagnostic and stay in the machine's travel.
RoughResult rough(const RoughSettings& s, std::ostream& out, Io& io);

}  // namespace deflex::job
