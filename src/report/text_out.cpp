#include "deflex/report/text_out.hpp"

#include <charconv>
#include <cmath>
#include <cstring>

#include "deflex/report/held_text.hpp"

namespace deflex::report {

char* TextOut::put_fixed(char* out, double v, int decimals) {
  static const double kScale[] = {1, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  char b[kFixedBytes];
  const double s = v * kScale[decimals];
  if (!(std::fabs(s) < 9e15)) {
    auto r = std::to_chars(b, b + sizeof b, v, std::chars_format::fixed, decimals);
    std::memcpy(out, b, static_cast<std::size_t>(r.ptr - b));
    return out + (r.ptr - b);
  }
  const long long u = static_cast<long long>(s < 0 ? s - 0.5 : s + 0.5);  // round half away from zero
  unsigned long long a = u < 0 ? 0ull - static_cast<unsigned long long>(u) : static_cast<unsigned long long>(u);
  char* e = b + sizeof b;
  char* p = e;
  for (int i = 0; i < decimals; ++i) {
    *--p = static_cast<char>('0' + a % 10);
    a /= 10;
  }
  if (decimals > 0) *--p = '.';
  do {
    *--p = static_cast<char>('0' + a % 10);
    a /= 10;
  } while (a);
  if (u < 0) *--p = '-';  // u == 0 never gets a sign: no "-0.000000"
  std::memcpy(out, p, static_cast<std::size_t>(e - p));
  return out + (e - p);
}

void TextOut::fixed(double v, int decimals) {
  char b[kFixedBytes];
  *this << std::string_view(b, static_cast<std::size_t>(put_fixed(b, v, decimals) - b));
}

void TextOut::integer(unsigned long v) {
  char b[24];
  auto r = std::to_chars(b, b + sizeof b, v);
  buf_.append(b, r.ptr);
}

void TextOut::flush() {
  if (held_) {
    held_->take(std::move(buf_));  // the chunk's storage goes with it: no copy
    buf_.reserve(1 << 21);
    return;
  }
  o_->write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
  buf_.clear();
}

}  // namespace deflex::report
