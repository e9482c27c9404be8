#include "deflex/compensate/apply.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <sstream>

#include "contour.hpp"
#include "deflex/compensate/pairing.hpp"
#include "deflex/gcode/skeleton.hpp"
#include "deflex/interp/arc.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::compensate {
namespace {

// Where a missing axis word goes: after the highest axis word below it, else
// after the last G word, else after N, else after the last word of the block.
std::uint32_t insert_position(const gcode::Block& b, char axis) {
  const gcode::Word* best = nullptr;
  for (const gcode::Word& w : b.words)
    if ((w.letter == 'X' || w.letter == 'Y' || w.letter == 'Z') && w.letter < axis) best = &w;
  if (!best)
    for (const gcode::Word& w : b.words)
      if (w.letter == 'G') best = &w;
  if (!best)
    for (const gcode::Word& w : b.words)
      if (w.letter == 'N') best = &w;
  if (!best && !b.words.empty()) best = &b.words.back();
  return best ? best->end : b.begin;
}

// The value a control will read back from a number deflex writes, mm.
double written_mm(double value_mm, bool inch, const profile::Dialect& d) {
  std::string s = writer::format_number(inch ? value_mm / 25.4 : value_mm, inch, d);
  double v = std::strtod(s.c_str(), nullptr);
  return inch ? v * 25.4 : v;
}

}  // namespace

// A block deflex may split: words only N, G1/G01, G90/G91, X, Y, Z, F.
static bool split_form(const gcode::Block& b) {
  if (b.macro || b.block_delete || !b.comments.empty()) return false;
  for (const gcode::Word& w : b.words) {
    if (w.letter == 'G' && (w.code10() == 10 || w.code10() == 900 || w.code10() == 910)) continue;
    if (w.letter != 'N' && w.letter != 'X' && w.letter != 'Y' && w.letter != 'Z' && w.letter != 'F') return false;
  }
  return true;
}

// An arc deflex may linearise: its own G2/G3 word, centre by I/J/K (not R),
// words only N, G2/G3, X, Y, Z, I, J, K, F, and in its plane (no helix). The
// chords go in before it as G1 blocks and the block keeps the last piece of the
// arc, its centre words re-aimed from the new start; the G word in the block
// keeps the motion mode of the blocks after it.
static bool arc_split_form(const gcode::Block& b, const interp::Motion& m) {
  if (b.macro || b.block_delete || !b.comments.empty()) return false;
  bool g = false;
  for (const gcode::Word& w : b.words) {
    if (w.letter == 'G' && (w.code10() == 20 || w.code10() == 30)) {
      g = true;
      continue;
    }
    if (w.letter != 'N' && w.letter != 'X' && w.letter != 'Y' && w.letter != 'Z' && w.letter != 'I' &&
        w.letter != 'J' && w.letter != 'K' && w.letter != 'F')
      return false;
  }
  const int normal = interp::plane_axes(m.plane).n;
  return g && std::fabs(m.end_mm[normal] - m.start_mm[normal]) < 1e-9;
}

std::vector<bool> splittable(const gcode::Program& prog, const std::vector<interp::Motion>& motions) {
  std::vector<bool> ok(motions.size(), false);
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  for (std::size_t i = 0; i < motions.size(); ++i) {
    const interp::Motion& m = motions[i];
    // Under G41/G42 a line is split by points of its contour (the mirror
    // pass sets them); an arc's chords would be chords of the centre's arc,
    // and a corner piece has no block: neither is split.
    if (!m.plain || !m.compensable() || m.kind == interp::MotionKind::rapid || m.corner) continue;
    if (m.comp && m.kind != interp::MotionKind::linear) continue;
    prog.lex(m.line, b, quiet);
    ok[i] = m.kind == interp::MotionKind::linear ? split_form(b) : arc_split_form(b, m);
  }
  return ok;
}

// A plain G1 in G91: each axis word becomes the increment from where the
// written program stands (`carried`, on the grid of the written digits) to the
// compensated end, so the control's sum of increments is the compensated
// position, and back to the original's once the offsets return to zero. The
// programmer's text stays where the increment written does not change.
// The increment on axis a from where the written program stands to `want_mm`,
// as written; `carried` moves on by it. Unknown (NaN): nothing deflex wrote
// moved the axis, the control stands where the original puts it.
static double step_to(double* carried, int a, const interp::Motion& m, double want_mm, const profile::Dialect& d) {
  if (std::isnan(carried[a])) carried[a] = m.start_mm[a];
  const double step = written_mm(written_mm(want_mm, m.inch, d) - carried[a], m.inch, d);
  carried[a] += step;
  return step;
}

static void write_increments(writer::Rewriter& w, const gcode::Block& b, const interp::Motion& m, const V3& o,
                             double* carried, const profile::Dialect& d, WriteStats& st) {
  static const char axes[] = {'X', 'Y', 'Z'};
  for (int a = 0; a < 3; ++a) {
    const double step = step_to(carried, a, m, m.end_mm[a] + o[a], d);
    const gcode::Word* word = b.find(axes[a]);
    if (word) {
      // The block's own increment (a split move starts elsewhere than its block did).
      const double programmed = word->value * (m.inch ? 25.4 : 1.0);
      if (written_mm(programmed, m.inch, d) != step) {
        w.set_number(*word, m.inch ? step / 25.4 : step, m.inch);
        ++st.numbers_changed;
      }
    } else if (step != 0.0) {
      w.insert_word(insert_position(b, axes[a]), axes[a], m.inch ? step / 25.4 : step, m.inch);
      ++st.words_inserted;
    }
  }
}

namespace {

const char kAxes[] = {'X', 'Y', 'Z'};

// apply_offsets' pass over the motions: the edits of each motion's block, and
// what the output program's control holds as it goes (axes and feed, in
// WriteState, so a piece goes on from the one before).
class OffsetWriter {
 public:
  OffsetWriter(const gcode::Program& prog, const profile::Dialect& d, const std::vector<interp::Motion>& motions,
               const std::vector<V3>& offsets, const std::vector<bool>* inserted, const std::vector<double>* feeds,
               WriteState& ws, writer::Rewriter& w, WriteStats& st)
      : prog_(prog), d_(d), motions_(motions), offsets_(offsets), inserted_(inserted), feeds_(feeds), ws_(ws),
        w_(w), st_(st), carried_(ws.carried_mm), contour_(detail::contour_targets(motions, offsets, d)) {}

  void motion(std::size_t i) {
    const interp::Motion& m = motions_[i];
    const V3 o = offsets_.empty() ? V3(V3::Zero()) : offsets_[i];
    if (inserted_ && (*inserted_)[i]) {
      insert_piece(i, o);
      return;
    }
    // Under G41/G42 the motion is the tool centre's; its block states the
    // contour's point, which the writer moves (the centre moves with it), and
    // a piece the control adds at a corner has no block.
    if (m.corner) return;
    const interp::Vec3& end = m.comp ? m.contour_end_mm : m.end_mm;
    if (!m.plain) {
      // Cycles, G28/G30/G53, subprograms, G91: never moved, and never preceded
      // by a moved point (compensate::movable), so they end where they did.
      for (int a = 0; a < 3; ++a) carried_[a] = end[a];
      feed_edit(i);
      return;
    }
    // An arc whose first part went into inserted chords: its centre words,
    // relative to the new start (what the control holds after the last chord).
    const bool arc = interp::is_arc(m);
    prog_.lex(m.line, b_, quiet_);
    if (arc && inserted_ && i > 0 && (*inserted_)[i - 1]) reaim_centre(m, o);
    if (m.incremental) write_increments(w_, b_, m, o, carried_, d_, st_);
    else write_axes(i, m, o, end);
    feed_edit(i);
  }

  // --feed-limit: the modal F of the output program, mm/min (ws.carried_feed),
  // after the F words of the untouched lines before `line` (blocks deflex does
  // not touch may set F themselves; ws.scanned is the last line looked at).
  void feed_words_up_to(std::uint32_t line, bool inch) {
    for (std::uint32_t l = ws_.scanned + 1; l < line; ++l) {
      prog_.lex(l, b_, quiet_);
      if (const gcode::Word* f = b_.find('F')) ws_.carried_feed = f->value * (inch ? 25.4 : 1.0);
    }
    ws_.scanned = std::max(ws_.scanned, line);
  }

 private:
  // The F word a feed motion needs after --feed-limit (called after its
  // coordinate words, so an added F comes last in the block).
  void feed_edit(std::size_t i) {
    const interp::Motion& m = motions_[i];
    if (!feeds_ || m.kind == interp::MotionKind::rapid || (inserted_ && (*inserted_)[i])) return;
    feed_words_up_to(m.line, m.inch);
    const double want = (*feeds_)[i];
    const double scale = m.inch ? 25.4 : 1.0;
    prog_.lex(m.line, b_, quiet_);
    const gcode::Word* f = b_.find('F');
    if (f && std::fabs(want - m.feed_mm_per_min) > 1e-9) {
      w_.set_number(*f, want / scale, m.inch);
      ++st_.feeds_changed;
    } else if (!f && !(std::fabs(ws_.carried_feed - want) <= 1e-9)) {
      w_.insert_word(b_.words.back().end, 'F', want / scale, m.inch);
      ++st_.feeds_changed;
    }
    ws_.carried_feed = want;
  }

  // A new G1 block before its parent's block, with all three axes (and the
  // parent's F, so the split piece runs at the programmed feed).
  void insert_piece(std::size_t i, const V3& o) {
    const interp::Motion& m = motions_[i];
    std::vector<std::pair<char, double>> words;
    for (int a = 0; a < 3; ++a) {
      const double want = m.comp ? contour_[i][a] : m.end_mm[a] + o[a];
      if (m.incremental) {  // in G91: increments from where the written program stands
        const double step = step_to(carried_, a, m, want, d_);
        words.push_back({kAxes[a], m.inch ? step / 25.4 : step});
        continue;
      }
      words.push_back({kAxes[a], m.inch ? want / 25.4 : want});
      carried_[a] = written_mm(want, m.inch, d_);
    }
    prog_.lex(m.line, b_, quiet_);
    if (feeds_) {
      feed_words_up_to(m.line, m.inch);
      if (!(std::fabs(ws_.carried_feed - (*feeds_)[i]) <= 1e-9)) words.push_back({'F', (*feeds_)[i] / (m.inch ? 25.4 : 1.0)});
      ws_.carried_feed = (*feeds_)[i];
    } else if (const gcode::Word* f = b_.find('F')) {
      words.push_back({'F', f->value});
    }
    // The pieces run in the distance mode of the block they split: where it
    // sets the mode itself, they say it too (they come before it).
    bool sets_mode = false;
    for (const gcode::Word& x : b_.words) sets_mode = sets_mode || (x.letter == 'G' && (x.code10() == 900 || x.code10() == 910));
    const char* lead = !sets_mode ? "G1" : m.incremental ? "G91 G1" : "G90 G1";
    w_.insert_block_before(m.line, w_.format_block(m.line - 1, words, m.inch, "", lead));
    ++st_.blocks_inserted;
  }

  // The centre words of the arc lexed into b_, from where the control stands.
  void reaim_centre(const interp::Motion& m, const V3& o) {
    static const char centre[] = {'I', 'J', 'K'};
    const int normal = interp::plane_axes(m.plane).n;
    for (int a = 0; a < 3; ++a) {
      if (a == normal) continue;
      const double want = m.center_mm[a] + o[a] - carried_[a];
      const gcode::Word* word = b_.find(centre[a]);
      if (word) {
        w_.set_number(*word, m.inch ? want / 25.4 : want, m.inch);
        ++st_.numbers_changed;
      } else {
        // After the centre word before it in I, J, K, else after the axis words.
        const gcode::Word* after = nullptr;
        for (const gcode::Word& x : b_.words)
          if (x.letter >= 'I' && x.letter < centre[a]) after = &x;
        w_.insert_word(after ? after->end : insert_position(b_, '['), centre[a], m.inch ? want / 25.4 : want, m.inch);
        ++st_.words_inserted;
      }
    }
  }

  // The axis words of the G90 block lexed into b_ for the moved end.
  void write_axes(std::size_t i, const interp::Motion& m, const V3& o, const interp::Vec3& end) {
    for (int a = 0; a < 3; ++a) {
      const double want = m.comp ? contour_[i][a] : end[a] + o[a];
      const gcode::Word* word = b_.find(kAxes[a]);
      if (word) {
        // Splice only when the number written changes (an offset below the
        // last written digit leaves the programmer's text alone).
        if (want != end[a] && written_mm(want, m.inch, d_) != written_mm(end[a], m.inch, d_)) {
          w_.set_number(*word, m.inch ? want / 25.4 : want, m.inch);
          carried_[a] = written_mm(want, m.inch, d_);
          ++st_.numbers_changed;
        } else {
          carried_[a] = end[a];
        }
      } else if (!(std::fabs(carried_[a] - want) <= 1e-9) &&  // the cheap test first: most blocks hold it
                 !(std::fabs(carried_[a] - written_mm(want, m.inch, d_)) <= 1e-9)) {
        // The block relies on the modal value, which the previous block moved
        // (or which is unknown): say what this block means, unless the
        // number written would be the one the control holds.
        if (std::isnan(carried_[a]) && o[a] == 0.0) continue;
        w_.insert_word(insert_position(b_, kAxes[a]), kAxes[a], m.inch ? want / 25.4 : want, m.inch);
        carried_[a] = written_mm(want, m.inch, d_);
        ++st_.words_inserted;
      }
    }
  }

  const gcode::Program& prog_;
  const profile::Dialect& d_;
  const std::vector<interp::Motion>& motions_;
  const std::vector<V3>& offsets_;
  const std::vector<bool>* inserted_;
  const std::vector<double>* feeds_;
  WriteState& ws_;
  writer::Rewriter& w_;
  WriteStats& st_;
  double* carried_;  // what the output program's control holds, mm (ws.carried_mm)
  Diagnostics quiet_{nullptr, 0};
  gcode::Block b_;
  const std::vector<interp::Vec3> contour_;
};

}  // namespace

std::string apply_offsets(const gcode::Program& prog, const profile::Dialect& d,
                          const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets,
                          WriteStats* stats, const std::vector<bool>* inserted,
                          const std::vector<double>* feeds, WriteState* state) {
  WriteState whole;
  WriteState& ws = state ? *state : whole;
  writer::Rewriter w(prog, d, &ws.numbers_taken);
  WriteStats st;
  OffsetWriter ow(prog, d, motions, offsets, inserted, feeds, ws, w, st);
  for (std::size_t i = 0; i < motions.size(); ++i) ow.motion(i);
  const std::uint32_t first = ws.first_line ? ws.first_line : prog.first_line();
  const std::uint32_t last = ws.last_line ? ws.last_line : prog.last_line();
  // The F words of the lines after the last motion: the next piece starts
  // from the feed they leave.
  if (feeds && state && last >= first) ow.feed_words_up_to(last + 1, ws.inch_after);
  if (stats) *stats = st;
  if (!state && w.edits() == 0) return prog.bytes();
  if (prog.line_count() == 0) return prog.bytes();
  std::ostringstream out;
  w.write(out, first, last);
  return out.str();
}

namespace {

// The line facts of the original program: its motions are those of `om` that
// deflex did not insert.
std::vector<LineFacts> original_facts(const gcode::Program& original, const std::vector<interp::Motion>& om,
                                      const std::vector<bool>* inserted, bool ignore_feed) {
  std::vector<LineFacts> f(original.line_count() + 1);
  LineFactsSink sink;
  sink.lines = &f;
  // In `om` a split move starts at its last inserted point; in the original
  // it starts where the first of them does.
  std::size_t group = 0;  // first motion after the last one deflex did not insert
  for (std::size_t i = 0; i < om.size(); ++i) {
    if (inserted && (*inserted)[i]) continue;
    interp::Motion m = om[i];
    m.start_mm = om[group].start_mm;
    sink.motion(m);
    group = i + 1;
  }
  fill_line_text(original, f, ignore_feed);
  return f;
}

using Fail = std::function<void(std::uint32_t line, const std::string& what)>;

// How far an output motion lies from where deflex meant it: an inserted one
// from the move or arc it splits (from that move's original start: in `om`
// the parent starts at the last inserted point), any other from the original
// end (and an arc's centre, which moves with it).
double displacement_mm(const std::vector<interp::Motion>& om, const std::vector<bool>* inserted, std::size_t i,
                       const MotionPair& p, const interp::Motion& y) {
  const interp::Motion& x = om[p.original];
  if (p.inserted) {
    std::size_t s0 = i;
    while (s0 > 0 && (*inserted)[s0 - 1]) --s0;
    PathPiece parent = piece_of(x);
    parent.start_mm = om[s0].start_mm;
    return (V3(y.end_mm[0], y.end_mm[1], y.end_mm[2]) - nearest_on(parent, y.end_mm)).norm();
  }
  double dist = 0;
  for (int k = 0; k < 3; ++k) dist = std::max(dist, std::fabs(y.end_mm[k] - x.end_mm[k]));
  if (interp::is_arc(x))
    for (int k = 0; k < 3; ++k) dist = std::max(dist, std::fabs(y.center_mm[k] - x.center_mm[k]));
  return dist;
}

// Every motion read back against the one deflex meant, through the pairing.
// Each motion of the written program, as the interpreter gives it, against
// the original's (nothing kept: the check runs while the output is read back).
class MotionCheck : public interp::MotionSink {
 public:
  MotionCheck(const std::vector<interp::Motion>& om, const LinePairing& pairing, const interp::Options& opt,
              const std::vector<bool>& movable, double max_offset_mm, const std::vector<bool>* inserted,
              const std::vector<double>* feeds, const Fail& fail)
      : om_(om), pairer_(pairing, om, inserted), movable_(movable), max_offset_mm_(max_offset_mm),
        inserted_(inserted), feeds_(feeds), fail_(fail),
        // Numbers are written with the dialect's decimals: allow their rounding.
        round_mm_(writer::rounding_mm(false, opt.dialect) * 1.001),
        round_in_(writer::rounding_mm(true, opt.dialect) * 1.001) {}

  void motion(const interp::Motion& y) override {
    // Pieces the control adds round a G41/G42 corner (in the air) pair with
    // nothing: a corner whose turn deflex moved across a threshold of the
    // control's rule (an arc from 0.05 rad on LinuxCNC) has one more or one
    // fewer. Such a piece stays near the corner's moves.
    if (y.corner) {
      const V3 e(y.end_mm[0], y.end_mm[1], y.end_mm[2]);
      double dist = 1e300;
      for (std::size_t k = i_ ? i_ - 1 : 0; k < std::min(i_ + 3, om_.size()); ++k)
        dist = std::min(dist, (e - nearest_on(piece_of(om_[k]), y.end_mm)).norm());
      if (dist > max_offset_mm_ + y.comp_radius_mm * 0.1)
        fail_(y.line, "a piece round a corner under cutter compensation is off the path");
      return;
    }
    while (i_ < om_.size() && om_[i_].corner) ++i_;
    const std::size_t i = i_++;
    if (i >= om_.size()) fail_(1, "the written program has more motions than the original");
    const interp::Motion& x = om_[i];
    const bool ins = inserted_ && (*inserted_)[i];
    const MotionPair p = pairer_.next(y);
    if (p.original == MotionPair::none || p.inserted != ins || (!ins && p.original != i))
      fail_(x.line, "a motion has no counterpart in the original");
    if (ins && om_[p.original].kind == interp::MotionKind::rapid) fail_(x.line, "an inserted block before a rapid");
    if (x.kind != y.kind) fail_(x.line, "a motion changed its kind");
    if (x.kind != interp::MotionKind::rapid) {
      // Feeds: as programmed, or as --feed-limit lowered them (never higher).
      const double want = feeds_ ? (*feeds_)[i] : x.feed_mm_per_min;
      if (std::fabs(y.feed_mm_per_min - want) > 1e-6 * std::max(1.0, want) + (x.inch ? 1e-4 : 0.0)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "a feed rate is not the one deflex meant (%.4f mm/min read back, %.4f meant)",
                      y.feed_mm_per_min, want);
        fail_(x.line, buf);
      }
      if (y.feed_mm_per_min > x.feed_mm_per_min * (1 + 1e-9)) fail_(x.line, "a feed rate went up");
    }
    const double r = (x.inch ? round_in_ : round_mm_) * std::sqrt(3.0);
    const double allowed = movable_[i] || ins || x.comp ? max_offset_mm_ + r : r;
    double dist = displacement_mm(om_, inserted_, i, p, y);
    // Under G41/G42 the control places each point of the centre path from
    // the contour's elements on both sides of it: where deflex turned one a
    // little, the point slides along the path (a start-up's end, the end of
    // a corner arc, where two offset lines meet). What must hold is that it
    // stays on the path deflex meant: its distance to this motion's or the
    // next one's.
    if (x.comp && !ins) {
      const V3 e(y.end_mm[0], y.end_mm[1], y.end_mm[2]);
      for (std::size_t k = i; k < std::min(i + 2, om_.size()); ++k)
        dist = std::min(dist, (e - nearest_on(piece_of(om_[k]), y.end_mm)).norm());
    }
    if (dist > allowed) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "a %s motion moved by %.6f mm (allowed %.6f mm)",
                    ins ? "inserted" : movable_[i] ? "compensated" : "fixed", dist, allowed);
      fail_(x.line, buf);
    }
  }
  void finish() {
    while (i_ < om_.size() && om_[i_].corner) ++i_;
    if (!pairer_.complete() || i_ != om_.size()) fail_(1, "the written program has a different number of motions");
  }

 private:
  const std::vector<interp::Motion>& om_;
  MotionPairer pairer_;
  const std::vector<bool>& movable_;
  double max_offset_mm_;
  const std::vector<bool>* inserted_;
  const std::vector<double>* feeds_;
  const Fail& fail_;
  double round_mm_, round_in_;
  std::size_t i_ = 0;
};

}  // namespace

void safety_check(const gcode::Program& original, const std::vector<interp::Motion>& om, const std::string& text,
                  const interp::Options& opt, const std::vector<bool>& movable, double max_offset_mm,
                  const std::vector<bool>* inserted, const std::vector<double>* feeds) {
  const gcode::Program out(SourceText(original.source().name() + " (compensated)", text));
  safety_check(original, om, out, opt, movable, max_offset_mm, inserted, feeds);
}

struct ReadBack::Impl {
  // The written program's motions go to the sink of the piece being read.
  struct Forward : interp::MotionSink {
    interp::MotionSink* to = nullptr;
    void motion(const interp::Motion& m) override { to->motion(m); }
  };
  // The written program's lines are not the original's: which run more than
  // once is not asked of them (the check compares where motions go).
  explicit Impl(const interp::Options& o) : opt(readback(o)), it(opt, diags, forward) {}
  static interp::Options readback(interp::Options o) {
    o.repeated_lines = nullptr;
    return o;
  }
  interp::Options opt;
  std::ostringstream errs;
  Diagnostics diags{&errs, 0};
  Forward forward;
  interp::Interpreter it;
};

ReadBack::ReadBack(const interp::Options& opt) : impl_(std::make_unique<Impl>(opt)) {}
ReadBack::~ReadBack() = default;

bool ReadBack::read(const gcode::Program& piece, interp::MotionSink& sink, std::string& errors) {
  impl_->forward.to = &sink;
  impl_->it.feed(piece);
  impl_->forward.to = nullptr;
  errors = impl_->errs.str();
  return impl_->diags.errors() == 0;
}

void safety_check(const gcode::Program& original, const std::vector<interp::Motion>& om, const gcode::Program& out,
                  const interp::Options& opt, const std::vector<bool>& movable, double max_offset_mm,
                  const std::vector<bool>* inserted, const std::vector<double>* feeds, ReadBack* read_back,
                  std::uint32_t line_base) {
  const Fail fail = [&](std::uint32_t line, const std::string& what) {
    throw Error(ErrorKind::internal, original.source().name() + ":" + std::to_string(line + line_base) +
                                    ":1: error: safety check failed: " + what +
                                    "; nothing was written (this is a bug in deflex, please report it)");
  };
  // Blocks inserted before each original line.
  std::vector<std::uint32_t> before(original.line_count() + 2, 0);
  std::size_t n_inserted = 0;
  if (inserted)
    for (std::size_t i = 0; i < om.size(); ++i)
      if ((*inserted)[i]) { ++before[om[i].line]; ++n_inserted; }
  if (out.line_count() != original.line_count() + n_inserted)
    fail(1, "the written program has an unexpected number of lines");
  const LinePairing want = expected_pairing(before, original.line_count(), out.line_count());
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  std::vector<LineFacts> fa = original_facts(original, om, inserted, feeds), fb(out.line_count() + 1);
  fill_line_text(out, fb, feeds);
  for (std::uint32_t ol = 1; ol <= out.line_count(); ++ol) {
    if (want.inserted(ol)) {
      out.lex(ol, b, quiet);
      if (!split_form(b) || !b.find('X') || !b.find('Y') || !b.find('Z'))
        fail(want.parent_of_b[ol], "an inserted block is not a plain G1 X Y Z [F] block");
    } else if (fa[want.a_of_b[ol]].skeleton != fb[ol].skeleton) {
      fail(want.a_of_b[ol], feeds ? "the block changed in more than its coordinate and feed words"
                                  : "the block changed in more than its coordinate words");
    }
  }
  std::ostringstream errs;
  Diagnostics diags(&errs, 0);
  MotionCheck check(om, want, opt, movable, max_offset_mm, inserted, feeds, fail);
  LineFactsSink facts;
  facts.lines = &fb;
  struct Both : interp::MotionSink {
    interp::MotionSink *x, *y;
    void motion(const interp::Motion& m) override { x->motion(m); y->motion(m); }
  } both;
  both.x = &facts;
  both.y = &check;
  if (read_back) {
    std::string e;
    if (!read_back->read(out, both, e)) fail(1, "the written program does not read back cleanly:\n" + e);
  } else {
    interp::Options o = opt;
    o.repeated_lines = nullptr;  // the written program's lines are not the original's
    interp::interpret(out, o, diags, both);
    if (diags.errors()) fail(1, "the written program does not read back cleanly:\n" + errs.str());
  }
  // What diff and simulate --reference will find from the structure alone must
  // be what deflex did, or they would judge the program against the wrong blocks.
  const LinePairing found = pair_lines(fa, fb, pairing_options(max_offset_mm));
  for (std::uint32_t ol = 1; ol <= out.line_count(); ++ol)
    if (found.a_of_b[ol] != want.a_of_b[ol] || found.parent_of_b[ol] != want.parent_of_b[ol])
      fail(want.a_of_b[ol] ? want.a_of_b[ol] : want.parent_of_b[ol],
           "the written program does not pair with the original block by block (line " + std::to_string(ol) +
               " of the output)");
  check.finish();
}

}  // namespace deflex::compensate
