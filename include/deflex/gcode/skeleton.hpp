// The "skeleton" of a block: everything but its coordinate words. Two blocks
// with equal skeletons differ at most in X Y Z I J K R words (their numbers,
// their presence, the blanks around them) — what deflex is allowed to change.
#pragma once
#include <cstdint>

#include "deflex/gcode/program.hpp"

namespace deflex::gcode {

bool is_coordinate_letter(char letter);

// 64-bit hash of the block's bytes without its coordinate words and without
// blanks; `b` is the lexed line.
// With ignore_feed, F words are left out too (deflex --feed-limit changes them).
std::uint64_t skeleton_hash(const Program& p, const Block& b, bool ignore_feed = false);

}  // namespace deflex::gcode
