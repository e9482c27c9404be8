// deflex stock: the stock after earlier operations (job::write_rest_stock), as a .zmap (every cell's
// height, compact: stock/zmap_file.hpp) for the next operation, or as a closed
// binary STL (stock/mesh_out.hpp) for a CAM system or a viewer.
#include "common.hpp"
#include "deflex/job/stock.hpp"

namespace deflex::cli {

int cmd_stock(const std::vector<std::string>& args, Io& io) {
  job::StockSettings s;
  std::string output;
  double tol_mm = 0.001;
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")(
      "output,o", po::value(&output), "the stock to write (atomically): FILE.zmap, every cell's height; any other name, a binary STL")(
      "stock", po::value(&s.stock), "box:X0,Y0,Z0,X1,Y1,Z1 (mm, work frame), an STL/STEP/IGES solid or a .zmap (default: config stock)")(
      "tool-file", po::value(&s.tool_file), "tool library (YAML, Fusion 360 JSON or LinuxCNC .tbl)")(
      "cell-mm", po::value(&s.cell_mm)->default_value(0.05, "0.05"), "Z-map cell size, mm")(
      "mesh-tolerance", po::value(&tol_mm)->default_value(0.001, "0.001"),
      "how far the STL's surface may pass from a cell's height where triangles are merged, mm (0: only exactly flat or planar cells)");
  add_stock_from_options(desc, s.stock_from);
  add_read_options(desc, s.read);
  std::vector<std::string> none;
  parse_with_files(args, desc, none, 0);
  if (help) {
    print_help(io.out, "deflex stock [--stock S] [--stock-from A.nc [--stock-from-tools LIB] ...] -o rest.zmap|rest.stl",
               "Builds the stock - a box or a solid, then each earlier program swept into it\n"
               "with its own tools from the tool library, geometry only - and writes it.\n"
               "-o rest.zmap: the Z-map itself, every cell's height exactly, compressed\n"
               "(docs/zmap.md); `--stock rest.zmap` of a later run reads it back in well\n"
               "under a second. Any other name: a closed binary STL for a viewer or a CAM\n"
               "system: the top through the cell centres, walls, a flat bottom 0.01 mm under\n"
               "the stock's base. Flat regions are merged into large triangles within\n"
               "--mesh-tolerance; the surface is within it of every cell's height.\n",
               desc);
    return 0;
  }
  if (output.empty() || output == "-")
    throw Error(ErrorKind::settings, "stock: -o FILE.zmap or -o FILE.stl is required (both are binary)");
  const job::StockFile f = job::write_rest_stock(s, output, tol_mm, io);
  const stock::GridSpec& g = f.grid;
  if (f.zmap) {
    io.err << output << ": " << g.nx << " x " << g.ny << " cells of " << g.cell_mm << " mm, every height as computed\n";
    return 0;
  }
  io.err << output << ": " << f.triangles << " triangles (" << 2.0 * (g.nx + 1.0) * (g.ny + 1.0)
         << " for the full grid of " << g.nx << " x " << g.ny << " cells of " << g.cell_mm << " mm), within "
         << tol_mm << " mm of every cell\n";
  return 0;
}

}  // namespace deflex::cli
