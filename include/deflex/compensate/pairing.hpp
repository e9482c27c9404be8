// Pairing a compensated program with its original, from the program structure.
//
// deflex changes only coordinate words and inserts `G1 X Y Z [F]` blocks (N
// per the dialect) before the block of a move they split or an arc they
// linearise. So every block of the original has its block in the output with
// the same skeleton (gcode/skeleton.hpp), in the same order, and every block
// only in the output is an inserted one. The one place that knows this is here:
// the safety check, `simulate --reference` and `diff` all pair through it.
//
// Lines are aligned in memory linear in the programs' size: lines whose
// skeleton is unique on both sides are anchors (patience: the longest run of
// them in the same order), recursively inside the gaps; then lines whose whole
// text is unique on both sides (unchanged blocks pair exactly); what is left
// is matched in order, a line of the output that has the form of an inserted
// block and lies on the next original move being taken as inserted where the
// line after it pairs better with that move.
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "deflex/compensate/compensate.hpp"
#include "deflex/gcode/program.hpp"
#include "deflex/interp/motion.hpp"

namespace deflex::compensate {

// The geometry of a motion that pairing needs.
struct PathPiece {
  interp::MotionKind kind = interp::MotionKind::rapid;
  std::uint8_t plane = 17;
  interp::Vec3 start_mm{}, end_mm{}, center_mm{};
};
PathPiece piece_of(const interp::Motion& m);

// What pairing knows of one line of a program.
struct LineFacts {
  std::uint64_t skeleton = 0;  // gcode::skeleton_hash (F left out when pairing a --feed-limit output)
  std::uint64_t text = 0;      // hash of the whole line, blanks left out
  std::uint32_t motions = 0;   // motions the block commands
  bool split_form = false;     // words only N, G1, X, Y, Z, F (an axis at least), no comment
  PathPiece path;              // start of its first motion; end, kind, centre of its last
};

// Fills the motion part of the facts (index = line number, [0] unused) as the
// interpreter gives the motions, so a caller need not keep them all.
struct LineFactsSink : interp::MotionSink {
  std::vector<LineFacts>* lines = nullptr;
  void motion(const interp::Motion& m) override;
};
// Fills the text part (skeleton, text, split_form) of every line; `lines` has
// p.line_count() + 1 entries.
void fill_line_text(const gcode::Program& p, std::vector<LineFacts>& lines, bool ignore_feed);
// Both, from the program and its motions.
std::vector<LineFacts> line_facts(const gcode::Program& p, const std::vector<interp::Motion>& motions,
                                  bool ignore_feed);

struct PairingOptions {
  // An inserted block lies within this of the move it splits; within it, the
  // nearer of two candidate blocks pairs with a move (mm).
  double near_mm = 1.0;
};
// What the safety check and simulate --reference use for a machine whose
// offsets are capped at max_offset_mm: the same, so what passes the one is
// judged alike by the other.
PairingOptions pairing_options(double max_offset_mm);

// Line-level pairing of program A (the original) with B (e.g. compensated).
struct LinePairing {
  std::vector<std::uint32_t> a_of_b;     // per line of B: its line in A, 0 if only in B
  std::vector<std::uint32_t> b_of_a;     // per line of A: its line in B, 0 if only in A
  std::vector<std::uint32_t> parent_of_b;  // per line of B only in B: the line of A whose move it splits, else 0
  std::size_t work_entries = 0;          // largest number of entries the alignment held at once (memory check)
  bool inserted(std::uint32_t line_b) const { return parent_of_b[line_b] != 0; }
};

LinePairing pair_lines(const std::vector<LineFacts>& a, const std::vector<LineFacts>& b, const PairingOptions& o = {});

// The pairing deflex means when it inserted inserted_before[l] blocks right
// before line l of A (at least lines_a + 1 entries); what the safety check expects.
LinePairing expected_pairing(const std::vector<std::uint32_t>& inserted_before, std::uint32_t lines_a,
                             std::uint32_t lines_b);

// Where a point meant to lie on `piece` should be: the nearest point on the
// move (segment), or on the arc's circle in its plane.
V3 nearest_on(const PathPiece& piece, const interp::Vec3& p);

// One motion of B and its counterpart in A's motion list.
struct MotionPair {
  static constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
  std::size_t original = none;  // the same motion of A; for an inserted one, the motion it splits
  bool inserted = false;
};

// Pairs B's motions, given in order, with A's through the line pairing.
class MotionPairer {
 public:
  // `passed_over` (may be null): motions of `a` that are not A's (compensate's
  // own inserted motions, when `a` is its list).
  MotionPairer(const LinePairing& lines, const std::vector<interp::Motion>& a,
               const std::vector<bool>* passed_over = nullptr);
  // The counterpart of B's next motion; original == none when it has none.
  MotionPair next(const interp::Motion& b);
  bool complete();  // every motion of A paired

 private:
  void skip_passed_over();
  const LinePairing& lines_;
  const std::vector<interp::Motion>& a_;
  const std::vector<bool>* passed_over_;
  std::size_t k_ = 0;
};

// Per motion of B: its end minus the point it was meant to reach on A (the
// judge's intent offset). Exactly zero for a motion deflex left alone. Throws
// Error(ErrorKind::input) naming the first motion of B without a counterpart.
std::vector<V3> intent_offsets(const LinePairing& lines, const std::vector<interp::Motion>& a,
                               const std::vector<interp::Motion>& b, const std::string& name_b);

}  // namespace deflex::compensate
