// The (DEFLEX PROBE ...) comments of deflex's probe program (probe.hpp).
#include <algorithm>
#include <cmath>

#include "deflex/measure/probe.hpp"
#include "deflex/measure/text.hpp"

namespace deflex::measure {
namespace {

using detail::fail;
using detail::Field;

constexpr std::string_view kOpen = "(DEFLEX PROBE";
constexpr std::string_view kForm = "(DEFLEX PROBE <id> <feature> AT <x> <y> <z> N <nx> <ny> <nz> BALL <radius>)";

// A number as the probe program writes it: [-+]digits.digits, the decimal
// point required (a Fanuc reader of the same program takes 10 for 10 increments).
std::optional<double> decimal(std::string_view s) {
  std::size_t i = !s.empty() && (s[0] == '-' || s[0] == '+') ? 1 : 0;
  int points = 0, digits = 0;
  for (; i < s.size(); ++i) {
    if (s[i] == '.') ++points;
    else if (s[i] >= '0' && s[i] <= '9') ++digits;
    else return std::nullopt;
  }
  if (points != 1 || digits == 0) return std::nullopt;
  return detail::number(s);
}

bool feature_name(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

struct Comment {
  const SourceText& src;
  std::uint32_t line;
  std::vector<Field> w;   // the words between "(DEFLEX PROBE" and ')'
  std::uint32_t end_col;  // of the ')'

  [[noreturn]] void bad(std::size_t k, const std::string& why) const {
    fail(src, line, k < w.size() ? w[k].col : end_col, why + "; expected " + std::string(kForm));
  }
  void keyword(std::size_t k, std::string_view kw) const {
    if (k >= w.size() || w[k].text != kw) bad(k, "expected " + std::string(kw));
  }
  double value(std::size_t k, const char* what) const {
    if (k >= w.size()) bad(k, std::string("missing ") + what);
    const auto v = decimal(w[k].text);
    if (!v) bad(k, std::string(what) + ": " + detail::quoted(w[k].text) + " is not a number with a decimal point");
    return *v;
  }
};

ProbeTarget target(const Comment& c) {
  ProbeTarget t;
  t.line = c.line;
  if (c.w.empty()) c.bad(0, "missing the point's id");
  const auto id = detail::positive_int(c.w[0].text);
  if (!id) c.bad(0, "the id " + detail::quoted(c.w[0].text) + " is not a whole number >= 1");
  t.id = *id;
  if (c.w.size() < 2 || !feature_name(c.w[1].text)) c.bad(1, "missing the feature's name (letters, digits, '_')");
  t.feature = std::string(c.w[1].text);
  c.keyword(2, "AT");
  for (int a = 0; a < 3; ++a) t.point_mm[a] = c.value(3 + a, "the point's coordinate");
  c.keyword(6, "N");
  Eigen::Vector3d n;
  for (int a = 0; a < 3; ++a) n[a] = c.value(7 + a, "the normal's component");
  c.keyword(10, "BALL");
  t.ball_radius_mm = c.value(11, "the ball radius");
  if (c.w.size() > 12) c.bad(12, "unexpected " + detail::quoted(c.w[12].text));
  // 1e-3: the program prints three decimals, which keeps |N| within ~1e-3 of 1.
  if (!(std::abs(n.norm() - 1) <= 1e-3))
    c.bad(7, "the normal has length " + std::to_string(n.norm()) + ", not 1 (an outward unit normal)");
  t.normal = n.normalized();
  if (!(t.ball_radius_mm > 0)) c.bad(11, "the ball radius must be > 0");
  return t;
}

}  // namespace

std::vector<ProbeTarget> read_probe_targets(const std::string& text, const std::string& file) {
  const SourceText src(file, text);
  std::vector<ProbeTarget> out;
  for (std::uint32_t l = 1; l <= src.line_count(); ++l) {
    const std::string_view t = src.line_text(l);
    for (std::size_t at = t.find(kOpen); at != std::string_view::npos; at = t.find(kOpen, at + 1)) {
      const std::size_t from = at + kOpen.size();
      const std::size_t close = t.find(')', from);
      if (close == std::string_view::npos) fail(src, l, static_cast<std::uint32_t>(at + 1), "DEFLEX PROBE comment without ')'");
      Comment c{src, l, detail::words(t.substr(from, close - from)), static_cast<std::uint32_t>(close + 1)};
      if (c.w.empty() || c.w[0].col != 2) c.bad(0, "expected one blank after PROBE");
      for (Field& f : c.w) f.col += static_cast<std::uint32_t>(from);
      out.push_back(target(c));
      const int want = static_cast<int>(out.size());
      if (out.back().id != want)
        fail(src, l, c.w[0].col, "probe point " + std::to_string(out.back().id) + " out of order: expected " +
                                     std::to_string(want) + " (ids run 1, 2, 3 ... in program order)");
    }
  }
  if (out.empty())
    fail(src, 1, 1, "no (DEFLEX PROBE ...) comment: is this deflex's probe program?");
  return out;
}

}  // namespace deflex::measure
