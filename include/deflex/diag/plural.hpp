// A count with its noun for messages and summaries: "1 point", "2 points".
#pragma once
#include <cstdint>
#include <string>

namespace deflex {

// `n` and `one` (the singular) for n == 1, else `many` (default: one + "s").
inline std::string plural(std::uint64_t n, const std::string& one, const std::string& many = "") {
  return std::to_string(n) + " " + (n == 1 ? one : many.empty() ? one + "s" : many);
}

}  // namespace deflex
