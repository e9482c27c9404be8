#include "deflex/compensate/pipeline.hpp"

#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <ostream>

#include "deflex/compensate/pieces.hpp"
#include "deflex/engage/path.hpp"
#include "internal.hpp"

namespace deflex::compensate {

namespace {

// The design normals of a program in pieces: they read it on their own, a
// window ahead of the pieces.
struct AheadNormals {
  explicit AheadNormals(const PipelineInput& in)
      : ahead(in.path, in.lines_per_read, in.interp, in.motions_per_piece, in.fix, in.settings->threads != 1),
        normals(
            [this](std::vector<interp::Motion>& more) {
              std::unique_ptr<ProgramPiece> p = ahead.next();
              if (p) more.insert(more.end(), p->motions.begin(), p->motions.end());
              return p != nullptr;
            },
            in.physics->part, in.physics->tools, path_of(*in.settings), in.settings->part_reach_mm,
            [s = in.settings](const interp::Motion& m) { return tool_id(m, *s); }) {}
  static engage::PathOptions path_of(const Settings& s) {
    engage::PathOptions po;
    po.cl_spacing_mm = s.cl_spacing_mm;
    return po;
  }
  PieceCutter ahead;
  DesignNormals normals;
};

}  // namespace

std::size_t simulate_in_pieces(const PipelineInput& in) {
  PieceCutter cut(in.path, in.lines_per_read, in.interp, in.motions_per_piece, in.fix, in.settings->threads != 1);
  AheadNormals an(in);
  std::unique_ptr<stock::ZMap> map;
  const Physics& ph = *in.physics;
  if (ph.consumable_stock && ph.consumable_stock == ph.stock)
    map = std::make_unique<stock::ZMap>(std::move(*ph.consumable_stock));
  Simulation sim(ph, *in.settings, an.normals, in.sinks.nominal, std::move(map), in.progress, in.total_motions);
  std::size_t before = 0, n = 0;
  while (std::unique_ptr<ProgramPiece> p = cut.next()) {
    an.normals.forget_before(before);
    before = p->first_motion;
    sim.add(p->motions);
    n += p->motions.size();
  }
  sim.finish();
  return n;
}

namespace {

// --feed-limit in pieces: the program as written simulated first, on a copy
// of the stock, its points to the nominal sink; a cutting block whose peak
// force, torque or power exceeds its limit gets its feed lowered as
// Compensation does on the whole program (detail::lowered_feed). Returns the
// lowered feeds by motion index (few) and their lines in program order.
struct FeedPlan {
  std::map<std::size_t, double> lowered;
  std::vector<std::uint32_t> lines;
};

FeedPlan plan_feeds(const PipelineInput& in) {
  const Physics& ph = *in.physics;
  const Settings& s = *in.settings;
  PieceCutter cut(in.path, in.lines_per_read, in.interp, in.motions_per_piece, in.fix, in.settings->threads != 1);
  AheadNormals an(in);
  struct Open {  // a motion whose samples may still come
    std::size_t index;
    double feed;
    bool can_lower;
    std::uint32_t line;
    double share = 1;  // the least Point::feed_share of its points
  };
  std::deque<Open> open;
  FeedPlan plan;
  auto settle = [&](std::size_t below) {
    for (; !open.empty() && open.front().index < below; open.pop_front()) {
      const Open& o = open.front();
      if (!o.can_lower || o.share >= 1) continue;
      plan.lowered[o.index] = detail::lowered_feed(o.feed, o.share);
      plan.lines.push_back(o.line);
    }
  };
  std::unique_ptr<stock::ZMap> copy;
  if (ph.stock) copy = std::make_unique<stock::ZMap>(detail::clone(*ph.stock));
  Simulation sim(ph, s, an.normals,
                 [&](const Point& p) {
                   // Samples come in order: the motions before are done, and this
                   // one is the first still open.
                   settle(p.motion);
                   if (!open.empty() && open.front().index == p.motion)
                     open.front().share = std::min(open.front().share, p.feed_share);
                   if (in.sinks.nominal) in.sinks.nominal(p);
                 },
                 std::move(copy), in.progress, in.total_motions);
  std::size_t before = 0;
  while (std::unique_ptr<ProgramPiece> p = cut.next()) {
    an.normals.forget_before(before);
    before = p->first_motion;
    for (std::size_t i = 0; i < p->motions.size(); ++i) {
      const interp::Motion& m = p->motions[i];
      open.push_back({p->first_motion + i, m.feed_mm_per_min, m.plain && m.kind != interp::MotionKind::rapid, m.line});
    }
    sim.add(p->motions);
  }
  sim.finish();
  settle(std::numeric_limits<std::size_t>::max());
  return plan;
}

}  // namespace

PipelineResult compensate_in_pieces(const PipelineInput& in, std::ostream& out) {
  const bool limit = in.settings->feed_limit_N > 0;
  if (limit && in.settings->gain == 0.0)
    throw Error(ErrorKind::internal, "compensate: a gain of 0 with a feed limit reads the program whole");
  FeedPlan plan;
  if (limit) plan = plan_feeds(in);
  // With a plan the mirror pass runs alone, at the planned feeds.
  Settings s = *in.settings;
  s.feed_limit_N = 0;
  PieceCutter cut(in.path, in.lines_per_read, in.interp, in.motions_per_piece, in.fix, in.settings->threads != 1);
  AheadNormals an(in);
  DesignNormals& normals = an.normals;
  Compensation comp(*in.physics, s, normals, in.sinks, in.progress, in.total_motions, !limit);
  WriteState ws;
  ReadBack read_back(in.interp);
  process::MachiningClock clock(in.limits);
  PipelineResult res;
  std::size_t before = 0;  // first motion of the piece before
  std::vector<double> planned;
  while (std::unique_ptr<ProgramPiece> p = cut.next()) {
    ++res.pieces;
    // Only the last samples of the piece before may still come.
    normals.forget_before(before);
    before = p->first_motion;
    const std::vector<bool> split_ok = splittable(p->text, p->motions);
    if (limit) {
      planned.resize(p->motions.size());
      for (std::size_t i = 0; i < p->motions.size(); ++i) {
        const auto it = plan.lowered.find(p->first_motion + i);
        planned[i] = it == plan.lowered.end() ? p->motions[i].feed_mm_per_min : it->second;
      }
    }
    const Result r = comp.add(p->motions, movable(p->motions), &split_ok, limit ? &planned : nullptr);
    if (in.on_piece) in.on_piece(r);
    ws.first_line = p->first_line;
    ws.last_line = p->last_line;
    ws.inch_after = p->inch_after;
    WriteStats w;
    const std::vector<double>* feeds = limit ? &r.feeds_mm_per_min : nullptr;
    const std::string text = apply_offsets(p->text, in.interp.dialect, r.motions, r.offsets, &w, &r.inserted,
                                           feeds, &ws);
    res.written.numbers_changed += w.numbers_changed;
    res.written.words_inserted += w.words_inserted;
    res.written.blocks_inserted += w.blocks_inserted;
    res.written.feeds_changed += w.feeds_changed;
    // The check sees the piece numbered from 1, the written one too, read with
    // the state the written pieces before left.
    const std::uint32_t base = p->first_line - 1;
    std::vector<interp::Motion> om = r.motions;
    for (interp::Motion& m : om) m.line -= base;
    gcode::Tape tape = p->tape;
    const gcode::Program written(SourceText(p->text.source().name() + " (compensated)", text, 1), tape);
    safety_check(p->own, om, written, in.interp, movable(r.motions), s.max_offset_mm, &r.inserted, feeds,
                 &read_back, base);
    out << text;
    for (std::size_t i = 0; i < r.motions.size(); ++i)
      clock.add(r.motions[i], limit ? r.feeds_mm_per_min[i] : std::numeric_limits<double>::quiet_NaN());
  }
  res.totals = comp.finish();
  res.totals.feed_lowered_lines = std::move(plan.lines);
  res.time = clock.finish();
  return res;
}

}  // namespace deflex::compensate
