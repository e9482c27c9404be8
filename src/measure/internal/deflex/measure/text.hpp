// What the text readers of src/measure share (and the FRF reader of
// src/stability): located errors through the project's Diagnostics (source
// line and caret), fields of a line, numbers. A header of this build only,
// never installed (cmake/modules.cmake: src/<module>/internal/).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::measure::detail {

// Throws Error(ErrorKind::input) whose text is the Diagnostic as the compiler
// prints it (file:line:col: error: message, the line, a caret), carrying the
// Diagnostic for callers that want its location.
[[noreturn]] void fail(const SourceText& src, std::uint32_t line, std::uint32_t col, const std::string& message);

// A piece of a line and its 1-based column.
struct Field {
  std::string_view text;
  std::uint32_t col = 1;
};

bool is_blank(char c);
std::string_view trim(std::string_view s);
// Whitespace-separated words of a line.
std::vector<Field> words(std::string_view line);
// Comma-separated fields of a line, each trimmed of blanks (col: its first
// byte that is not blank, or where it would be when it is empty).
std::vector<Field> comma_fields(std::string_view line);

// The whole of `s` as a finite decimal number (std::from_chars: locale-free,
// exact, correctly rounded; a leading '+' allowed). nullopt: not a number, or
// not all of `s`, or NaN, infinite, out of range.
std::optional<double> number(std::string_view s);
// Why `s` is no number, for a message: "'x' is not a number", "'nan' is not finite".
std::string not_a_number(std::string_view s);

// `s` as a positive int (digits only, no sign).
std::optional<int> positive_int(std::string_view s);

// `s` shown in a message, cut to a readable length.
std::string quoted(std::string_view s);

}  // namespace deflex::measure::detail
