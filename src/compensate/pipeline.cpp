#include "deflex/compensate/pipeline.hpp"

#include <ostream>

#include "deflex/compensate/pieces.hpp"
#include "deflex/engage/path.hpp"

namespace deflex::compensate {

namespace {

// The design normals of a program in pieces: they read it on their own, a
// window ahead of the pieces.
struct AheadNormals {
  explicit AheadNormals(const PipelineInput& in)
      : ahead(in.path, in.lines_per_read, in.interp, in.motions_per_piece, in.fix),
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
  PieceCutter cut(in.path, in.lines_per_read, in.interp, in.motions_per_piece, in.fix);
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

PipelineResult compensate_in_pieces(const PipelineInput& in, std::ostream& out) {
  const Settings& s = *in.settings;
  PieceCutter cut(in.path, in.lines_per_read, in.interp, in.motions_per_piece, in.fix);
  AheadNormals an(in);
  DesignNormals& normals = an.normals;
  Compensation comp(*in.physics, s, normals, in.sinks, in.progress, in.total_motions);
  WriteState ws;
  ReadBack read_back(in.interp);
  process::MachiningClock clock(in.limits);
  PipelineResult res;
  std::size_t before = 0;  // first motion of the piece before
  while (std::unique_ptr<ProgramPiece> p = cut.next()) {
    ++res.pieces;
    // Only the last samples of the piece before may still come.
    normals.forget_before(before);
    before = p->first_motion;
    const std::vector<bool> split_ok = splittable(p->text, p->motions);
    const Result r = comp.add(p->motions, movable(p->motions), &split_ok);
    if (in.on_piece) in.on_piece(r);
    ws.first_line = p->first_line;
    ws.last_line = p->last_line;
    WriteStats w;
    const std::string text = apply_offsets(p->text, in.interp.dialect, r.motions, r.offsets, &w, &r.inserted,
                                           nullptr, &ws);
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
    safety_check(p->own, om, written, in.interp, movable(r.motions), s.max_offset_mm, &r.inserted, nullptr,
                 &read_back, base);
    out << text;
    for (const interp::Motion& m : r.motions) clock.add(m);
  }
  res.totals = comp.finish();
  res.time = clock.finish();
  return res;
}

}  // namespace deflex::compensate
