#include "terminal_line.hpp"

namespace deflex::cli {

namespace {
constexpr char kClear[] = "\r\033[K";  // to the row's start, erase to its end (ECMA-48 EL)
}

void TerminalLine::clear() {
  if (!shown_) return;
  terminal_->sputn(kClear, sizeof kClear - 1);
  shown_ = false;
}

void TerminalLine::show(const std::string& text) {
  if (!shown_ && text.empty()) return;
  terminal_->sputn(kClear, sizeof kClear - 1);
  terminal_->sputn(text.data(), static_cast<std::streamsize>(text.size()));
  terminal_->pubsync();
  shown_ = !text.empty();
}

int TerminalLine::overflow(int c) {
  if (c == traits_type::eof()) return traits_type::not_eof(c);
  clear();
  return terminal_->sputc(traits_type::to_char_type(c));
}

std::streamsize TerminalLine::xsputn(const char* s, std::streamsize n) {
  clear();
  return terminal_->sputn(s, n);
}

}  // namespace deflex::cli
