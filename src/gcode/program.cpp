#include "deflex/gcode/program.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace deflex::gcode {

int Word::code10() const {
  // Range first: 10 * value must fit an int (converting a larger double is UB).
  if (!(value >= 0 && value < 1e8)) return -1;
  double t = value * 10.0;
  double r = std::round(t);
  if (std::fabs(t - r) > 1e-6) return -1;  // G54.15 is no code
  return static_cast<int>(r);
}

namespace {

inline bool is_space(char c) { return c == ' ' || c == '\t'; }
inline bool is_digit(char c) { return c >= '0' && c <= '9'; }
inline char upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 32) : c; }
inline bool is_letter(char c) { c = upper(c); return c >= 'A' && c <= 'Z'; }

// First non-blank character of a line, or 0.
char first_char(std::string_view s) {
  for (char c : s)
    if (!is_space(c)) return c;
  return 0;
}

// The end of the run of letters, digits and points from `i` (a name).
std::uint32_t word_end(const std::string& s, std::uint32_t i, std::uint32_t e) {
  while (i < e && (is_letter(s[i]) || is_digit(s[i]) || s[i] == '.' || s[i] == '_')) ++i;
  return i;
}

// Whether the letters at `i` begin a macro B keyword (Fanuc Custom Macro B:
// control, operators, functions) or a LinuxCNC O-word keyword, both refused
// as macro B; any other run of letters is no G-code.
bool macro_keyword(const std::string& s, std::uint32_t i, std::uint32_t e) {
  std::string w;
  while (i < e && is_letter(s[i]) && w.size() < 9) w += upper(s[i++]);
  static const char* const kWords[] = {
      "IF", "THEN", "GOTO", "WHILE", "DO", "END", "EQ", "NE", "GT", "GE", "LT", "LE", "AND", "OR", "XOR", "MOD",
      "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "ATN", "SQRT", "SQR", "ABS", "BIN", "BCD", "ROUND", "RND", "FIX",
      "FUP", "LN", "EXP", "POW", "ADP", "POPEN", "PCLOS", "DPRNT", "BPRNT", "SETVN",
      // LinuxCNC O-words (o100 sub ... o100 endsub)
      "SUB", "ENDSUB", "CALL", "RETURN", "ENDWHILE", "REPEAT", "ENDREPEAT", "ELSE", "ELSEIF", "ENDIF", "BREAK",
      "CONTINUE"};
  for (const char* k : kWords)
    if (w == k) return true;
  return false;
}

const double kPow10[] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11,
                         1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// One line being lexed: the cursor `i` over the line's bytes up to `e` (its
// end without the line end), the block it fills and whether all went well.
// Program::lex runs once per block (and again at every subprogram repeat):
// its steps are inlined into it, so the cursor stays in a register (left to
// the compiler, items() and address() stayed out of line and lexing
// six_surfaces.nc took 13% longer).
struct LineLexer {
  const std::string& s;
  const SourceText& src;
  Diagnostics& diags;
  Block& b;
  std::uint32_t i, e;
  bool ok = true;

  std::uint32_t col(std::uint32_t off) const { return off - b.begin + 1; }
  [[gnu::always_inline]] bool error(std::uint32_t off, std::string msg) {
    diags.report(Severity::error, src, b.line, col(off), std::move(msg));
    return false;
  }
  void mark_macro(std::uint32_t off) {
    if (!b.macro) { b.macro = true; b.macro_col = col(off); }
  }

  // Leading blanks, then `%` (true: the line is a tape mark) or block delete
  // `/` with its optional level digit.
  bool tape_mark_or_block_delete() {
    while (i < e && is_space(s[i])) ++i;
    if (i < e && s[i] == '%') {
      b.kind = LineKind::percent;
      return true;
    }
    if (i < e && s[i] == '/') {
      b.block_delete = true;
      ++i;
      if (i < e && is_digit(s[i])) b.block_delete_level = static_cast<std::uint8_t>(s[i++] - '0');
    }
    return false;
  }

  // The words and comments of the line. One message per line for characters
  // that cannot start a word: the rest of a garbled line would only echo it.
  [[gnu::always_inline]] void items() {
    while (i < e) {
      char c = s[i];
      if (is_space(c)) { ++i; continue; }
      if (c == '(') {
        if (!comment()) break;
        continue;
      }
      if (c == ';') {
        b.comments.push_back({i, e, true});
        break;
      }
      if (c == '#' || c == '[' || c == ']' || c == '=') { mark_macro(i); ++i; continue; }
      bool iso_colon = c == ':' && b.words.empty() && !b.macro;  // `:1234` = O1234 (ISO)
      if (!is_letter(c) && !iso_colon) {
        if (b.macro) { ++i; continue; }
        ok = error(i, std::string("unexpected character '") + c + "'");
        break;
      }
      if (!address(c, iso_colon)) break;
    }
  }

  // A `( ... )` comment from `i`; false: not closed on the line.
  bool comment() {
    std::uint32_t start = i;
    while (i < e && s[i] != ')') {
      if (s[i] == '(' && i != start) {
        // Fanuc comments do not nest: a second `(` is an alarm there.
        ok = error(i, "nested '(' inside a comment (Fanuc comments do not nest)");
      }
      ++i;
    }
    if (i == e) { ok = error(start, "comment not closed: missing ')' before end of line"); return false; }
    ++i;
    b.comments.push_back({start, i, false});
    return true;
  }

  // A letter `c` at `i`: an address followed by a number, or a macro keyword
  // (IF, GOTO, WHILE, DO, END, SIN ...), recognised by a second letter.
  // False: an error that ends the line.
  [[gnu::always_inline]] bool address(char c, bool iso_colon) {
    std::uint32_t start = i++;
    char letter = iso_colon ? 'O' : upper(c);
    std::uint32_t j = i;
    while (j < e && is_space(s[j])) ++j;
    if (j < e && (s[j] == '#' || s[j] == '[' || (is_letter(s[j]) && (b.macro || macro_keyword(s, start, e))))) {
      mark_macro(start);
      i = j;
      return true;
    }
    if (i < e && is_letter(s[i])) {
      // Letters that form no word (a header line without its parentheses:
      // `profile.nc (...)`): the control alarms at the first letter.
      ok = error(start, std::string("letters that form no word: '") + c + "' is not followed by a number ('" +
                            std::string(s, start, std::min<std::uint32_t>(word_end(s, start, e) - start, 24)) + "')");
      return false;
    }
    if (letter == 'O' && !b.macro && !b.words.empty() && start > b.begin && (is_digit(s[start - 1]) || s[start - 1] == '.')) {
      // X11O.: a program number only stands first in a block.
      ok = error(start, std::string("the letter '") + c + "' where a digit was expected (a zero typed as the letter O?)");
      return false;
    }
    if (b.macro) {
      // Inside a macro block keep going without parsing numbers exactly.
      while (i < e && !is_letter(s[i]) && s[i] != '(' && s[i] != ';') ++i;
      return true;
    }
    word(letter, start, j);
    return true;
  }

  // The number of the word `letter` at `start`, from `j`: [+-] digits
  // [. digits], spaces allowed between characters. Appends the word.
  [[gnu::always_inline]] void word(char letter, std::uint32_t start, std::uint32_t j) {
    Word w;
    w.letter = letter;
    w.begin = start;
    w.num_begin = j;
    bool neg = false;
    if (j < e && (s[j] == '+' || s[j] == '-')) {
      neg = s[j] == '-';
      ++j;
    }
    std::uint64_t mant = 0;
    int digits = 0, frac = 0, sig = 0;
    bool point = false, overflow = false;
    std::uint32_t last = j;
    for (; j < e; ++j) {
      char d = s[j];
      if (is_digit(d)) {
        if (mant == 0 && d == '0' && !point) { ++digits; last = j + 1; continue; }
        if (sig < 18) { mant = mant * 10 + static_cast<unsigned>(d - '0'); ++sig; if (point) ++frac; }
        else if (!point) overflow = true;  // more than 18 integer digits
        ++digits;
        last = j + 1;
      } else if (d == '.' && !point) {
        point = true;
        last = j + 1;
      } else if (is_space(d)) {
        continue;
      } else {
        break;
      }
    }
    if (digits == 0) {
      ok = error(start, std::string("address '") + letter + "' has no number");
      i = std::max(last, start + 1);
      return;
    }
    if (overflow) ok = error(start, "number too long");
    double v = static_cast<double>(mant);
    // mant < 2^63 with at most 18 digits; dividing by an exact power of ten
    // rounds once, so a literal with up to 15 significant digits is exact.
    v = frac <= 22 ? v / kPow10[frac] : v * std::pow(10.0, -frac);
    w.value = neg ? -v : v;
    w.has_point = point;
    w.end = last;
    i = last;
    if (letter == 'O' && b.words.empty()) {
      b.kind = LineKind::program_number;
      b.program_number = static_cast<std::int64_t>(v);
    }
    b.words.push_back(w);
  }
};

// Empties `b` (keeping its storage) for line `line`; returns the end of the
// line's text, before its line end.
std::uint32_t start_block(const SourceText& src, std::uint32_t line, Block& b) {
  const std::string& s = src.bytes();
  b.line = line;
  b.begin = src.line_begin(line);
  b.end = src.line_end_with_eol(line);
  std::uint32_t e = b.end;
  if (e > b.begin && s[e - 1] == '\n') --e;
  if (e > b.begin && s[e - 1] == '\r') --e;
  b.text_end = e;
  b.kind = LineKind::blank;
  b.block_delete = false;
  b.block_delete_level = 0;
  b.macro = false;
  b.macro_col = 0;
  b.program_number = -1;
  b.words.clear();
  b.comments.clear();
  return e;
}

}  // namespace

Program::Program(SourceText src) : src_(std::move(src)) {
  Tape tape;
  find_tape_end(tape);
}

Program::Program(SourceText piece, Tape& tape) : src_(std::move(piece)) { find_tape_end(tape); }

void Program::find_tape_end(Tape& tape) {
  // `%` before any block is the tape start; a `%` after blocks is the tape end,
  // and whatever follows it is kept but never read (Fanuc behaviour).
  closing_percent_ = tape.closing_percent;
  for (std::uint32_t l = first_line(); !closing_percent_ && l <= last_line(); ++l) {
    std::string_view t = src_.line_text(l);
    char c = first_char(t);
    if (c == '%') {
      if (tape.seen_block) closing_percent_ = l;
    } else if (c != 0 && c != '(' && c != ';') {
      tape.seen_block = true;
    }
  }
  tape.closing_percent = closing_percent_;
}

bool Program::lex(std::uint32_t line, Block& b, Diagnostics& diags) const {
  const std::uint32_t e = start_block(src_, line, b);
  if (closing_percent_ && line > closing_percent_) { b.kind = LineKind::ignored; return true; }
  LineLexer lx{src_.bytes(), src_, diags, b, b.begin, e};
  // A line longer than any control reads is refused unread: lexing it again at
  // every subprogram repeat would multiply its cost.
  if (e - b.begin > kMaxLineBytes) {
    b.kind = LineKind::blank;
    return lx.error(b.begin + kMaxLineBytes, "line longer than " + std::to_string(kMaxLineBytes) + " bytes");
  }
  if (lx.tape_mark_or_block_delete()) return true;
  lx.items();
  if (b.kind != LineKind::program_number && (!b.words.empty() || b.macro)) b.kind = LineKind::block;
  return lx.ok;
}

}  // namespace deflex::gcode
