#include "deflex/diag/diagnostics.hpp"

#include <algorithm>
#include <cstring>
#include <ostream>
#include <utility>

namespace deflex {

SourceText::SourceText(std::string name, std::string bytes, std::uint32_t first_line)
    : SourceText(std::move(name), std::move(bytes)) {
  first_line_ = first_line;
}

SourceText::SourceText(std::string name, std::string bytes)
    : name_(std::move(name)), bytes_(std::move(bytes)) {
  if (bytes_.size() >= 0xFFFFFFFFu)
    throw Error(ErrorKind::io, name_ + ": file larger than 4 GiB is not supported");
  line_begin_.reserve(bytes_.size() / 16 + 1);
  line_begin_.push_back(0);
  const char* p = bytes_.data();
  const char* end = p + bytes_.size();
  // A line ends at LF; CR before LF belongs to the line end. A lone CR is kept as text.
  while (const char* nl = static_cast<const char*>(std::memchr(p, '\n', end - p))) {
    p = nl + 1;
    if (p == end) break;
    line_begin_.push_back(static_cast<std::uint32_t>(p - bytes_.data()));
  }
  if (bytes_.empty()) line_begin_.clear();
}

std::uint32_t SourceText::line_of(std::uint32_t offset) const {
  auto it = std::upper_bound(line_begin_.begin(), line_begin_.end(), offset);
  return static_cast<std::uint32_t>(it - line_begin_.begin()) + first_line_ - 1;
}

namespace {

// Control bytes from the input (ESC sequences, CR, NUL ...) would act on the
// user's terminal: they are shown as \xNN. Tabs stay (the caret keeps them).
bool control(unsigned char c) { return (c < 0x20 && c != '\t') || c == 0x7f; }
void append_printable(std::string& out, std::string_view in) {
  static const char hex[] = "0123456789abcdef";
  for (unsigned char c : in) {
    if (!control(c)) {
      out += static_cast<char>(c);
      continue;
    }
    out += "\\x";
    out += hex[c >> 4];
    out += hex[c & 15];
  }
}

}  // namespace

std::string format(const Diagnostic& d) {
  static const char* names[] = {"note", "warning", "error"};
  std::string s;
  append_printable(s, d.file);
  if (d.line) s += ":" + std::to_string(d.line) + ":" + std::to_string(d.col);
  s += std::string(s.empty() ? "" : ": ") + names[static_cast<int>(d.severity)] + ": ";
  append_printable(s, d.message);
  s += "\n";
  if (!d.source_line.empty() || d.line) {
    s += "  ";
    append_printable(s, d.source_line);
    s += "\n  ";
    // Keep tabs under tabs so the caret lines up in a terminal; an escaped
    // byte takes four columns.
    const std::uint32_t caret = d.caret_col ? d.caret_col : d.col;
    for (std::uint32_t i = 1; i < caret && i - 1 < d.source_line.size(); ++i) {
      const unsigned char c = static_cast<unsigned char>(d.source_line[i - 1]);
      s += c == '\t' ? "\t" : control(c) ? "    " : " ";
    }
    s += "^\n";
  }
  return s;
}

void Diagnostics::emit(Diagnostic d) {
  if (d.severity == Severity::error) ++errors_;
  if (d.severity == Severity::warning) ++warnings_;
  d.message = name_settings(d.message, names_);
  if (held_ == Held::dropping) return;
  if (held_ == Held::holding) {
    held_messages_.push_back(std::move(d));
    if (held_messages_.size() >= hold_bound_ && hold_full_) std::exchange(hold_full_, nullptr)();
    return;
  }
  put(std::move(d));
}

void Diagnostics::put(Diagnostic d) {
  if (out_) *out_ << format(d);
  // Errors are few (a run stops after max_errors): kept even when the rest
  // is not, for the Error that ends the run (with_errors_of).
  if (keep_ || d.severity == Severity::error) all_.push_back(std::move(d));
}

void Diagnostics::hold(std::size_t bound, std::function<void()> full) {
  held_ = Held::holding;
  hold_bound_ = bound;
  hold_full_ = std::move(full);
}

void Diagnostics::release() {
  held_ = Held::no;
  hold_full_ = nullptr;
  for (Diagnostic& d : held_messages_) put(std::move(d));
  std::vector<Diagnostic>().swap(held_messages_);
}

void Diagnostics::drop_held() {
  held_ = Held::dropping;
  hold_full_ = nullptr;
  std::vector<Diagnostic>().swap(held_messages_);
}

Error::Error(ErrorKind kind, const std::string& text)
    : std::runtime_error(name_settings(text, {})), kind_(kind), text_(text) {}

std::vector<std::string> Error::settings() const { return settings_named(text_); }

std::string Error::message(const SettingNames& names) const { return name_settings(text_, names); }

Error& Error::with_errors_of(const Diagnostics& d) {
  for (const Diagnostic& x : d.all())
    if (x.severity == Severity::error) diagnostics_.push_back(x);
  return *this;
}

void Diagnostics::report(Severity s, const SourceText& src, std::uint32_t line, std::uint32_t col,
                         std::string message) {
  Diagnostic d{s, src.name(), line, col, std::move(message), {}};
  const std::string_view text = src.line_text(line);
  // Lines up to kEcho bytes are echoed whole; longer ones as a window around the column.
  constexpr std::size_t kEcho = 240;
  if (text.size() <= kEcho) {
    d.source_line = std::string(text);
  } else {
    const std::size_t c = col ? col - 1 : 0;
    const std::size_t from = std::min(c > kEcho / 2 ? c - kEcho / 2 : 0, text.size());
    d.source_line = (from ? "..." : "") + std::string(text.substr(from, kEcho)) + (from + kEcho < text.size() ? "..." : "");
    d.caret_col = static_cast<std::uint32_t>(c - from + 1 + (from ? 3 : 0));
  }
  emit(std::move(d));
}

void Diagnostics::report(Severity s, std::string file, std::string message) {
  emit(Diagnostic{s, std::move(file), 0, 0, std::move(message), {}});
}

}  // namespace deflex
