// A program file kept as bytes, with its line index; lines are lexed on demand.
#pragma once
#include <cstdint>
#include <iosfwd>
#include <string>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/gcode/block.hpp"

namespace deflex::gcode {

// Longest line read, bytes: far beyond any control's block (Fanuc: 256
// characters); a longer line is an error at this column.
inline constexpr std::uint32_t kMaxLineBytes = 65536;

// What a piece of a program needs to know of the pieces before it: whether a
// block came yet (a `%` before any block is the tape start, after one the
// tape end) and the line of the tape end once it came.
struct Tape {
  bool seen_block = false;
  std::uint32_t closing_percent = 0;
};

class Program {
 public:
  explicit Program(SourceText src);
  // A piece of a longer file (gcode/reader.hpp): `tape` says what came before
  // and is updated to what comes after.
  Program(SourceText piece, Tape& tape);
  // A piece whose tape end (0: none in or before it) is known already.
  Program(SourceText piece, std::uint32_t closing_percent_line) : src_(std::move(piece)), closing_percent_(closing_percent_line) {}
  const SourceText& source() const { return src_; }
  const std::string& bytes() const { return src_.bytes(); }
  std::uint32_t line_count() const { return static_cast<std::uint32_t>(src_.line_count()); }
  // Line numbers in the file: 1 and line_count() for a whole program.
  std::uint32_t first_line() const { return src_.first_line(); }
  std::uint32_t last_line() const { return src_.last_line(); }
  // Line number of the closing `%`; lines after it are ignored text. 0 if none.
  std::uint32_t closing_percent_line() const { return closing_percent_; }
  // Lexes line `line` (1-based) into `b` (reusing its storage). Lexical errors
  // are reported to `diags`; a line with errors comes back with kind `block`
  // and macro=false but words possibly incomplete — `ok` tells.
  bool lex(std::uint32_t line, Block& b, Diagnostics& diags) const;

 private:
  void find_tape_end(Tape& tape);
  SourceText src_;
  std::uint32_t closing_percent_ = 0;
};

// Reads a whole file (or `stdin_stream` for "-") into a SourceText; throws Error(io).
// (gcode/reader.cpp: ProgramReader::whole_text)
SourceText read_source(const std::string& path, std::istream* stdin_stream = nullptr);

}  // namespace deflex::gcode
