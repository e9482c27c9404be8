// A measured FRF as CSV (frf.hpp): the columns by name, then one row per
// frequency. Located errors, fields and numbers as measure's readers have them
// (deflex/measure/text.hpp).
#include <algorithm>
#include <array>
#include <cstdio>
#include <string>
#include <map>
#include <optional>

#include "deflex/measure/text.hpp"
#include "deflex/profile/yaml.hpp"
#include "deflex/stability/frf.hpp"

namespace deflex::stability {
namespace {

namespace text = measure::detail;

// The columns: frequency, then re/im of xx, xy, yx, yy (Frf2's (i, j) in that order).
constexpr std::array<const char*, 9> kColumns = {"frequency_Hz",   "re_xx_mm_per_N", "im_xx_mm_per_N",
                                                 "re_xy_mm_per_N", "im_xy_mm_per_N", "re_yx_mm_per_N",
                                                 "im_yx_mm_per_N", "re_yy_mm_per_N", "im_yy_mm_per_N"};
// Required: frequency and the direct terms; the cross terms may be absent.
constexpr std::array<bool, 9> kRequired = {true, true, true, false, false, false, false, true, true};
constexpr std::size_t kMinRows = 3;

struct Header {
  std::size_t count = 0;                                // fields per row
  std::array<std::optional<std::size_t>, 9> index;      // each column's field, by kColumns
};

Header header(const SourceText& src, std::uint32_t line, const std::vector<text::Field>& f) {
  if (text::number(f.front().text))
    text::fail(src, line, f.front().col, "the first line is data, not a header: expected a header naming frequency_Hz,"
                                         "re_xx_mm_per_N,im_xx_mm_per_N,re_yy_mm_per_N,im_yy_mm_per_N");
  Header h;
  h.count = f.size();
  for (std::size_t i = 0; i < f.size(); ++i) {
    const auto it = std::find(kColumns.begin(), kColumns.end(), f[i].text);
    if (it == kColumns.end())
      text::fail(src, line, f[i].col, "unknown column " + text::quoted(f[i].text) + " (columns: frequency_Hz, " +
                                          "re_/im_ of xx, yy and optionally xy, yx, each _mm_per_N)");
    auto& slot = h.index[static_cast<std::size_t>(it - kColumns.begin())];
    if (slot) text::fail(src, line, f[i].col, "column " + text::quoted(f[i].text) + " given twice");
    slot = i;
  }
  for (std::size_t c = 0; c < kColumns.size(); ++c)
    if (kRequired[c] && !h.index[c]) text::fail(src, line, 1, std::string("no column ") + kColumns[c]);
  for (std::size_t c = 3; c < 7; c += 2)  // a cross term needs both its parts
    if (h.index[c].has_value() != h.index[c + 1].has_value())
      text::fail(src, line, 1, std::string("column ") + kColumns[h.index[c] ? c + 1 : c] + " missing: a cross term " +
                                   "needs its real and imaginary parts");
  return h;
}

// One row's numbers by kColumns (0 for an absent cross term).
std::array<double, 9> row(const SourceText& src, std::uint32_t line, const std::vector<text::Field>& f,
                          const Header& h) {
  if (f.size() != h.count) {
    const auto col = f.size() > h.count ? f[h.count].col - 1 : static_cast<std::uint32_t>(src.line_text(line).size() + 1);
    text::fail(src, line, col,
               "expected " + std::to_string(h.count) + " fields as the header names, found " + std::to_string(f.size()));
  }
  std::array<double, 9> v{};
  for (std::size_t c = 0; c < kColumns.size(); ++c) {
    if (!h.index[c]) continue;
    const text::Field& x = f[*h.index[c]];
    const auto n = text::number(x.text);
    if (!n) text::fail(src, line, x.col, std::string(kColumns[c]) + ": " + text::not_a_number(x.text));
    v[c] = *n;
  }
  return v;
}

std::string number_text(double v, int digits) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

Frf2 matrix_of(const std::array<double, 9>& v) {
  Frf2 h;
  h << std::complex<double>(v[1], v[2]), std::complex<double>(v[3], v[4]),  //
      std::complex<double>(v[5], v[6]), std::complex<double>(v[7], v[8]);
  return h;
}

}  // namespace

Frf parse_frf_csv(std::string_view bytes, const std::string& file) {
  const SourceText src(file, std::string(bytes));
  std::optional<Header> cols;
  std::uint32_t header_line = 0;
  Frf frf;
  frf.source = file;
  for (std::uint32_t l = 1; l <= src.line_count(); ++l) {
    const std::string_view t = text::trim(src.line_text(l));
    if (t.empty() || t.front() == '#') continue;
    const std::vector<text::Field> f = text::comma_fields(src.line_text(l));
    if (!cols) {
      cols = header(src, l, f);
      header_line = l;
      continue;
    }
    const std::array<double, 9> v = row(src, l, f, *cols);
    const std::uint32_t col = f[*cols->index[0]].col;
    if (!(v[0] > 0)) text::fail(src, l, col, "frequency_Hz must be > 0");
    if (!frf.frequency_Hz.empty() && !(v[0] > frf.frequency_Hz.back()))
      text::fail(src, l, col, "frequency_Hz must ascend strictly (the row before has " +
                                  number_text(frf.frequency_Hz.back(), 9) + " Hz)");
    frf.frequency_Hz.push_back(v[0]);
    frf.h_mm_per_N.push_back(matrix_of(v));
  }
  if (!cols)
    text::fail(src, std::max<std::uint32_t>(1, src.last_line()), 1,
               src.line_count() ? "no header: expected a line naming frequency_Hz and the FRF's columns"
                                : "the file is empty: expected a header and at least 3 rows");
  if (frf.frequency_Hz.size() < kMinRows)
    text::fail(src, header_line, 1, "an FRF needs at least " + std::to_string(kMinRows) + " rows, found " +
                                        std::to_string(frf.frequency_Hz.size()));
  return frf;
}

Frf load_frf_csv(const std::string& path) { return parse_frf_csv(yaml::read_file(path), path); }

std::string frf_csv(const Frf& frf) {
  std::string out;
  for (std::size_t c = 0; c < kColumns.size(); ++c) out += std::string(c ? "," : "") + kColumns[c];
  out += '\n';
  for (std::size_t i = 0; i < frf.frequency_Hz.size(); ++i) {
    const Frf2& h = frf.h_mm_per_N[i];
    const double v[9] = {frf.frequency_Hz[i], h(0, 0).real(), h(0, 0).imag(), h(0, 1).real(), h(0, 1).imag(),
                         h(1, 0).real(),      h(1, 0).imag(), h(1, 1).real(), h(1, 1).imag()};
    for (int c = 0; c < 9; ++c) out += (c ? "," : "") + number_text(v[c], 17);
    out += '\n';
  }
  return out;
}

}  // namespace deflex::stability
