// One line of a Fanuc/ISO program, lexed without losing a byte: every word and
// comment knows its byte range in the source, so the writer can copy untouched
// text and splice new numbers into changed words only.
#pragma once
#include <cstdint>
#include <string_view>
#include <vector>

namespace deflex::gcode {

// A letter address with its number, e.g. `X-12.5`, `g 0 1` or `G54.1`.
struct Word {
  char letter = 0;              // upper case
  bool has_point = false;       // the number was written with a decimal point
  std::uint32_t begin = 0;      // byte offset of the letter
  std::uint32_t num_begin = 0;  // byte offset of the number (sign or first digit)
  std::uint32_t end = 0;        // one past the last byte of the number
  double value = 0.0;           // the number as written (no unit or decimal rule applied)
  // G/M code as an integer times 10 (G54.1 -> 541, G1 -> 10); -1 if not a
  // valid code (more than one decimal, negative).
  int code10() const;
};

struct Comment {
  std::uint32_t begin = 0;  // `(` or `;`
  std::uint32_t end = 0;    // one past `)` or end of line text
  bool semicolon = false;
};

enum class LineKind : std::uint8_t {
  blank,        // nothing but spaces / comments
  block,        // words (possibly with comments)
  percent,      // a `%` tape mark
  program_number,  // `O1234` or `:1234` (ISO) possibly followed by a comment
  ignored       // text after the closing `%`
};

struct Block {
  std::uint32_t line = 0;          // 1-based
  std::uint32_t begin = 0;         // first byte of the line
  std::uint32_t text_end = 0;      // end of the line text (before CR/LF)
  std::uint32_t end = 0;           // past the line end
  LineKind kind = LineKind::blank;
  bool block_delete = false;       // leading `/` (optional skip; `/n` records n)
  std::uint8_t block_delete_level = 0;
  bool macro = false;              // contains macro B syntax: never interpreted
  std::uint32_t macro_col = 0;     // column of the first macro token
  std::int64_t program_number = -1;  // for program_number lines
  std::vector<Word> words;
  std::vector<Comment> comments;

  const Word* find(char letter) const {
    for (const Word& w : words)
      if (w.letter == letter) return &w;
    return nullptr;
  }
  int count(char letter) const {
    int n = 0;
    for (const Word& w : words) n += w.letter == letter;
    return n;
  }
};

}  // namespace deflex::gcode
