// Numbers in words for messages and summaries: a count with its noun ("1
// point", "2 points"), a value with a fixed number of decimals or of
// significant digits.
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>

namespace deflex {

// `n` and `one` (the singular) for n == 1, else `many` (default: one + "s").
inline std::string plural(std::uint64_t n, const std::string& one, const std::string& many = "") {
  return std::to_string(n) + " " + (n == 1 ? one : many.empty() ? one + "s" : many);
}

// `v` with `decimals` decimals ("2.500"), as a message or a program comment shows it.
inline std::string fixed_decimals(double v, int decimals) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

// `v` to 10 significant digits, trailing zeros dropped ("0.05", "1e-06"):
// a value as given, without the noise of its binary fraction.
inline std::string significant_digits(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

}  // namespace deflex
