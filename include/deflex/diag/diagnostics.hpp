// Compiler-style diagnostics and the error type of each failure class.
#pragma once
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "deflex/diag/settings.hpp"

namespace deflex {

// What kind of failure an Error is. The library says what went wrong; the
// front end decides what to make of it (the CLI's exit codes: cli/exit.hpp).
enum class ErrorKind {
  input,     // the program (or a compared program) has errors
  settings,  // a setting the caller gave is invalid: a value out of range, settings that exclude each other
  config,    // config.yaml, machine profile, dialect or library error
  io,        // a file could not be read or written
  internal   // a bug in deflex
};

enum class Severity { note, warning, error };

// Text of a file with a line index, so a byte offset maps to line:col.
// Lines are 1-based, columns are 1-based byte columns (as gcc prints them).
class SourceText {
 public:
  SourceText() = default;
  SourceText(std::string name, std::string bytes);
  // A piece of a longer file (gcode::ProgramReader) whose first line is line
  // `first_line` of the file: lines keep their numbers in the file, byte
  // offsets count from the piece's first byte.
  SourceText(std::string name, std::string bytes, std::uint32_t first_line);
  const std::string& name() const { return name_; }
  const std::string& bytes() const { return bytes_; }
  std::size_t line_count() const { return line_begin_.size(); }
  std::uint32_t first_line() const { return first_line_; }
  std::uint32_t last_line() const { return first_line_ + static_cast<std::uint32_t>(line_begin_.size()) - 1; }
  // Byte range of line `line` (1-based) without its line end. (Inline, as
  // line_end_with_eol(): the lexer asks for them once per line.)
  std::string_view line_text(std::uint32_t line) const {
    if (line < first_line_ || line - first_line_ >= line_begin_.size()) return {};
    std::uint32_t b = line_begin_[line - first_line_], e = line_end_with_eol(line);
    if (e > b && bytes_[e - 1] == '\n') --e;
    if (e > b && bytes_[e - 1] == '\r') --e;
    return std::string_view(bytes_).substr(b, e - b);
  }
  std::uint32_t line_begin(std::uint32_t line) const { return line_begin_[line - first_line_]; }
  // Byte offset just past line `line` including its line end.
  std::uint32_t line_end_with_eol(std::uint32_t line) const {
    const std::size_t k = line - first_line_ + 1;  // index of the next line's start
    return k < line_begin_.size() ? line_begin_[k] : static_cast<std::uint32_t>(bytes_.size());
  }
  std::uint32_t line_of(std::uint32_t offset) const;  // 1-based

 private:
  std::string name_;
  std::string bytes_;
  std::vector<std::uint32_t> line_begin_;
  std::uint32_t first_line_ = 1;
};

struct Diagnostic {
  Severity severity = Severity::error;
  std::string file;
  std::uint32_t line = 0;  // 0: no location
  std::uint32_t col = 0;
  std::string message;
  std::string source_line;  // empty: no excerpt
  // Column of the caret in source_line when that is an excerpt of a long line
  // (0: col). A 10 MB line is not echoed whole.
  std::uint32_t caret_col = 0;
};

// Collects diagnostics, prints them as they come (gcc format), counts errors
// and stops a run after max_errors.
class Diagnostics {
 public:
  explicit Diagnostics(std::ostream* out = nullptr, int max_errors = 20)
      : out_(out), max_errors_(max_errors) {}
  void report(Severity s, const SourceText& src, std::uint32_t line, std::uint32_t col,
              std::string message);
  void report(Severity s, std::string file, std::string message);  // no location
  int errors() const { return errors_; }
  int warnings() const { return warnings_; }
  bool too_many() const { return max_errors_ > 0 && errors_ >= max_errors_; }
  // Everything reported, unless set_keep(false); errors are always kept.
  const std::vector<Diagnostic>& all() const { return all_; }
  void set_keep(bool keep) { keep_ = keep; }
  // How the messages name settings (diag/settings.hpp); default: by keyword.
  void set_names(SettingNames names) { names_ = std::move(names); }
  // Messages kept back, for a pass whose messages must follow others not
  // known yet (deflex path interprets while the text checks run beside it):
  // counted as they come, printed and kept only at release(), in order. Once
  // `bound` are held, `full` is called (it should release() or drop_held()):
  // holding never takes more memory than that.
  void hold(std::size_t bound, std::function<void()> full);
  // Prints and keeps what is held, and every later message as it comes.
  void release();
  // Forgets what is held and every later message (still counted).
  void drop_held();

 private:
  void emit(Diagnostic d);
  void put(Diagnostic d);  // print and keep
  std::ostream* out_;
  int max_errors_;
  int errors_ = 0;
  int warnings_ = 0;
  bool keep_ = true;
  SettingNames names_;
  std::vector<Diagnostic> all_;
  enum class Held { no, holding, dropping } held_ = Held::no;
  std::vector<Diagnostic> held_messages_;
  std::size_t hold_bound_ = 0;
  std::function<void()> hold_full_;
};

// A failure that ends the run, of one kind. Its text may name settings as
// {keyword} (diag/settings.hpp): what() names them by their keywords, message()
// as a front end calls them. An error that ends a run because the program has
// errors carries those errors (diagnostics()), so a caller has their
// locations without reading the text.
class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& text);
  ErrorKind kind() const { return kind_; }
  // The settings the message is about, by keyword (empty: none).
  std::vector<std::string> settings() const;
  // The message with each setting named by `names`.
  std::string message(const SettingNames& names) const;
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }
  // This error with the errors `d` reported (warnings and notes left out).
  Error& with_errors_of(const Diagnostics& d);

 private:
  ErrorKind kind_;
  std::string text_;
  std::vector<Diagnostic> diagnostics_;
};

std::string format(const Diagnostic& d);

}  // namespace deflex
