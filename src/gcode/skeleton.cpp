#include "deflex/gcode/skeleton.hpp"

namespace deflex::gcode {

bool is_coordinate_letter(char l) {
  return l == 'X' || l == 'Y' || l == 'Z' || l == 'I' || l == 'J' || l == 'K' || l == 'R';
}

std::uint64_t skeleton_hash(const Program& p, const Block& b, bool ignore_feed) {
  const std::string& bytes = p.bytes();
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a
  auto add = [&](std::uint32_t from, std::uint32_t to) {
    for (std::uint32_t i = from; i < to; ++i) {
      char c = bytes[i];
      if (c == ' ' || c == '\t') continue;
      h ^= static_cast<unsigned char>(c);
      h *= 1099511628211ull;
    }
  };
  std::uint32_t at = b.begin;
  for (const Word& w : b.words) {
    if (!is_coordinate_letter(w.letter) && !(ignore_feed && w.letter == 'F')) continue;
    add(at, w.begin);
    at = w.end;
  }
  add(at, b.text_end);
  return h;
}

}  // namespace deflex::gcode
