// PLY point clouds: the vertices of an ascii or binary PLY file (samples.hpp),
// every other element read past by its declared properties.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>

#include "deflex/diag/plural.hpp"
#include "deflex/measure/samples.hpp"
#include "ply_header.hpp"
#include "deflex/measure/text.hpp"

namespace deflex::measure {
namespace {

using ply::Element;
using ply::Header;
using ply::Property;
using ply::Type;

// A value of type t at p, in the file's byte order.
double value_at(const char* p, Type t, bool big_endian) {
  unsigned char b[8];
  const std::size_t n = ply::size_of(t);
  std::memcpy(b, p, n);
  if (big_endian != (std::endian::native == std::endian::big)) std::reverse(b, b + n);
  auto as = [&b]<class T>(T v) {
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  };
  switch (t) {
    case Type::i8: return as(std::int8_t{});
    case Type::u8: return as(std::uint8_t{});
    case Type::i16: return as(std::int16_t{});
    case Type::u16: return as(std::uint16_t{});
    case Type::i32: return as(std::int32_t{});
    case Type::u32: return as(std::uint32_t{});
    case Type::f32: return as(float{});
    case Type::f64: return as(double{});
  }
  return 0;
}

class BinaryBody {
 public:
  BinaryBody(const std::string& bytes, const std::string& file, const Header& h)
      : bytes_(bytes), file_(file), h_(h), big_(h.format == ply::Format::binary_be), at_(h.data_begin) {}
  std::vector<Sample> read();

 private:
  [[noreturn]] void bad(const std::string& why) const {
    throw Error(ErrorKind::input, file_ + ": error: " + e_->name + " " + std::to_string(k_) + " at byte " +
                                      std::to_string(start_) + ": " + why);
  }
  // The next n bytes, or an error naming what the file should still hold.
  const char* take(std::uint64_t n, const std::string& what) {
    if (bytes_.size() - at_ < n)
      bad("the file ends inside its " + what + " (the header says 'element " + e_->name + " " + std::to_string(e_->count) + "')");
    const char* p = bytes_.data() + at_;
    at_ += static_cast<std::size_t>(n);
    return p;
  }
  void element(std::vector<Sample>& out);

  const std::string& bytes_;
  const std::string& file_;
  const Header& h_;
  bool big_;
  std::size_t at_;
  const Element* e_ = nullptr;
  std::uint64_t k_ = 0;       // index of the element being read
  std::size_t start_ = 0;     // its first byte
};

void BinaryBody::element(std::vector<Sample>& out) {
  const bool vertex = e_ == &h_.elements[h_.vertex];
  Sample s;
  for (std::size_t i = 0; i < e_->props.size(); ++i) {
    const Property& p = e_->props[i];
    if (p.list) {
      const double n = value_at(take(ply::size_of(p.count_type), "list " + p.name), p.count_type, big_);
      if (n < 0) bad("list " + p.name + " has a negative length " + std::to_string(static_cast<long long>(n)));
      take(static_cast<std::uint64_t>(n) * ply::size_of(p.type), "list " + p.name);
      continue;
    }
    const char* v = take(ply::size_of(p.type), p.name);
    if (!vertex) continue;
    for (int a = 0; a < 3; ++a) {
      if (i != h_.xyz[a]) continue;
      s.p_mm[a] = value_at(v, p.type, big_);
      if (!std::isfinite(s.p_mm[a])) bad(p.name + " is not a finite number");
    }
  }
  if (vertex) out.push_back(s);
}

std::vector<Sample> BinaryBody::read() {
  std::vector<Sample> out;
  // Reserve no more than the bytes can hold: a header may lie about the count.
  out.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(h_.elements[h_.vertex].count, (bytes_.size() - at_) / 3)));
  for (const Element& e : h_.elements) {
    e_ = &e;
    // Each instance takes at least one byte (every element has a property),
    // so a lying count ends at the end of the file.
    for (k_ = 0; k_ < e.count; ++k_) {
      start_ = at_;
      element(out);
    }
  }
  if (at_ != bytes_.size())
    throw Error(ErrorKind::input, file_ + ": error: " + plural(bytes_.size() - at_, "byte") +
                                      " after the last element at byte " + std::to_string(at_) +
                                      ": the header's element counts do not match the data");
  return out;
}

class AsciiBody {
 public:
  AsciiBody(const std::string& bytes, const std::string& file, const Header& h)
      : src_(file, bytes), h_(h), line_(h.data_line) {}
  std::vector<Sample> read();

 private:
  // The next line that is not blank, or 0 at the end of the file.
  std::uint32_t next_line() {
    while (line_ <= src_.last_line() && detail::trim(src_.line_text(line_)).empty()) ++line_;
    return line_ <= src_.last_line() ? line_++ : 0;
  }
  void element(const Element& e, std::uint64_t k, std::vector<Sample>& out);

  const SourceText src_;
  const Header& h_;
  std::uint32_t line_;
};

// One element on one line, as the format requires of ascii files.
void AsciiBody::element(const Element& e, std::uint64_t k, std::vector<Sample>& out) {
  const std::uint32_t l = next_line();
  const std::string what = e.name + " " + std::to_string(k);
  if (!l)
    detail::fail(src_, src_.last_line() ? src_.last_line() : 1, 1,
                 "the file ends before " + what + " (the header says 'element " + e.name + " " + std::to_string(e.count) + "')");
  const std::vector<detail::Field> w = detail::words(src_.line_text(l));
  const auto end_col = static_cast<std::uint32_t>(src_.line_text(l).size() + 1);
  const bool vertex = &e == &h_.elements[h_.vertex];
  Sample s;
  s.line = l;
  std::size_t j = 0;  // next word
  for (std::size_t i = 0; i < e.props.size(); ++i) {
    const Property& p = e.props[i];
    if (j >= w.size()) detail::fail(src_, l, end_col, what + ": no value for " + p.name);
    if (p.list) {
      std::uint64_t n = 0;
      const std::string_view t = w[j].text;
      const auto [stop, ec] = std::from_chars(t.data(), t.data() + t.size(), n);
      if (ec != std::errc() || stop != t.data() + t.size())
        detail::fail(src_, l, w[j].col, what + ": the length of list " + p.name + " must be a whole number >= 0, not " + detail::quoted(t));
      if (n > w.size() - j - 1) detail::fail(src_, l, end_col, what + ": list " + p.name + " has fewer than " + std::to_string(n) + " values");
      j += 1 + static_cast<std::size_t>(n);
      continue;
    }
    for (int a = 0; a < 3; ++a) {
      if (!vertex || i != h_.xyz[a]) continue;
      const auto v = detail::number(w[j].text);
      if (!v) detail::fail(src_, l, w[j].col, what + ": " + p.name + ": " + detail::not_a_number(w[j].text));
      s.p_mm[a] = *v;
    }
    ++j;
  }
  if (j < w.size()) detail::fail(src_, l, w[j].col, what + ": more values than its properties (" + std::to_string(j) + ")");
  if (vertex) out.push_back(s);
}

std::vector<Sample> AsciiBody::read() {
  std::vector<Sample> out;
  for (const Element& e : h_.elements)
    for (std::uint64_t k = 0; k < e.count; ++k) element(e, k, out);
  if (const std::uint32_t l = next_line())
    detail::fail(src_, l, 1, "data after the last element: the header's element counts do not match the data");
  return out;
}

}  // namespace

std::vector<Sample> parse_ply(const std::string& bytes, const std::string& file) {
  const Header h = ply::read_header(bytes, file);
  if (h.format == ply::Format::ascii) return AsciiBody(bytes, file, h).read();
  return BinaryBody(bytes, file, h).read();
}

}  // namespace deflex::measure
