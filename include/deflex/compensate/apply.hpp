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
};

// The program with each motion's end moved by offsets[i]: numbers spliced into
// the X/Y/Z words of plain blocks; where a block relies on a modal axis value
// that the previous block changed, the axis word is added with the value the
// block means. Untouched bytes are copied. All offsets zero: the input itself.
std::string apply_offsets(const gcode::Program& prog, const profile::Dialect& d,
                          const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets,
                          WriteStats* stats = nullptr);

// Reads `text` back as the control would and pairs every motion with the
// original: the same motions of the same kinds on the same lines, every block
// equal but for its coordinate words, non-movable motions where they were
// (within the rounding of the written numbers), movable ones moved by at most
// max_offset_mm. Throws Error(Exit::internal) naming the first difference.
void safety_check(const gcode::Program& original, const std::vector<interp::Motion>& original_motions,
                  const std::string& text, const interp::Options& opt, const std::vector<bool>& movable,
                  double max_offset_mm);

}  // namespace deflex::compensate
