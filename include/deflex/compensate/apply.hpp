// Writing a compensated program and proving it is what deflex meant.
#pragma once
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
std::string apply_offsets(const gcode::Program& prog, const profile::Dialect& d,
                          const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets,
                          WriteStats* stats = nullptr, const std::vector<bool>* inserted = nullptr,
                          const std::vector<double>* feeds_mm_per_min = nullptr);

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
// max_offset_mm. Throws Error(Exit::internal) naming the first difference.
// With `inserted` (may be null; `original_motions` then includes the inserted
// ones): each inserted block holds only N, G1, X, Y, Z, F and its motion ends
// within max_offset_mm of the move it splits.
void safety_check(const gcode::Program& original, const std::vector<interp::Motion>& original_motions,
                  const std::string& text, const interp::Options& opt, const std::vector<bool>& movable,
                  double max_offset_mm, const std::vector<bool>* inserted = nullptr,
                  const std::vector<double>* feeds_mm_per_min = nullptr);
// The same on the written program already read (it keeps the only copy of the
// text: at 10M blocks a second one is 280 MB).
void safety_check(const gcode::Program& original, const std::vector<interp::Motion>& original_motions,
                  const gcode::Program& written, const interp::Options& opt, const std::vector<bool>& movable,
                  double max_offset_mm, const std::vector<bool>* inserted = nullptr,
                  const std::vector<double>* feeds_mm_per_min = nullptr);

}  // namespace deflex::compensate
