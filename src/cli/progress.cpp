// What every command prints beside its result: the progress line, the
// machining time, the command line for a report's provenance.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "common.hpp"
#include "terminal_line.hpp"
#include "deflex/diag/parallel_trace.hpp"
#include "deflex/report/summary.hpp"
#include "deflex/stock/sweep.hpp"

namespace deflex::cli {

namespace {

// The Z-map work of a stage (stock::sweep_work): what a reader can compare
// with other engagement simulators, whatever the machine.
std::string sweep_work_since(const stock::SweepWork& before, std::chrono::duration<double> took) {
  const stock::SweepWork now = stock::sweep_work();
  const double cells = static_cast<double>(now.cells - before.cells);
  if (cells <= 0) return "";
  char buf[160];
  std::snprintf(buf, sizeof buf, "; Z-map: %.4g cells updated by %llu moves (%.3g cells/s)", cells,
                static_cast<unsigned long long>(now.moves - before.moves), cells / std::max(took.count(), 1e-9));
  return buf;
}

// The stage's available parallelism from the trace of its task graph.
std::string parallelism_since(const diag::ParallelTotals& before) {
  const diag::ParallelTotals now = diag::parallel_totals();
  const double work = now.work_s - before.work_s, path = now.path_s - before.path_s;
  if (now.loops == before.loops || !(path > 0)) return "";
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "deflex: parallelism: work %.1f s over a critical path of %.1f s: %.2f (%llu parallel loops; "
                "%.1f s serial)\n",
                work, path, work / path, static_cast<unsigned long long>(now.loops - before.loops),
                now.serial_s - before.serial_s);
  return buf;
}

}  // namespace

compensate::Progress progress_for(Io& io) {
  const bool shown = !io.quiet && (io.progress == ProgressWhen::always ||
                                   (io.progress == ProgressWhen::automatic && io.err_is_terminal));
  if (!shown && !io.verbose) return {};
  using Clock = std::chrono::steady_clock;
  struct State {
    std::string stage;
    Clock::time_point start;
    int decile = -1;
    stock::SweepWork work;  // at the stage's start
    diag::ParallelTotals loops;
  };
  auto st = std::make_shared<State>();
  // On a terminal one line redrawn in place; elsewhere (a log) a line per 10%.
  const bool redraw = io.line != nullptr;
  return [&io, st, shown, redraw](const std::string& stage, double f) {
    const Clock::time_point now = Clock::now();
    if (stage != st->stage) {
      if (shown && redraw) io.line->show("");
      if (io.verbose && !st->stage.empty()) {
        char done[32];
        std::snprintf(done, sizeof done, "%.1f s", std::chrono::duration<double>(now - st->start).count());
        io.err << "deflex: " << st->stage << " done in " << done << sweep_work_since(st->work, now - st->start)
               << "\n";
        // One thread of control only: compensate simulates the program as
        // written on a second one (diag/parallel_trace.hpp).
        if (st->stage == "simulating") io.err << parallelism_since(st->loops);
      }
      st->stage = stage;
      st->start = now;
      st->work = stock::sweep_work();
      st->loops = diag::parallel_totals();
      st->decile = -1;
    }
    if (!shown || stage.empty()) return;  // end_progress(): the last stage closed
    const double s = std::chrono::duration<double>(now - st->start).count();
    char buf[160];
    const int n = std::snprintf(buf, sizeof buf, "deflex: %s %3.0f%%, %s elapsed", stage.c_str(), 100.0 * f,
                                report::clock(s).c_str());
    std::string text(buf, static_cast<std::size_t>(std::max(0, n)));
    // The rest at the rate so far, once there is a rate to go by.
    if (f > 0.01 && f < 1 && s > 1) text += ", about " + report::clock(s * (1 - f) / f) + " left";
    if (redraw) {
      io.line->show(text);
    } else if (const int d = static_cast<int>(10 * f); d != st->decile) {
      st->decile = d;
      io.err << text << "\n";
    }
  };
}

void time_line(Io& io, const process::MachiningTime& before, const process::MachiningTime& after) {
  std::ostream& o = io.info();
  // One form for the line: h:mm:ss for all its times when one reaches an hour.
  const bool h = report::clock_has_hours(std::max(before.program.total_s, after.program.total_s));
  o << "  machining time:              " << report::clock(before.program.total_s, h) << " (cutting "
    << report::clock(before.program.cutting_s, h) << ", rapids " << report::clock(before.program.rapid_s, h) << ")";
  if (std::fabs(after.program.total_s - before.program.total_s) >= 0.5)
    o << ", compensated " << report::clock(after.program.total_s, h);
  o << (h ? " [h:mm:ss" : " [m:ss") << ", axis limits of the machine profile]\n";
}

std::string command_of(const char* cmd, const std::vector<std::string>& args) {
  std::string c = std::string("deflex ") + cmd;
  for (const std::string& w : args) {
    const bool plain = !w.empty() && w.find_first_not_of(
        "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.,:/=+@%") == std::string::npos;
    std::string q = "'";
    for (char ch : w) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    c += " " + (plain ? w : q + "'");
  }
  return c;
}

}  // namespace deflex::cli
