#include "deflex/compensate/pairing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "deflex/gcode/skeleton.hpp"
#include "deflex/interp/arc.hpp"

namespace deflex::compensate {

PathPiece piece_of(const interp::Motion& m) { return {m.kind, m.plane, m.start_mm, m.end_mm, m.center_mm}; }

void LineFactsSink::motion(const interp::Motion& m) {
  LineFacts& f = (*lines)[m.line];
  // A piece the control adds round a corner (G41/G42) is not the block's
  // move: the block's path and count are its own element's.
  if (m.corner) return;
  const interp::Vec3 start = f.motions ? f.path.start_mm : m.start_mm;
  f.path = piece_of(m);
  f.path.start_mm = start;
  ++f.motions;
}

namespace {

// The form of a block deflex inserts: words only N, G1, G90/G91, X, Y, Z, F,
// an axis word at least, no comment (apply_offsets writes `G1 X Y Z [F]`, led
// by the distance mode of a block that sets its own; diff also accepts a
// hand-written split that leaves modal axes out).
bool insert_form(const gcode::Block& b) {
  if (b.kind != gcode::LineKind::block || b.macro || b.block_delete || !b.comments.empty()) return false;
  bool axis = false;
  for (const gcode::Word& w : b.words) {
    if (w.letter == 'G' && (w.code10() == 10 || w.code10() == 900 || w.code10() == 910)) continue;
    if (w.letter == 'X' || w.letter == 'Y' || w.letter == 'Z') axis = true;
    else if (w.letter != 'N' && w.letter != 'F') return false;
  }
  return axis;
}

std::uint64_t text_hash(const std::string& bytes, std::uint32_t from, std::uint32_t to) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (std::uint32_t i = from; i < to; ++i) {
    if (bytes[i] == ' ' || bytes[i] == '\t') continue;
    h ^= static_cast<unsigned char>(bytes[i]);
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace

void fill_line_text(const gcode::Program& p, std::vector<LineFacts>& lines, bool ignore_feed) {
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  for (std::uint32_t l = 1; l <= p.line_count(); ++l) {
    p.lex(l, b, quiet);
    lines[l].skeleton = gcode::skeleton_hash(p, b, ignore_feed);
    lines[l].text = text_hash(p.bytes(), b.begin, b.text_end);
    lines[l].split_form = insert_form(b);
  }
}

std::vector<LineFacts> line_facts(const gcode::Program& p, const std::vector<interp::Motion>& motions,
                                  bool ignore_feed) {
  std::vector<LineFacts> f(p.line_count() + 1);
  LineFactsSink sink;
  sink.lines = &f;
  for (const interp::Motion& m : motions) sink.motion(m);
  fill_line_text(p, f, ignore_feed);
  return f;
}

PairingOptions pairing_options(double max_offset_mm) { return {std::max(1.0, 10 * max_offset_mm)}; }

V3 nearest_on(const PathPiece& piece, const interp::Vec3& p) {
  const V3 a(piece.start_mm[0], piece.start_mm[1], piece.start_mm[2]);
  const V3 b(piece.end_mm[0], piece.end_mm[1], piece.end_mm[2]);
  const V3 q(p[0], p[1], p[2]);
  if (piece.kind == interp::MotionKind::linear) {
    const V3 ab = b - a;
    const double t = ab.squaredNorm() > 0 ? std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    return a + t * ab;
  }
  if (piece.kind == interp::MotionKind::rapid) return b;
  // A chord end of a linearised arc: onto the circle, in the arc's plane (the
  // arcs deflex linearises are planar: their normal coordinate is the start's).
  const int normal = interp::plane_axes(piece.plane).n;
  const V3 c(piece.center_mm[0], piece.center_mm[1], piece.center_mm[2]);
  V3 radial = q - c, r0 = a - c;
  radial[normal] = 0;
  r0[normal] = 0;
  if (!(radial.norm() > 0)) return a;
  V3 on = c + radial * (r0.norm() / radial.norm());
  on[normal] = a[normal];
  return on;
}

namespace {

using Line = std::uint32_t;

// A rectangle of lines still to align: A's [a0, a1) against B's [b0, b1).
struct Gap {
  Line a0, a1, b0, b1;
  int level;  // 0: unique skeletons, 1: unique texts, 2: in order
  int depth;  // recursions at this level
};

class Aligner {
 public:
  Aligner(const std::vector<LineFacts>& a, const std::vector<LineFacts>& b, const PairingOptions& o)
      : a_(a), b_(b), o_(o) {
    r_.a_of_b.assign(b.size(), 0);
    r_.b_of_a.assign(a.size(), 0);
    r_.parent_of_b.assign(b.size(), 0);
  }

  LinePairing run() {
    std::vector<Gap> todo{{1, static_cast<Line>(a_.size()), 1, static_cast<Line>(b_.size()), 0, 0}};
    while (!todo.empty()) {
      Gap g = todo.back();
      todo.pop_back();
      trim_equal_text(g);
      if (g.a0 == g.a1 || g.b0 == g.b1) continue;
      if (g.level >= 2) {
        in_order(g);
        continue;
      }
      std::vector<std::pair<Line, Line>> anchors = unique_anchors(g);
      if (anchors.empty() || g.depth >= 8) {
        todo.push_back({g.a0, g.a1, g.b0, g.b1, g.level + 1, 0});
        continue;
      }
      Line pa = g.a0, pb = g.b0;
      for (auto [la, lb] : anchors) {
        pair(la, lb);
        todo.push_back({pa, la, pb, lb, g.level, g.depth + 1});
        pa = la + 1;
        pb = lb + 1;
      }
      todo.push_back({pa, g.a1, pb, g.b1, g.level, g.depth + 1});
      note_work(todo.size() * sizeof(Gap) / sizeof(Line));
    }
    find_parents();
    r_.work_entries = peak_ + r_.a_of_b.size() + r_.b_of_a.size() + r_.parent_of_b.size();
    return std::move(r_);
  }

 private:
  void pair(Line la, Line lb) {
    r_.a_of_b[lb] = la;
    r_.b_of_a[la] = lb;
  }
  void note_work(std::size_t entries) const { peak_ = std::max(peak_, entries); }

  // Lines of the same text at both ends of a gap are the same block.
  void trim_equal_text(Gap& g) {
    while (g.a0 < g.a1 && g.b0 < g.b1 && same_text(g.a0, g.b0)) pair(g.a0++, g.b0++);
    while (g.a0 < g.a1 && g.b0 < g.b1 && same_text(g.a1 - 1, g.b1 - 1)) pair(--g.a1, --g.b1);
  }
  bool same_text(Line la, Line lb) const {
    return a_[la].text == b_[lb].text && a_[la].skeleton == b_[lb].skeleton && a_[la].motions == b_[lb].motions;
  }

  std::uint64_t key(const LineFacts& f, int level) const { return level == 0 ? f.skeleton : f.text; }

  // Lines whose key occurs once in the gap on each side, the longest chain of
  // them in the same order on both (patience).
  std::vector<std::pair<Line, Line>> unique_anchors(const Gap& g) const {
    std::vector<std::pair<std::uint64_t, Line>> ka, kb;
    ka.reserve(g.a1 - g.a0);
    kb.reserve(g.b1 - g.b0);
    for (Line l = g.a0; l < g.a1; ++l) ka.push_back({key(a_[l], g.level), l});
    for (Line l = g.b0; l < g.b1; ++l) kb.push_back({key(b_[l], g.level), l});
    std::sort(ka.begin(), ka.end());
    std::sort(kb.begin(), kb.end());
    std::vector<std::pair<Line, Line>> cand;
    std::size_t i = 0, j = 0;
    while (i < ka.size() && j < kb.size()) {
      if (ka[i].first < kb[j].first) { ++i; continue; }
      if (kb[j].first < ka[i].first) { ++j; continue; }
      std::size_t ie = i, je = j;
      while (ie < ka.size() && ka[ie].first == ka[i].first) ++ie;
      while (je < kb.size() && kb[je].first == kb[j].first) ++je;
      if (ie - i == 1 && je - j == 1 && pairable(ka[i].second, kb[j].second))
        cand.push_back({ka[i].second, kb[j].second});
      i = ie;
      j = je;
    }
    note_work(2 * (ka.size() + kb.size()) + 2 * cand.size());
    std::sort(cand.begin(), cand.end());
    return longest_chain(cand);
  }

  // The longest subsequence of `cand` (sorted by A line) increasing in B line.
  static std::vector<std::pair<Line, Line>> longest_chain(const std::vector<std::pair<Line, Line>>& cand) {
    std::vector<std::size_t> tails, prev(cand.size(), SIZE_MAX);
    for (std::size_t k = 0; k < cand.size(); ++k) {
      auto it = std::lower_bound(tails.begin(), tails.end(), cand[k].second,
                                 [&](std::size_t t, Line v) { return cand[t].second < v; });
      if (it != tails.begin()) prev[k] = *(it - 1);
      if (it == tails.end()) tails.push_back(k);
      else *it = k;
    }
    std::vector<std::pair<Line, Line>> chain;
    for (std::size_t k = tails.empty() ? SIZE_MAX : tails.back(); k != SIZE_MAX; k = prev[k]) chain.push_back(cand[k]);
    std::reverse(chain.begin(), chain.end());
    return chain;
  }

  bool pairable(Line la, Line lb) const {
    const LineFacts &x = a_[la], &y = b_[lb];
    return x.skeleton == y.skeleton && x.motions == y.motions && (!x.motions || x.path.kind == y.path.kind);
  }
  double end_distance(Line la, Line lb) const {
    if (!a_[la].motions) return 0.0;
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += std::pow(a_[la].path.end_mm[k] - b_[lb].path.end_mm[k], 2);
    return std::sqrt(d2);
  }
  // Whether B's line has the form of a block inserted before A's line and lies on its move.
  bool insertable(Line lb, Line la) const { return split_distance(lb, la) >= 0; }
  double split_distance(Line lb, Line la) const {
    const LineFacts &y = b_[lb], &x = a_[la];
    if (!y.split_form || y.motions != 1 || y.path.kind != interp::MotionKind::linear) return -1;
    if (x.motions != 1 || x.path.kind == interp::MotionKind::rapid) return -1;
    const V3 on = nearest_on(x.path, y.path.end_mm);
    const double d = (V3(y.path.end_mm[0], y.path.end_mm[1], y.path.end_mm[2]) - on).norm();
    return d <= o_.near_mm ? d : -1;
  }

  // Whether B's line lb is a block inserted before A's line la rather than
  // la's own block. Both readings are possible when lb has the form of an
  // inserted block, lies on la's move and has la's skeleton: a raster without
  // N numbers whose moves are no longer than the offsets (a 0.125 mm step-over
  // under a 0.1 mm cap), where the compensated end of one move lies nearer the
  // end of the next than its own. No single line tells them apart, so the
  // reading is the first step of the cheapest alignment of the lines ahead
  // (window_cost): a wrong reading shifts every pairing after it onto a
  // neighbour's end, far off the path. Cheap cases first: with no later line
  // that could be la's own block within reach there is no question.
  bool inserted_before(Line la, Line lb, Line a_end, Line b_end) const {
    if (!insertable(lb, la)) return false;
    if (!pairable(la, lb)) return true;
    const Line slack = (b_end - lb) - (a_end - la);
    // A later line that could be la's own block ends within reach of la's end
    // (a compensated end lies within the offsets of its original).
    bool other = false;
    for (Line t = 1; t <= std::min<Line>(slack, kMaxInserts) && !other; ++t) {
      if (pairable(la, lb + t) && end_distance(la, lb + t) <= o_.near_mm) other = true;
      else if (!insertable(lb + t, la)) break;
    }
    return other && window_cost(la, lb, a_end, b_end, true) < window_cost(la, lb, a_end, b_end, false);
  }

  // Blocks inserted before one move that the look-ahead considers: twice
  // what deflex writes (Settings::max_splits_per_move, 32); arc chords never
  // pair with the arc, so they raise no question.
  static constexpr Line kMaxInserts = 64;
  static constexpr Line kWindowA = 8;  // A lines the alignment looks ahead
  // The cost of a line only in A or only in B (not on the next move): more
  // than any pairing or split within reach, so the alignment makes one only
  // where nothing else fits.
  double lone_cost() const { return 4 * o_.near_mm; }

  // The least cost of aligning the next kWindowA lines of A from la with B's
  // lines from lb, lb taken as inserted before la (insert) or as la's own
  // block: each paired line costs its end distance, each inserted line its
  // distance to the move it splits, a line only in A or B lone_cost().
  double window_cost(Line la, Line lb, Line a_end, Line b_end, bool insert) const {
    const Line rows = std::min<Line>(kWindowA, a_end - la);
    const Line cols = std::min<Line>(b_end - lb, rows + std::min<Line>((b_end - lb) - (a_end - la), kMaxInserts));
    const double inf = std::numeric_limits<double>::infinity();
    // dp[r][c]: A lines la..la+r-1 aligned with B lines lb..lb+c-1.
    std::vector<double> dp((rows + 1) * (cols + 1), inf);
    auto at = [&](Line r, Line c) -> double& { return dp[r * (cols + 1) + c]; };
    if (insert) at(0, 1) = split_distance(lb, la);
    else at(1, 1) = end_distance(la, lb);
    for (Line r = insert ? 0 : 1; r <= rows; ++r)
      for (Line c = 1; c <= cols; ++c) {
        const double here = at(r, c);
        if (here == inf) continue;
        if (r < rows && c < cols && pairable(la + r, lb + c))
          at(r + 1, c + 1) = std::min(at(r + 1, c + 1), here + end_distance(la + r, lb + c));
        if (r < rows) at(r + 1, c) = std::min(at(r + 1, c), here + lone_cost());
        if (c < cols) {
          const double d = r < rows ? split_distance(lb + c, la + r) : -1;
          at(r, c + 1) = std::min(at(r, c + 1), here + (d >= 0 ? d : lone_cost()));
        }
      }
    double best = inf;
    for (Line c = 1; c <= cols; ++c) best = std::min(best, at(rows, c));
    return best;
  }

  // What no anchor decides: in order; B has (b1-b0)-(a1-a0) extra lines.
  void in_order(const Gap& g) {
    Line i = g.a0, j = g.b0;
    while (i < g.a1 && j < g.b1) {
      const std::int64_t slack = static_cast<std::int64_t>(g.b1 - j) - static_cast<std::int64_t>(g.a1 - i);
      if (slack > 0 && inserted_before(i, j, g.a1, g.b1)) {
        ++j;
      } else if (pairable(i, j)) {
        pair(i++, j++);
      } else if (slack > 0) {
        ++j;  // only in B
      } else if (slack < 0) {
        ++i;  // only in A
      } else {
        ++i;
        ++j;
      }
    }
  }

  // A line only in B is a split of the move of the next paired line when it
  // has the form, lies on that move, and no line only in A comes between.
  void find_parents() {
    Line next_a = 0;
    for (Line lb = static_cast<Line>(b_.size()); lb-- > 1;) {
      if (r_.a_of_b[lb]) {
        next_a = r_.a_of_b[lb];
        continue;
      }
      if (!next_a || (next_a > 1 && !r_.b_of_a[next_a - 1])) continue;
      if (insertable(lb, next_a)) r_.parent_of_b[lb] = next_a;
    }
  }

  const std::vector<LineFacts>& a_;
  const std::vector<LineFacts>& b_;
  PairingOptions o_;
  LinePairing r_;
  mutable std::size_t peak_ = 0;  // work entries held at once, at most
};

}  // namespace

LinePairing pair_lines(const std::vector<LineFacts>& a, const std::vector<LineFacts>& b, const PairingOptions& o) {
  return Aligner(a, b, o).run();
}

LinePairing expected_pairing(const std::vector<std::uint32_t>& inserted_before, std::uint32_t lines_a,
                             std::uint32_t lines_b) {
  LinePairing r;
  r.a_of_b.assign(lines_b + 1, 0);
  r.b_of_a.assign(lines_a + 1, 0);
  r.parent_of_b.assign(lines_b + 1, 0);
  Line ob = 0;
  for (Line l = 1; l <= lines_a && ob < lines_b; ++l) {
    for (std::uint32_t k = 0; k < inserted_before[l] && ob < lines_b; ++k) r.parent_of_b[++ob] = l;
    if (ob == lines_b) break;
    r.a_of_b[++ob] = l;
    r.b_of_a[l] = ob;
  }
  return r;
}

MotionPairer::MotionPairer(const LinePairing& lines, const std::vector<interp::Motion>& a,
                           const std::vector<bool>* passed_over)
    : lines_(lines), a_(a), passed_over_(passed_over) {}

// Pieces the control adds round a G41/G42 corner have no block: they pair
// with nothing (MotionCheck, intent_offsets).
void MotionPairer::skip_passed_over() {
  while (k_ < a_.size() && ((passed_over_ && (*passed_over_)[k_]) || a_[k_].corner)) ++k_;
}

MotionPair MotionPairer::next(const interp::Motion& b) {
  skip_passed_over();
  const Line lb = b.line;
  if (lb >= lines_.a_of_b.size() || k_ >= a_.size()) return {};
  if (const Line parent = lines_.parent_of_b[lb]) {
    // An inserted block: the motion it splits is A's next one, not yet paired.
    if (a_[k_].line != parent) return {};
    return {k_, true};
  }
  const Line la = lines_.a_of_b[lb];
  if (!la || a_[k_].line != la) return {};
  return {k_++, false};
}

bool MotionPairer::complete() {
  skip_passed_over();
  return k_ == a_.size();
}

std::vector<V3> intent_offsets(const LinePairing& lines, const std::vector<interp::Motion>& a,
                               const std::vector<interp::Motion>& b, const std::string& name_b) {
  std::vector<V3> off(b.size(), V3::Zero());
  MotionPairer pairer(lines, a);
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (b[i].corner) {  // moves with the corner: the offset of the move before it
      off[i] = i ? off[i - 1] : V3(V3::Zero());
      continue;
    }
    const MotionPair p = pairer.next(b[i]);
    if (p.original == MotionPair::none)
      throw Error(ErrorKind::input, name_b + ":" + std::to_string(b[i].line) +
                                   ":1: error: this motion has no counterpart in the reference: not the same program");
    const interp::Motion& x = a[p.original];
    const V3 end(b[i].end_mm[0], b[i].end_mm[1], b[i].end_mm[2]);
    // A motion deflex left alone ends exactly where the original does: zero.
    off[i] = p.inserted ? V3(end - nearest_on(piece_of(x), b[i].end_mm))
                        : V3(end - V3(x.end_mm[0], x.end_mm[1], x.end_mm[2]));
  }
  if (!pairer.complete())
    throw Error(ErrorKind::input, name_b + ": error: motions of the reference have no counterpart in this program");
  return off;
}

}  // namespace deflex::compensate
