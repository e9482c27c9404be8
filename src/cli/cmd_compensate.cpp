// deflex compensate | simulate: the product. The options into the job's
// settings, the job API (deflex/job/job.hpp) run, its figures printed.
#include <cstdio>

#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/job/job.hpp"

namespace deflex::cli {
namespace {

const char* kCompensateHelp =
    "Simulates the cut of the program on the stock - engagement of the cutter in the\n"
    "material as cut so far, mean cutting force over a revolution, deflection of tool,\n"
    "holder, spindle and machine C(h)F - and moves each cutting point by the mirror\n"
    "method (P_comp = P_nom - gain e n, iterated to a fixed point) so that the deflected\n"
    "tool lands on the programmed surface. The fixed point is found in one pass in\n"
    "program order: each move end is solved (secant steps, one engagement evaluation\n"
    "each) with the moves before it already cut where they will run.\n"
    "Only the X/Y/Z (and a re-aimed arc's I/J/K) numbers of cutting blocks change (an\n"
    "axis word is added where a modal value would carry an offset into the next\n"
    "block; a G1/G2/G3 in G91 gets the increments that reach the compensated\n"
    "points); rapids, canned cycles, subprograms that run more than once (see\n"
    "--expand-subprograms), G41/G42 start-up moves, and points predicted inside\n"
    "+-tolerance stay as programmed. Under G41/G42 deflex simulates the tool centre's\n"
    "path (as `deflex path --centre` prints it, the D radius from the profile's\n"
    "tool_offsets or the tool library) and moves the programmed contour, so that the\n"
    "control's own offset lands the tool where the compensation means; the D words\n"
    "and the G41/G42 blocks stay as written. A long G1 whose error varies\n"
    "along it gets G1 blocks inserted before it; an arc whose compensation varies is\n"
    "linearised (G1 chords within 1 um, the arc block keeps the last piece) when its\n"
    "block has its own G2/G3 and I/J/K, else moved whole with a warning. Offsets are\n"
    "capped at the machine profile's max_offset_mm. The written program is read back\n"
    "and checked against the original before anything is written; with --gain 0 the\n"
    "output is the input. A long program is read, compensated, written and checked\n"
    "in pieces of 16,384 lines, so memory does not grow with it; --report writes\n"
    "points.csv as the points come and keeps what report.html draws on disk.\n"
    "--report DIR writes report.html (open it in a browser: provenance, summary, the\n"
    "surface in 3D and top views coloured by the error as written and compensated,\n"
    "plots of force, deflection, engagement and cusp along the path, the worst lines),\n"
    "points.csv (one row per CL point), flank_profile.csv and summary.json.\n"
    "--feed-limit N also lowers F (by the ratio of N to the predicted peak force) on\n"
    "cutting blocks whose peak force would exceed N, restoring the programmed F after.\n"
    "The surface normal (points.csv normal_source) comes, best first, from the part\n"
    "model (--part): the cutter's contact with the design surface at the programmed\n"
    "tip, where it lies within reach; else, for a ball end, from the tip surface\n"
    "fitted through the CL points of the same and the adjacent passes, where they\n"
    "determine it (not on a lone pass, nor on an edge pass without two passes\n"
    "beside it: such points are left as programmed and counted in the [left_alone]\n"
    "warning, normal_source undetermined); for flat and bull-nose ends from the\n"
    "tool and the travel: the wall of a flank cut, else the normal to the travel\n"
    "in its vertical plane (blind to a slope across the feed).\n"
    "Where the holder (the machine profile's holder:), the neck or the shank above\n"
    "the flutes would stand more than 0.01 mm in the stock (the --stock-from programs'\n"
    "rest stock included), the program is in error: exit 1, nothing written, an error\n"
    "at the first such line with the depth and the least stick-out (holder) or reach\n"
    "(neck, shank) that clears it. `deflex check --stock` finds the same without the\n"
    "forces.\n"
    "Every cutting point is also held against the machine: its spindle power and\n"
    "torque against the profile's spindle: S1 curve, and its a_p against the\n"
    "zero-order stability limit of its own engagement and S from the tool tip's\n"
    "modes (chatter; the profile's dynamics: damping_ratio, default 0.03): a\n"
    "warning at the line where either is passed (`deflex stability` draws the\n"
    "lobes; docs/stability.md).\n";

void summary_line(Io& io, const char* what, const report::ErrorStats& s, double tol) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "  %-28s max %.4f mm, rms %.4f mm, %.1f%% of %s outside +-%.4f mm\n", what,
                s.max_abs, s.rms, 100.0 * s.share_out, plural(s.points, "point").c_str(), tol);
  io.info() << buf;
}

// The figures of a compensation: the counts, the predicted error before and
// after, the machining time, what the run used.
void print_compensated(const job::Run& j, const job::CompensateResult& c, Io& io) {
  const compensate::Result& r = c.result;
  const compensate::WriteStats& ws = c.written;
  io.info() << j.prog.source().name() << ": " << plural(r.compensated_points, "point") << " compensated, "
            << plural(ws.numbers_changed, "number") << " changed, " << plural(ws.words_inserted, "axis word") << " added, "
            << plural(ws.blocks_inserted, "block") << " inserted to split moves; mirror: "
            << plural(r.evaluations, "engagement evaluation") << ", at most " << plural(r.iterations, "update")
            << " per point" << (r.converged ? "" : " (not converged)") << "\n";
  const double tol = j.settings.tolerance_mm;
  summary_line(io, "predicted error, as written:", c.figures.error_as_written, tol);
  summary_line(io, "predicted error, compensated:", c.figures.error, tol);
  time_line(io, c.time_as_written, c.time_compensated);
  io.info() << "  " << c.used.text << "\n";
}

// The figures of a simulation: one line on stdout, the time and what it used.
void print_simulated(const job::Run& j, const job::SimulateResult& s, Io& io) {
  const report::ErrorStats& st = s.figures.error;
  char buf[300];
  std::snprintf(buf, sizeof buf,
                "%s: %s%s: surface error max %.4f mm, rms %.4f mm, %.1f%% outside +-%.4f mm "
                "(undercut up to %.4f, overcut up to %.4f mm)\n",
                j.prog.source().name().c_str(), plural(st.points, "CL point").c_str(),
                j.given.reference.empty() ? "" : " against the reference", st.max_abs, st.rms, 100.0 * st.share_out,
                j.settings.tolerance_mm, st.max_under, -st.max_over);
  io.out << buf;
  time_line(io, s.time, s.time);
  io.info() << "  " << s.used.text << "\n";
}

}  // namespace

int cmd_compensate(const std::vector<std::string>& args, Io& io) {
  job::Settings s;
  bool help = false;
  std::string job_file;
  po::options_description desc("options");
  describe(desc, s, help, job_file, true);
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
  if (!job_file.empty()) job::apply_job_file(job_file, s, files);
  if (help) {
    print_help(io.out,
               "deflex compensate IN [-o OUT] [--machine M] [--tool-file F] [--tool ID] [--material M | --kt K --kr K "
               "--ka K [--kte K --kre K --kae K]] [--stock box:X0,Y0,Z0,X1,Y1,Z1 | --stock FILE] [--tolerance MM] "
               "[--gain G] [--report DIR]",
               kCompensateHelp, desc);
    return 0;
  }
  if (files.empty()) throw Error(ErrorKind::settings, "compensate: a program IN (or - for stdin) is required");
  s.program = files[0];
  ProgressLine progress(io);
  job::Run run = job::open(s, job::Purpose::compensate, io, &progress);
  const job::CompensateResult c = job::compensate(run, io.out, io, &progress, command_of("compensate", args));
  print_compensated(run, c, io);
  return 0;
}

int cmd_simulate(const std::vector<std::string>& args, Io& io) {
  job::Settings s;
  bool help = false;
  std::string job_file;
  po::options_description desc("options");
  describe(desc, s, help, job_file, false);
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
  if (!job_file.empty()) job::apply_job_file(job_file, s, files);
  if (help) {
    print_help(io.out,
               "deflex simulate IN [--reference ORIGINAL] [--report DIR] (options as deflex compensate)",
               "Predicts the surface error of a program without changing it: where the deflected\n"
               "tool lands against the programmed path, or with --reference, against the path of\n"
               "another program with the same blocks (the design intent): that is how a\n"
               "compensated program is judged. A summary goes to stdout; --report DIR writes\n"
               "report.html, points.csv and summary.json. A holder, neck or shank that would\n"
               "run into the stock is an error, as in compensate: exit 1, no report.\n",
               desc);
    return 0;
  }
  if (files.empty()) throw Error(ErrorKind::settings, "simulate: a program IN (or - for stdin) is required");
  s.program = files[0];
  ProgressLine progress(io);
  job::Run run = job::open(s, job::Purpose::simulate, io, &progress);
  const job::SimulateResult r = job::simulate(run, io, &progress, command_of("simulate", args));
  print_simulated(run, r, io);
  return 0;
}

}  // namespace deflex::cli
