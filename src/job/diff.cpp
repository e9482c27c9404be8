// job::diff() (diff.hpp).
#include "deflex/job/diff.hpp"

#include <algorithm>
#include <cmath>

#include "deflex/compensate/pairing.hpp"
#include "deflex/gcode/skeleton.hpp"
#include "deflex/job/setup.hpp"

namespace deflex::job {
namespace {

struct Side {
  gcode::Program prog;
  std::vector<compensate::LineFacts> lines;  // index = line number
};

// The program and what pairing needs of each line; F words are left out of
// the skeletons so that a block whose feed changed still pairs (and is listed
// as changed in more than coordinates).
Side read_side(const std::string& file, const Setup& s, Diagnostics& diags, Io& io) {
  Side side{gcode::Program(gcode::read_source(file, &io.in)), {}};
  side.lines.resize(side.prog.line_count() + 1);
  compensate::LineFactsSink sink;
  sink.lines = &side.lines;
  interp::interpret(side.prog, s.interp(), diags, sink);
  compensate::fill_line_text(side.prog, side.lines, true);
  return side;
}


// Lines between two paired ones: a block only in B that splits the next
// paired move (deflex compensate inserts them) is a coordinate change, its
// displacement its distance from that move; everything else is listed.
void note_unpaired(const Side& a, const Side& b, const compensate::LinePairing& pairing,
                   const std::vector<std::string>& files, std::uint32_t from_a, std::uint32_t to_a,
                   std::uint32_t from_b, std::uint32_t to_b, DiffResult& rep) {
  for (std::uint32_t l = from_a; l < to_a; ++l)
    rep.other.push_back(files[0] + ":" + std::to_string(l) + ": only in A: " + std::string(a.prog.source().line_text(l)));
  for (std::uint32_t l = from_b; l < to_b; ++l) {
    if (const std::uint32_t parent = pairing.parent_of_b[l]) {
      const compensate::V3 p(b.lines[l].path.end_mm[0], b.lines[l].path.end_mm[1], b.lines[l].path.end_mm[2]);
      const double d = (p - compensate::nearest_on(a.lines[parent].path, b.lines[l].path.end_mm)).norm();
      rep.splits.push_back({l, parent, d});
      rep.max_mm = std::max(rep.max_mm, d);
      continue;
    }
    rep.other.push_back(files[1] + ":" + std::to_string(l) + ": only in B: " + std::string(b.prog.source().line_text(l)));
  }
}

// Whether two paired lines differ in their F words (skeletons with F).
bool feed_differs(const Side& a, const Side& b, std::uint32_t la, std::uint32_t lb) {
  Diagnostics quiet(nullptr, 0);
  gcode::Block x, y;
  a.prog.lex(la, x, quiet);
  b.prog.lex(lb, y, quiet);
  return gcode::skeleton_hash(a.prog, x) != gcode::skeleton_hash(b.prog, y);
}

// One paired line: unchanged, moved, or changed in more than coordinates.
void compare_pair(const Side& a, const Side& b, const std::vector<std::string>& files, std::uint32_t la,
                  std::uint32_t lb, DiffResult& rep) {
  const compensate::LineFacts &x = a.lines[la], &y = b.lines[lb];
  std::string_view ta = a.prog.source().line_text(la), tb = b.prog.source().line_text(lb);
  // Same text but a different end point: an earlier change carried over by a
  // modal axis word. It moved, so it is listed, but it was not edited.
  if (ta == tb && x.motions == y.motions && (!x.motions || x.path.end_mm == y.path.end_mm)) return;
  if (x.motions != y.motions || x.path.kind != y.path.kind || (!x.motions && ta != tb) || feed_differs(a, b, la, lb)) {
    rep.other.push_back(files[0] + ":" + std::to_string(la) + " / " + files[1] + ":" + std::to_string(lb) +
                        ": changed in more than coordinates: '" + std::string(ta) + "' -> '" + std::string(tb) + "'");
    return;
  }
  const interp::Vec3 &e0 = x.path.end_mm, &e1 = y.path.end_mm;
  DiffChange c{la, lb, {e1[0] - e0[0], e1[1] - e0[1], e1[2] - e0[2]}, 0, ta != tb};
  rep.edited += c.edited;
  c.distance_mm = std::sqrt(c.d_mm[0] * c.d_mm[0] + c.d_mm[1] * c.d_mm[1] + c.d_mm[2] * c.d_mm[2]);
  rep.max_mm = std::max(rep.max_mm, c.distance_mm);
  rep.mean_mm += c.distance_mm;  // a sum until compare() ends
  rep.changes.push_back(c);
}

DiffResult compare(const Side& a, const Side& b, const compensate::LinePairing& pairing,
               const std::vector<std::string>& files) {
  DiffResult rep;
  std::uint32_t pa = 0, pb = 0;  // last paired lines
  for (std::uint32_t lb = 1; lb < b.lines.size(); ++lb) {
    const std::uint32_t la = pairing.a_of_b[lb];
    if (!la) continue;
    note_unpaired(a, b, pairing, files, pa + 1, la, pb + 1, lb, rep);
    compare_pair(a, b, files, la, lb, rep);
    pa = la;
    pb = lb;
  }
  note_unpaired(a, b, pairing, files, pa + 1, static_cast<std::uint32_t>(a.lines.size()), pb + 1,
                static_cast<std::uint32_t>(b.lines.size()), rep);
  if (!rep.changes.empty()) rep.mean_mm /= static_cast<double>(rep.changes.size());
  return rep;
}

}  // namespace

DiffResult diff(const DiffSettings& s, Io& io) {
  if (!(s.pair_mm > 0)) throw Error(ErrorKind::settings, "{pair_mm} must be > 0");
  const Setup setup = resolve(s.read);
  Diagnostics diags = io.diagnostics(setup.max_errors);
  const Side a = read_side(s.a, setup, diags, io);
  const Side b = read_side(s.b, setup, diags, io);
  if (diags.errors()) throw Error(ErrorKind::input, "the programs have errors; no comparison made").with_errors_of(diags);
  const compensate::LinePairing pairing = compensate::pair_lines(a.lines, b.lines, {s.pair_mm});
  return compare(a, b, pairing, {s.a, s.b});
}

}  // namespace deflex::job
