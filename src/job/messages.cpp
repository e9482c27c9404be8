// What a compensation says of itself on the way (internal.hpp): the moves
// it leaves as written and why, the points they leave outside the
// tolerance, lowered feeds, capped offsets, arcs, convergence.
#include <cstdio>

#include "deflex/diag/plural.hpp"
#include "internal.hpp"

namespace deflex::job::detail {

namespace {

// The moves of a reason deflex leaves as written, and whether that may change.
std::string moves_of(interp::Fixed why) {
  switch (why) {
    case interp::Fixed::cutter_comp:
      return "cutter compensation start-up moves (G41/G42 entries), and moves under it in G91 or with G90.1 arcs";
    case interp::Fixed::incremental: return "incremental (G91) arcs with absolute centres (G90.1), not compensated";
    case interp::Fixed::subprogram: return "moves in subprograms that run more than once";
    case interp::Fixed::canned_cycle: return "canned-cycle moves (drilling is not a surface)";
    case interp::Fixed::machine_frame: return "moves in machine coordinates (G53/G28/G30)";
    case interp::Fixed::block_delete: return "block-delete '/' moves (run or not at the operator's switch)";
    case interp::Fixed::no_normal:
      return "points whose surface normal the program does not determine (a ball end without {part}: the first "
             "or last pass without two passes beside it within 8 mm, a single pass, points off a smooth surface; "
             "give the part model with {part})";
    case interp::Fixed::held:
      return "moves ending where a block deflex cannot re-target starts (a canned cycle, G28/G30/G53, a subprogram "
             "that runs more than once, a change of work offset, an arc that stays)";
    case interp::Fixed::gouge:
      return "moves the gouge check finds cutting into the part ({part}): the program gouges there, and compensating "
             "would move the gouge";
    default: return std::string("moves: ") + interp::to_string(why);
  }
}

// The subprogram of the first point left alone in one, its calls and the
// largest error left: the same blocks run at each call, so deflex cannot
// give each pass its own compensation in place.
std::string subprogram_calls(const Run& j, const report::RunFigures::LeftAlone& l) {
  const interp::CallStructure& c = *j.calls;
  const std::uint32_t o_line = l.first_line < c.sub_of.size() ? c.sub_of[l.first_line] : 0;
  std::string calls;
  auto it = c.calls.find(o_line);
  if (it != c.calls.end())
    for (std::uint32_t line : it->second) calls += (calls.empty() ? "" : ", ") + std::to_string(line);
  char buf[96];
  std::snprintf(buf, sizeof buf, "; the largest error left %.4f mm", l.largest_mm);
  return (o_line ? " (the first here, in " + c.name_of(o_line, j.prog) + ", called at line" +
                       (it != c.calls.end() && it->second.size() > 1 ? "s " : " ") + calls + ")"
                 : std::string(" (the first here)")) +
         buf + "; {expand_subprograms} writes each call inline and compensates each pass";
}

}  // namespace

void print_left_alone(const Run& j, const report::RunFigures& f, Io& io) {
  for (const auto& [why, l] : j.left_moves)
    io.info() << j.prog.source().name() << ": note: " << l.blocks << (l.blocks == 1 ? " executed block stays" : " executed blocks stay")
              << " as written: " << io.named(moves_of(why)) << "; the first at line " << l.first_line << "\n";
  if (f.left_alone.empty()) return;
  std::vector<std::uint32_t> lines;
  for (const auto& [why, l] : f.left_alone) lines.push_back(l.first_line);
  const auto text = lines_of_file(j, lines);
  Diagnostics diags = io.diagnostics(0);
  for (const auto& [why, l] : f.left_alone) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s outside +-%.4f mm %s left as programmed on ", plural(l.points, "point").c_str(),
                  j.settings.tolerance_mm, l.points == 1 ? "is" : "are");
    std::string more = " (the first here)";
    if (why == interp::Fixed::subprogram && j.calls) more = subprogram_calls(j, l);
    diags.report(Severity::warning, text.at(l.first_line), l.first_line, 1, buf + moves_of(why) + more + " [left_alone]");
  }
}

report::Json left_alone_json(const report::RunFigures& f) {
  report::Json a = report::Json::array();
  for (const auto& [why, l] : f.left_alone)
    a.push_back({{"reason", interp::to_string(why)}, {"points", l.points}, {"first_line", l.first_line},
                 {"largest_error_mm", l.largest_mm}});
  return a;
}

// The warnings and notes of the mirror pass: lowered feeds, plausibility,
// capped offsets, linearised and non-uniform arcs, convergence.
void print_compensation(const Run& j, const compensate::Result& r, const compensate::Plausibility& pl, Io& io) {
  if (!r.feed_lowered_lines.empty()) {
    std::string lines;
    for (std::size_t i = 0; i < r.feed_lowered_lines.size() && i < 12; ++i)
      lines += (i ? ", " : "") + std::to_string(r.feed_lowered_lines[i]);
    if (r.feed_lowered_lines.size() > 12) lines += ", ...";
    io.info() << j.prog.source().name() << ": note: feed lowered on " << plural(r.feed_lowered_lines.size(), "block")
           << " to keep the peak force under " << j.settings.feed_limit_N << " N"
           << (j.physics.spindle.set ? " and the spindle's power and torque within its S1 rating" : "") << " ("
           << (r.feed_lowered_lines.size() == 1 ? "line " : "lines ") << lines << ")\n";
  }
  print_plausibility(j, pl, io);
  if (!r.capped_lines.empty() && !pl.find("offset_cap")) {
    std::string lines;
    for (std::size_t i = 0; i < r.capped_lines.size() && i < 12; ++i) lines += (i ? ", " : "") + std::to_string(r.capped_lines[i]);
    if (r.capped_lines.size() > 12) lines += ", ...";
    io.err << j.prog.source().name() << ": warning: the offset was capped at max_offset_mm = " << j.settings.max_offset_mm
           << " mm on " << plural(r.capped_lines.size(), "point") << " ("
           << (r.capped_lines.size() == 1 ? "line " : "lines ") << lines << ")\n";
  }
  if (r.linearised_arcs)
    io.info() << j.prog.source().name() << ": note: " << plural(r.linearised_arcs, "arc")
           << (r.linearised_arcs == 1 ? " whose compensation varies along it was" : " whose compensation varies along them were")
           << " linearised (G1 chords within "
           << j.settings.chord_tol_mm << " mm of the arc; the arc block keeps the last piece)\n";
  for (std::uint32_t l : r.nonuniform_arcs)
    io.err << j.prog.source().name() << ":" << l
           << ":1: warning: the compensation varies along this arc by more than the tolerance; it is kept as a translated arc\n";
  if (!r.converged)
    io.err << j.prog.source().name() << ": warning: the mirror iteration did not converge in " << plural(r.iterations, "update")
           << " at " << plural(r.unconverged_points, "point") << " (largest change left " << r.last_change_mm
           << " mm); the best iterate is written\n";
}

}  // namespace deflex::job::detail
