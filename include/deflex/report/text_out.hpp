// Fast text output of numbers for the large files deflex prints: `path` (a
// line per motion) and points.csv (a row per CL point). printf's %f and
// std::to_chars with a precision cost ~450 instructions a number; scaling to
// an integer of the last decimal is exact enough for measured quantities (it
// can differ from correctly rounded output only at a tie one decimal further)
// and about ten times cheaper. Huge values fall back to std::to_chars.
#pragma once
#include <ostream>
#include <string>
#include <string_view>

namespace deflex::report {

class HeldText;

// Appends text to a buffer and hands it to the stream (or holds it) in
// chunks of ~1 MiB.
class TextOut {
 public:
  explicit TextOut(std::ostream& o) : o_(&o) { buf_.reserve(1 << 21); }
  // The text goes to `held`, whose caller decides later whether it goes out.
  explicit TextOut(HeldText& held) : held_(&held) { buf_.reserve(1 << 21); }
  ~TextOut() { flush(); }
  TextOut(const TextOut&) = delete;
  TextOut& operator=(const TextOut&) = delete;
  // `v` with `decimals` (0..9) decimals, rounded half away from zero; never "-0.0".
  void fixed(double v, int decimals);
  // The same written at `p` (at most kFixedBytes bytes); returns its end. For
  // a caller that makes a line of several numbers and appends it at once
  // (`deflex path`: one append a line, not one a number, took 10% off it).
  static constexpr std::size_t kFixedBytes = 64;
  static char* put_fixed(char* p, double v, int decimals);
  void integer(unsigned long v);
  TextOut& operator<<(std::string_view s) {
    buf_.append(s);
    if (buf_.size() > (1 << 20)) flush();
    return *this;
  }
  TextOut& operator<<(char c) {
    buf_.push_back(c);
    if (buf_.size() > (1 << 20)) flush();
    return *this;
  }
  void flush();

 private:
  std::ostream* o_ = nullptr;
  HeldText* held_ = nullptr;
  std::string buf_;
};

}  // namespace deflex::report
