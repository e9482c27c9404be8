// Writes a program back: untouched bytes are copied as they are, changed
// numbers are spliced into their words, new words and blocks are formatted for
// the target control's dialect. With no edit the output equals the input.
#pragma once
#include <array>
#include <cstdint>
#include <fstream>
#include <functional>
#include <ostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "deflex/gcode/program.hpp"
#include "deflex/profile/profile.hpp"

namespace deflex::writer {

// The largest rounding of a coordinate written per the dialect, mm: half its
// last decimal (inch: in mm).
double rounding_mm(bool inch, const profile::Dialect& d);

// How a program writes its numbers, learnt from its own words, so that what
// deflex changes or adds reads like the rest of the program (a post that
// writes `Z27.000 F800.000` gets `Z26.990`, not `Z26.99`).
struct NumberStyle {
  static constexpr int kUnknown = -1;
  // Per letter (index letter - 'A'): the decimals every number of that letter
  // is padded to (a fixed-width style: the program's words of it show
  // trailing zeros and almost all have that many decimals), else kUnknown
  // (the dialect's trailing_zeros decides).
  std::array<int, 26> fixed_decimals;
  // Per letter: 1 "0.5", 0 ".5", kUnknown (the dialect's leading_zero decides).
  std::array<int, 26> leading_zero;
  bool blanks = true;  // blanks between words (no block of the program has one: false)
  NumberStyle() {
    fixed_decimals.fill(kUnknown);
    leading_zero.fill(kUnknown);
  }
};
// The style of the first `max_lines` lines of `p` (the rest of a CAM program
// is written alike). Coordinate letters (X Y Z I J K R) share their evidence
// where one letter has none of its own.
NumberStyle learn_style(const gcode::Program& p, std::uint32_t max_lines = 2000);

// `value` in program units (mm in G21, inch in G20), formatted per the dialect:
// always with a decimal point, so no control reads it as least input
// increments, rounded to the dialect's decimals. With a style, the word of
// `letter` is padded and led as the program writes that letter (the value
// read back is the same: only zeros are added or left out).
std::string format_number(double value, bool inch, const profile::Dialect& d, const NumberStyle* style = nullptr,
                          char letter = 0);

// A comment in the dialect's style: `(text)` or `; text`. Parentheses inside a
// paren comment would end it early (Fanuc comments do not nest): they become [ ].
std::string format_comment(const std::string& text, const profile::Dialect& d);

class Rewriter {
 public:
  // `numbers_taken` (may be null): the N numbers inserted blocks took, kept by
  // the caller across the pieces of a program written in pieces.
  Rewriter(const gcode::Program& prog, const profile::Dialect& d, std::map<long, long>* numbers_taken = nullptr)
      : prog_(prog), d_(d), numbers_taken_(numbers_taken ? numbers_taken : &own_numbers_) {}
  // Replaces the number of word `w` by `value` (program units).
  void set_number(const gcode::Word& w, double value, bool inch);
  // Inserts ` L<value>` right after byte offset `at` (e.g. after the last axis word).
  void insert_word(std::uint32_t at, char letter, double value, bool inch);
  // Inserts a whole new block (text without line end) after line `line`, using
  // that line's line ending.
  void insert_block_after(std::uint32_t line, const std::string& text);
  // Text of a new block to insert after `after_line`, for the dialect: an N
  // word first when the dialect numbers inserted blocks, then the words
  // (program units), then the comment in the dialect's style. `lead` (e.g.
  // "G1") goes right after the N word. Inserted blocks take the free numbers
  // between the nearest numbered blocks before and after them, in order, so no
  // two blocks share a number: where none is free, a dialect that `increment`s
  // writes the block without N, one that `require`s N refuses (Error(input),
  // naming the line and the gap). Call it once per block, in output order.
  std::string format_block(std::uint32_t after_line, const std::vector<std::pair<char, double>>& words, bool inch,
                           const std::string& comment = "", const std::string& lead = "");
  // Inserts a whole new block (text without line end) before line `line`,
  // ended like that line (or like the line before it when `line` has no end).
  void insert_block_before(std::uint32_t line, const std::string& text);
  std::size_t edits() const { return edits_.size(); }
  // Streams the result. Throws Error(input) if a changed line breaks the
  // dialect's line-length limit.
  void write(std::ostream& out);
  std::string str();
  // Only lines first..last (a piece of a program read with lines of context
  // around it; every edit lies in it).
  void write(std::ostream& out, std::uint32_t first_line, std::uint32_t last_line);

 private:
  struct Edit {
    std::uint32_t begin, end;  // bytes replaced: [begin, end)
    std::uint32_t seq;         // keeps insertions at one offset in call order
    std::string text;
    bool new_block = false;
  };
  void check_line_lengths() const;
  // The program's style, learnt at the first number written.
  const NumberStyle& style();
  std::string number(char letter, double value, bool inch);
  const gcode::Program& prog_;
  const profile::Dialect& d_;
  std::vector<Edit> edits_;
  // Per N number of the block before a gap: how many numbers after it inserted
  // blocks took (gaps with unnumbered blocks between them share one).
  std::map<long, long>* numbers_taken_;
  std::map<long, long> own_numbers_;
  std::optional<NumberStyle> style_;
};

// Checks, before any work, that `path` can be written as an output:
// not the input (same file, also through links), an existing path a regular
// file (through symlinks: a device, FIFO or directory is refused), its folder
// existing and writable. Throws Error(usage) for what the user must change
// (the input, a non-regular file, a missing folder), Error(io) when the folder
// is not writable.
void check_output_path(const std::string& path, const std::string& input_path);

// Checks, before any work, that a report folder exists as a directory or can
// be created (its parent exists and is writable). Throws Error(usage/io).
void check_output_folder(const std::string& dir);

// A file written atomically: the content goes to a temporary file beside
// `path` (check_output_path first), renamed over it by commit(); destroyed
// without commit() (an error, or nothing worth keeping), it leaves `path` as it
// was. A symlink is followed (its target is replaced, the link stays); an
// existing file keeps its mode (and owner, where allowed); a new one gets 0666
// less the umask. Throws Error(io) when writing fails.
class AtomicFile {
 public:
  AtomicFile(const std::string& path, const std::string& input_path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  std::ostream& stream() { return out_; }
  void commit();

 private:
  std::string path_, target_, tmp_;
  std::ofstream out_;
  bool have_old_ = false;
  unsigned old_mode_ = 0, old_uid_ = 0, old_gid_ = 0;
  int slot_ = -1;  // in writer/temp_files.hpp's registry
};

// Writes `path` atomically (an AtomicFile committed when `fill` returned normally).
void write_file_atomically(const std::string& path, const std::string& input_path,
                           const std::function<void(std::ostream&)>& fill);

// Writes through a temporary file (in TMPDIR) and copies it to `out` only
// when `fill` returned: a program written piece by piece reaches standard
// output whole or not at all. Throws Error(io) on a failed write.
void write_through_temporary(std::ostream& out, const std::function<void(std::ostream&)>& fill);

}  // namespace deflex::writer
