#include "ply_header.hpp"

#include <charconv>

#include "deflex/measure/text.hpp"

namespace deflex::measure::ply {
namespace {

using detail::fail;
using detail::Field;

// Both spellings of the format description (Turk 1994 and the later
// int8 ... float64 names of rply and MeshLab).
bool type_named(std::string_view s, Type& t) {
  static const std::pair<std::string_view, Type> names[] = {
      {"char", Type::i8},   {"int8", Type::i8},   {"uchar", Type::u8},   {"uint8", Type::u8},
      {"short", Type::i16}, {"int16", Type::i16}, {"ushort", Type::u16}, {"uint16", Type::u16},
      {"int", Type::i32},   {"int32", Type::i32}, {"uint", Type::u32},   {"uint32", Type::u32},
      {"float", Type::f32}, {"float32", Type::f32}, {"double", Type::f64}, {"float64", Type::f64}};
  for (const auto& [n, type] : names)
    if (s == n) return t = type, true;
  return false;
}

class HeaderReader {
 public:
  HeaderReader(const SourceText& src, Header& h) : src_(src), h_(h) {}
  void line(std::uint32_t l, const std::vector<Field>& w);
  void finish(std::uint32_t end_line);

 private:
  void format(std::uint32_t l, const std::vector<Field>& w);
  void element(std::uint32_t l, const std::vector<Field>& w);
  void property(std::uint32_t l, const std::vector<Field>& w);
  const SourceText& src_;
  Header& h_;
  bool have_format_ = false;
};

void HeaderReader::format(std::uint32_t l, const std::vector<Field>& w) {
  if (have_format_) fail(src_, l, w[0].col, "a second format line");
  if (!h_.elements.empty()) fail(src_, l, w[0].col, "the format line must come before the elements");
  if (w.size() != 3) fail(src_, l, w[0].col, "expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
  if (w[1].text == "ascii") h_.format = Format::ascii;
  else if (w[1].text == "binary_little_endian") h_.format = Format::binary_le;
  else if (w[1].text == "binary_big_endian") h_.format = Format::binary_be;
  else fail(src_, l, w[1].col, "unknown format " + detail::quoted(w[1].text) + " (expected ascii, binary_little_endian or binary_big_endian)");
  if (w[2].text != "1.0") fail(src_, l, w[2].col, "PLY version " + detail::quoted(w[2].text) + " (deflex reads 1.0)");
  have_format_ = true;
}

void HeaderReader::element(std::uint32_t l, const std::vector<Field>& w) {
  if (w.size() != 3) fail(src_, l, w[0].col, "expected 'element <name> <count>'");
  Element e;
  e.name = std::string(w[1].text);
  const std::string_view c = w[2].text;
  const auto [end, ec] = std::from_chars(c.data(), c.data() + c.size(), e.count);
  if (ec != std::errc() || end != c.data() + c.size()) fail(src_, l, w[2].col, "the count " + detail::quoted(c) + " is not a whole number >= 0");
  for (const Element& o : h_.elements)
    if (o.name == e.name) fail(src_, l, w[1].col, "a second element " + detail::quoted(e.name));
  h_.elements.push_back(std::move(e));
}

void HeaderReader::property(std::uint32_t l, const std::vector<Field>& w) {
  if (h_.elements.empty()) fail(src_, l, w[0].col, "a property before any element");
  Property p;
  const bool list = w.size() >= 2 && w[1].text == "list";
  if (w.size() != (list ? 5u : 3u))
    fail(src_, l, w[0].col, "expected 'property <type> <name>' or 'property list <count type> <item type> <name>'");
  std::size_t k = 1;
  if (list) {
    p.list = true;
    if (!type_named(w[2].text, p.count_type) || !is_integral(p.count_type))
      fail(src_, l, w[2].col, "a list's count type must be a PLY integer type, not " + detail::quoted(w[2].text));
    k = 3;
  }
  if (!type_named(w[k].text, p.type)) fail(src_, l, w[k].col, "unknown type " + detail::quoted(w[k].text));
  p.name = std::string(w[k + 1].text);
  Element& e = h_.elements.back();
  for (const Property& o : e.props)
    if (o.name == p.name) fail(src_, l, w[k + 1].col, "a second property " + detail::quoted(p.name) + " of " + e.name);
  e.props.push_back(std::move(p));
}

void HeaderReader::line(std::uint32_t l, const std::vector<Field>& w) {
  if (w.empty()) return;
  const std::string_view k = w[0].text;
  if (k == "comment" || k == "obj_info") return;
  if (k == "format") format(l, w);
  else if (k == "element") element(l, w);
  else if (k == "property") property(l, w);
  else fail(src_, l, w[0].col, "unknown header line " + detail::quoted(k) + " (expected format, element, property, comment, end_header)");
}

void HeaderReader::finish(std::uint32_t end_line) {
  if (!have_format_) fail(src_, end_line, 1, "the header has no format line");
  bool found = false;
  for (std::size_t i = 0; i < h_.elements.size(); ++i) {
    const Element& e = h_.elements[i];
    if (e.props.empty()) fail(src_, end_line, 1, "element " + detail::quoted(e.name) + " has no property");
    if (e.name != "vertex") continue;
    found = true;
    h_.vertex = i;
    for (int a = 0; a < 3; ++a) {
      const std::string axis(1, "xyz"[a]);
      std::size_t k = 0;
      while (k < e.props.size() && e.props[k].name != axis) ++k;
      if (k == e.props.size() || e.props[k].list)
        fail(src_, end_line, 1, "the vertex element has no number property " + axis);
      h_.xyz[a] = k;
    }
  }
  if (!found) fail(src_, end_line, 1, "no vertex element: a point cloud's points are its vertices");
  if (h_.elements[h_.vertex].count == 0) fail(src_, end_line, 1, "the header says the cloud has no vertex");
}

}  // namespace

std::size_t size_of(Type t) {
  switch (t) {
    case Type::i8: case Type::u8: return 1;
    case Type::i16: case Type::u16: return 2;
    case Type::i32: case Type::u32: case Type::f32: return 4;
    case Type::f64: return 8;
  }
  return 1;
}

bool is_integral(Type t) { return t != Type::f32 && t != Type::f64; }

Header read_header(const std::string& bytes, const std::string& file) {
  // The header's lines alone: a binary body has no lines.
  std::size_t end = 0;
  std::uint32_t lines = 0;
  bool found = false;
  while (end < bytes.size() && !found) {
    const std::size_t nl = bytes.find('\n', end);
    const std::size_t stop = nl == std::string::npos ? bytes.size() : nl;
    found = detail::trim(std::string_view(bytes).substr(end, stop - end)) == "end_header";
    end = nl == std::string::npos ? bytes.size() : nl + 1;
    ++lines;
  }
  const SourceText src(file, bytes.substr(0, end));
  if (src.line_count() == 0) fail(src, 1, 1, "the file is empty: expected a PLY file ('ply' first)");
  if (detail::trim(src.line_text(1)) != "ply") fail(src, 1, 1, "not a PLY file: its first line must be 'ply'");
  if (!found) fail(src, src.last_line(), 1, "the header has no end_header line");
  Header h;
  HeaderReader r(src, h);
  for (std::uint32_t l = 2; l < lines; ++l) r.line(l, detail::words(src.line_text(l)));
  r.finish(lines);
  h.data_begin = end;
  h.data_line = lines + 1;
  return h;
}

}  // namespace deflex::measure::ply
