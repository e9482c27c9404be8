// deflex path | check | rewrite: read a program, interpret it, report
// (job::path, job::check, job::rewrite); here the options and the printing.
#include "common.hpp"

#include <algorithm>
#include <charconv>
#include <string_view>

#include "deflex/diag/plural.hpp"
#include "deflex/job/check.hpp"
#include "deflex/job/program.hpp"
#include "deflex/report/held_text.hpp"
#include "deflex/report/json.hpp"
#include "deflex/report/text_out.hpp"
#include "deflex/writer/temp_files.hpp"

namespace deflex::cli {
namespace {

// Formats the motions as they come and holds the text until the run says
// whether the program has an error (job::HoldingSink).
class PathPrinter : public job::HoldingSink {
 public:
  PathPrinter(std::ostream& o, bool lines, bool centre) : o_(o), lines_(lines), centre_(centre) {}
  void motion(const interp::Motion& m) override {
    // Under G41/G42 the motion is the tool centre's; the program's own point
    // is its contour end, and a corner piece has none.
    if (!centre_ && m.corner) return;
    // The line made here and appended at once (TextOut::put_fixed).
    char line[24 + 8 + 3 * (1 + report::TextOut::kFixedBytes) + 1];
    char* p = line;
    if (lines_) {
      p = std::to_chars(p, p + 24, m.line).ptr;
      *p++ = ' ';
    }
    const std::string_view kind = interp::to_string(m.kind);
    p = std::copy(kind.begin(), kind.end(), p);  // G0 .. G3
    for (double v : centre_ || !m.comp ? m.end_mm : m.contour_end_mm) {
      *p++ = ' ';
      p = report::TextOut::put_fixed(p, v, 6);
    }
    *p++ = '\n';
    out_ << std::string_view(line, static_cast<std::size_t>(p - line));
  }
  void finish(bool no_error) override {
    out_.flush();
    if (!no_error || !held_.size()) return;
    // Standard output is written from here on: a signal from then cuts it
    // short (the handler says so), before it leaves nothing.
    writer::temp_files::streaming_stdout();
    held_.write_to(o_);
  }
 private:
  std::ostream& o_;
  report::HeldText held_;
  report::TextOut out_{held_};
  bool lines_, centre_;
};

const char* kCheckHelp =
    "Reads and interprets the program as the control would and reports every problem\n"
    "as FILE:LINE:COL: error|warning: MESSAGE with the source line, on stderr. With a\n"
    "machine profile, every motion (arcs by their extent) is checked against the\n"
    "travel limits of the tool tip in machine coordinates (work offsets from the\n"
    "profile; tool length not included). With --part, the gouge check: at every CL\n"
    "point of every cutting move (0.5 mm apart) the programmed cutter is measured\n"
    "against the part model, and where it cuts into the part or stands off a face of\n"
    "it by more than --part-gap a warning names the lines and the largest gap (no\n"
    "stock, no simulation). With --stock (and --stock-from, the earlier programs' rest\n"
    "stock), the holder and shank check: the program swept through the stock as\n"
    "compensate sweeps it (no forces), and wherever the holder (the machine profile's\n"
    "holder:), the neck or the shank above the flutes would stand more than 0.01 mm\n"
    "in the material, an error at the first such line with the depth and the least\n"
    "stick-out (holder) or reach (neck, shank) that clears it: the same errors\n"
    "compensate and simulate stop on. A summary goes to stdout. Exit 0 when there is\n"
    "no error, 1 otherwise.\n";

const char* kPathHelp =
    "Prints one line per tool motion: KIND X Y Z, where KIND is G0, G1, G2 or G3 and\n"
    "X Y Z is the end point in mm (6 decimals) in the active work coordinate frame\n"
    "(G54..., as LinuxCNC's rs274 prints it). Canned cycles are expanded into their\n"
    "G0/G1 moves; G28/G30 print their intermediate and reference moves. Programs in\n"
    "inch are converted to mm. Points under G41/G42 are the programmed contour; with\n"
    "--centre they are the tool centre's path, as the control computes it from the D\n"
    "register's radius (the machine profile's tool_offsets, else the tool library's\n"
    "T<n> diameter / 2 for D<n>): a move's end where the offset elements meet, and the\n"
    "arcs (linuxcnc) or points (fanuc) the control adds round outside corners. Numbers without a decimal point follow the dialect's rule: fanuc reads\n"
    "X1000 as 1.000 mm (least input increment), linuxcnc as 1000 mm. A program with\n"
    "an error (or more executed blocks than --max-blocks) prints no path, only the\n"
    "diagnostics on stderr, and exits 1.\n";

}  // namespace

int cmd_path(const std::vector<std::string>& args, Io& io) {
  job::PathSettings ps;
  bool lines = false, centre = false, help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")
                    ("lines", po::bool_switch(&lines), "put the source line number first")
                    ("centre", po::bool_switch(&centre), "under G41/G42, the tool centre's path (default: the programmed contour)")
                    ("tool-file", po::value(&ps.tool_file), "tool library for G41/G42 radii (default: config tool_file, else the installed samples/tools.yaml)");
  add_read_options(desc, ps.read);
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
  if (!files.empty()) ps.program = files[0];
  if (help) { print_help(io.out, "deflex path FILE [--dialect D] [--lines] [--centre]", kPathHelp, desc); return 0; }
  if (ps.program.empty()) throw Error(ErrorKind::settings, "path: a program FILE (or - for stdin) is required");
  PathPrinter printer(io.out, lines, centre);
  return job::path(ps, printer, io).errors ? static_cast<int>(Exit::input) : 0;
}

int cmd_check(const std::vector<std::string>& args, Io& io) {
  job::CheckSettings cs;
  std::string format = "text";
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")
                    ("format", po::value(&format)->default_value("text"), "summary on stdout: text or json")
                    ("tool-file", po::value(&cs.tool_file), "tool library for the gouge check (default: config tool_file, else the installed samples/tools.yaml)")
                    ("tool", po::value(&cs.tool), "with --part or --stock: check every cut with this tool (default: the program's T words)")
                    ("stock", po::value(&cs.stock), "the holder and shank check against this stock: box:X0,Y0,Z0,X1,Y1,Z1 (mm, work frame), "
                                                    "an STL/STEP/IGES solid, a .zmap (deflex stock) or auto[:MARGIN] (default: none, no such check)");
  add_stock_from_options(desc, cs.stock_from);
  desc.add_options()
      ("cell-mm", po::value(&cs.cell_mm)->default_value(0.05, "0.05"), "with --stock: Z-map cell size, mm")
      ("cl-spacing", po::value(&cs.cl_spacing_mm)->default_value(0.5), "with --stock: largest distance between CL points along a move, mm")
      ("threads", po::value(&cs.threads)->default_value(0), "with --stock: worker threads (0: all cores)");
  add_part_options(desc, cs.part);
  add_read_options(desc, cs.read);
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
  if (!files.empty()) cs.program = files[0];
  if (help) {
    print_help(io.out, "deflex check FILE [--machine M] [--dialect D] [--part P] [--stock S [--stock-from A.nc ...]] [--format text|json]",
               kCheckHelp, desc);
    return 0;
  }
  if (format != "text" && format != "json") throw Error(ErrorKind::settings, "--format takes text or json");
  if (cs.program.empty()) throw Error(ErrorKind::settings, "check: a program FILE (or - for stdin) is required");
  cs.keep_diagnostics = format == "json";  // only JSON lists them again
  const job::CheckResult r = job::check(cs, io);
  const interp::Stats& st = r.stats;
  if (format == "json") {
    io.out << report::line({{"file", r.name}, {"lines", st.lines}, {"blocks", st.blocks},
                            {"motions", st.motions}, {"compensable_motions", st.compensable},
                            {"cutter_comp_motions", st.cutter_comp_motions}, {"errors", r.errors},
                            {"warnings", r.warnings}, {"dialect", r.dialect}, {"machine", r.machine},
                            {"interpretation_stopped_at_line", st.stopped_line},
                            {"diagnostics", report::to_json(r.diagnostics)}});
  } else {
    io.out << r.name << ": " << plural(st.lines, "line") << ", " << plural(st.blocks, "block") << ", "
           << plural(st.motions, "motion") << " (" << st.compensable << " compensable), " << plural(r.errors, "error")
           << ", " << plural(r.warnings, "warning") << " [dialect " << r.dialect
           << (r.machine.empty() ? std::string() : ", machine " + r.machine) << "]\n";
  }
  return r.errors ? static_cast<int>(Exit::input) : 0;
}

int cmd_rewrite(const std::vector<std::string>& args, Io& io) {
  job::RewriteSettings rs;
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")
                    ("output,o", po::value(&rs.output), "write here (atomically) instead of stdout");
  add_read_options(desc, rs.read);
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
  if (!files.empty()) rs.program = files[0];
  if (help) {
    print_help(io.out, "deflex rewrite FILE [-o OUT] [--dialect D]",
               "Reads and interprets the program, then writes it back through deflex's writer\n"
               "with no change: the output is byte for byte the input (CRLF, missing final\n"
               "newline, '%', comments and all). This is the identity the compensation builds on;\n"
               "use it to check that deflex reads a program. A program with errors is not written.\n", desc);
    return 0;
  }
  if (rs.program.empty()) throw Error(ErrorKind::settings, "rewrite: a program FILE (or - for stdin) is required");
  job::rewrite(rs, io, [] { writer::temp_files::streaming_stdout(); });
  return 0;
}

}  // namespace deflex::cli
