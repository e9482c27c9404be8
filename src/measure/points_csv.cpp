// A CMM's CSV export of surface points (samples.hpp).
#include <algorithm>
#include <cctype>
#include <map>

#include "deflex/measure/samples.hpp"
#include "deflex/measure/text.hpp"

namespace deflex::measure {
namespace {

using detail::Field;
using detail::fail;

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// A field in double quotes, as spreadsheets write header names, without them.
std::string_view unquote(std::string_view s) {
  return s.size() >= 2 && s.front() == '"' && s.back() == '"' ? s.substr(1, s.size() - 2) : s;
}

struct Columns {
  std::size_t count = 0;
  std::size_t xyz[3] = {0, 0, 0};
  std::optional<std::size_t> id;
};

// Why a header without x_mm may still name the axis: in another unit or in
// none. A CMM's inch export read as mm would be a 25.4x error.
std::string missing_axis(const std::vector<Field>& f, char axis) {
  const std::string a(1, axis);
  for (const Field& x : f) {
    const std::string n = lower(unquote(x.text));
    if (n == a + "_in" || n == a + "_inch" || n == a + "_inches")
      return "column '" + std::string(unquote(x.text)) + "' is in inches: deflex reads millimetres " +
             "(export in mm, with columns x_mm,y_mm,z_mm)";
    if (n == a) return "column '" + std::string(unquote(x.text)) + "' gives no unit: name it " + a + "_mm " +
                       "(millimetres) so that a unit slip cannot pass";
    if (n.starts_with(a + "_")) return "column '" + std::string(unquote(x.text)) + "' is not in mm (expected " + a + "_mm)";
  }
  return "no column " + a + "_mm (the header must name x_mm, y_mm and z_mm)";
}

Columns header(const SourceText& src, std::uint32_t line, std::vector<Field> f) {
  // Spreadsheets on Windows begin a UTF-8 file with a byte order mark.
  if (f.front().text.starts_with("\xEF\xBB\xBF")) f.front().text.remove_prefix(3), f.front().col += 3;
  // A spreadsheet in a locale with a decimal comma separates by ';'.
  if (f.size() == 1 && f.front().text.find(';') != std::string_view::npos)
    fail(src, line, f.front().col, "fields separated by ';': deflex reads comma-separated values with a decimal point");
  if (detail::number(f.front().text))
    fail(src, line, f.front().col, "the first line is data, not a header: expected a header naming x_mm,y_mm,z_mm");
  Columns c;
  c.count = f.size();
  std::map<std::string, std::size_t> seen;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const std::string n = lower(unquote(f[i].text));
    if (n.empty()) continue;  // an unnamed column is ignored like any other
    if (auto [it, fresh] = seen.emplace(n, i); !fresh)
      fail(src, line, f[i].col, "column " + detail::quoted(f[i].text) + " given twice");
  }
  const char* names[3] = {"x_mm", "y_mm", "z_mm"};
  for (int a = 0; a < 3; ++a) {
    const auto it = seen.find(names[a]);
    if (it == seen.end()) fail(src, line, 1, missing_axis(f, "xyz"[a]));
    c.xyz[a] = it->second;
  }
  if (auto it = seen.find("id"); it != seen.end()) c.id = it->second;
  return c;
}

Sample row(const SourceText& src, std::uint32_t line, const std::vector<Field>& f, const Columns& c) {
  if (f.size() != c.count) {
    const std::uint32_t col = f.size() > c.count ? f[c.count].col - 1 : static_cast<std::uint32_t>(src.line_text(line).size() + 1);
    fail(src, line, col, "expected " + std::to_string(c.count) + " fields as the header names, found " + std::to_string(f.size()));
  }
  Sample s;
  s.line = line;
  for (int a = 0; a < 3; ++a) {
    const Field& x = f[c.xyz[a]];
    const auto v = detail::number(unquote(x.text));
    if (!v) fail(src, line, x.col, std::string(1, "xyz"[a]) + "_mm: " + detail::not_a_number(x.text));
    s.p_mm[a] = *v;
  }
  if (c.id) {
    const Field& x = f[*c.id];
    const auto id = detail::positive_int(unquote(x.text));
    if (!id) fail(src, line, x.col, "id " + detail::quoted(x.text) + " is not a positive whole number");
    s.id = *id;
  }
  return s;
}

}  // namespace

std::vector<Sample> read_points_csv(const std::string& text, const std::string& file) {
  const SourceText src(file, text);
  std::optional<Columns> cols;
  std::uint32_t header_line = 0;
  std::vector<Sample> out;
  std::map<int, std::uint32_t> id_line;
  for (std::uint32_t l = 1; l <= src.line_count(); ++l) {
    const std::string_view t = detail::trim(src.line_text(l));
    if (t.empty() || t.front() == '#') continue;
    const std::vector<Field> f = detail::comma_fields(src.line_text(l));
    if (!cols) {
      cols = header(src, l, f);
      header_line = l;
      continue;
    }
    out.push_back(row(src, l, f, *cols));
    if (out.back().id < 0) continue;
    if (auto [it, fresh] = id_line.emplace(out.back().id, l); !fresh)
      fail(src, l, f[*cols->id].col,
           "id " + std::to_string(it->first) + " given twice (first on line " + std::to_string(it->second) + ")");
  }
  if (!cols) fail(src, std::max<std::uint32_t>(1, src.last_line()), 1,
                  src.line_count() ? "no header: expected a line naming x_mm,y_mm,z_mm" : "the file is empty: expected a header x_mm,y_mm,z_mm and points");
  if (out.empty()) fail(src, header_line, 1, "no points after the header");
  return out;
}

}  // namespace deflex::measure
