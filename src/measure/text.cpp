#include "deflex/measure/text.hpp"

#include <charconv>
#include <cmath>
#include <limits>

namespace deflex::measure::detail {

void fail(const SourceText& src, std::uint32_t line, std::uint32_t col, const std::string& message) {
  // Diagnostics::report builds the excerpt (a window of a long line, control
  // bytes escaped); format() prints it as every other located error of deflex.
  Diagnostics d(nullptr, 0);
  d.report(Severity::error, src, line, col, message);
  throw Error(ErrorKind::input, format(d.all().back())).with_errors_of(d);
}

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

std::vector<Field> words(std::string_view line) {
  std::vector<Field> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_blank(line[i])) ++i;
    const std::size_t b = i;
    while (i < line.size() && !is_blank(line[i])) ++i;
    if (i > b) out.push_back({line.substr(b, i - b), static_cast<std::uint32_t>(b + 1)});
  }
  return out;
}

std::vector<Field> comma_fields(std::string_view line) {
  std::vector<Field> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    const std::size_t end = comma == std::string_view::npos ? line.size() : comma;
    std::size_t b = start;
    while (b < end && is_blank(line[b])) ++b;
    out.push_back({trim(line.substr(b, end - b)), static_cast<std::uint32_t>(b + 1)});
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

std::optional<double> number(std::string_view s) {
  // from_chars takes no '+'; "+-1" must stay an error.
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string not_a_number(std::string_view s) {
  if (s.empty()) return "an empty field is not a number";
  double v = 0;
  std::string_view t = s;
  if (t.size() > 1 && t[0] == '+') t.remove_prefix(1);
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (end == t.data() + t.size() && ec == std::errc() && !std::isfinite(v))
    return quoted(s) + " is not a finite number";
  if (ec == std::errc::result_out_of_range) return quoted(s) + " is out of range";
  return quoted(s) + " is not a number";
}

std::optional<int> positive_int(std::string_view s) {
  if (s.empty() || s.size() > 9) return std::nullopt;  // 9 digits: no overflow of int
  int v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
    v = v * 10 + (c - '0');
  }
  if (v <= 0) return std::nullopt;
  return v;
}

std::string quoted(std::string_view s) {
  constexpr std::size_t kMax = 40;
  return "'" + std::string(s.substr(0, kMax)) + (s.size() > kMax ? "...'" : "'");
}

}  // namespace deflex::measure::detail
