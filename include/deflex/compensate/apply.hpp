// Writing a compensated program and proving it is what deflex meant.
#pragma once
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "deflex/compensate/compensate.hpp"
#include "deflex/gcode/program.hpp"
#include "deflex/interp/interpreter.hpp"

namespace deflex::compensate {

struct WriteStats {
  std::size_t numbers_changed = 0;  // coordinate numbers replaced
  std::size_t words_inserted = 0;   // axis words added where a modal value would carry an offset
  std::size_t blocks_inserted = 0;  // G1 blocks splitting a move
  std::size_t feeds_changed = 0;    // F words set or added (--feed-limit)
};

// The program with each motion's end moved by offsets[i]: numbers spliced into
// the X/Y/Z words of plain blocks; where a block relies on a modal axis value
// that the previous block changed, the axis word is added with the value the
// block means. Untouched bytes are copied. All offsets zero: the input itself.
// `inserted` (may be null): motions that are new blocks, written as
// `G1 X Y Z [F]` before the block of the next motion that is not inserted.
// What the writer carries from one piece of a program to the next when the
// program is written in pieces (null: the whole program in one call).
struct WriteState {
  double carried_mm[3] = {NAN, NAN, NAN};  // what the output program's control holds
  double carried_feed = NAN;               // its modal F (--feed-limit), mm/min
  std::uint32_t scanned = 0;               // the last line looked at for F words
  std::map<long, long> numbers_taken;      // N numbers taken by inserted blocks (writer::Rewriter)
  // The lines of `prog` to write, set per piece: a piece is read with lines of
  // context around it (the N numbers of inserted blocks look 200 lines about).
  std::uint32_t first_line = 0, last_line = 0;
  // The unit of the motion after the piece: the F words of the lines after its
  // last motion count in it (as on the whole program, where that motion reads them).
  bool inch_after = false;
};
std::string apply_offsets(const gcode::Program& prog, const profile::Dialect& d,
                          const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets,
                          WriteStats* stats = nullptr, const std::vector<bool>* inserted = nullptr,
                          const std::vector<double>* feeds_mm_per_min = nullptr, WriteState* state = nullptr);

// Per motion: whether its block may be split by inserting G1 blocks before it:
// a plain, compensable G1 whose block holds nothing but N, G1, X, Y, Z and F;
// or a plain, compensable arc in its plane (no helix) whose block holds its own
// G2/G3 word and nothing but N, X, Y, Z, I, J, K and F (centre by I/J/K, not R):
// its first part can then go into G1 chords before it.
std::vector<bool> splittable(const gcode::Program& prog, const std::vector<interp::Motion>& motions);

// Reads `text` back as the control would and pairs every motion with the
// original: the same motions of the same kinds on the same lines, every block
// equal but for its coordinate words, non-movable motions where they were
// (within the rounding of the written numbers), movable ones moved by at most
// max_offset_mm. Throws Error(ErrorKind::internal) naming the first difference.
// With `inserted` (may be null; `original_motions` then includes the inserted
// ones): each inserted block holds only N, G1, X, Y, Z, F and its motion ends
// within max_offset_mm of the move it splits.
void safety_check(const gcode::Program& original, const std::vector<interp::Motion>& original_motions,
                  const std::string& text, const interp::Options& opt, const std::vector<bool>& movable,
                  double max_offset_mm, const std::vector<bool>* inserted = nullptr,
                  const std::vector<double>* feeds_mm_per_min = nullptr);
// The interpreter of a program written in pieces, carried from one piece of
// it to the next (the control's state at the start of a piece is what the
// pieces before left).
class ReadBack {
 public:
  explicit ReadBack(const interp::Options& opt);
  ~ReadBack();
  // The piece's motions to `sink`; false, with the messages, when it does not
  // read cleanly.
  bool read(const gcode::Program& piece, interp::MotionSink& sink, std::string& errors);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The same on the written program already read (it keeps the only copy of the
// text: at 10M blocks a second one is 280 MB). In pieces: `original` and
// `written` are a piece each, numbered from line 1 (its motions too),
// `read_back` carries the written program's state, and `line_base` is added
// to the line numbers of the messages.
void safety_check(const gcode::Program& original, const std::vector<interp::Motion>& original_motions,
                  const gcode::Program& written, const interp::Options& opt, const std::vector<bool>& movable,
                  double max_offset_mm, const std::vector<bool>* inserted = nullptr,
                  const std::vector<double>* feeds_mm_per_min = nullptr, ReadBack* read_back = nullptr,
                  std::uint32_t line_base = 0);

}  // namespace deflex::compensate
