#include "deflex/gcode/reader.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <iostream>
#include <unistd.h>
#include <vector>

namespace deflex::gcode {
namespace {

// One read. A piece is cut from the front of what was read and the rest moved
// forward: 256 KiB (not 1 MiB) moves less than a piece of 16,384 CAM lines
// (about 400 KB) each time; the moving was 4% of `deflex path`.
constexpr std::size_t kReadBytes = 1u << 18;
constexpr std::size_t kPieceBytes = 8u << 20;  // a piece ends at the first line end past this

}  // namespace

ProgramReader::ProgramReader(std::string path, std::istream* stdin_stream, std::uint32_t max_lines)
    : path_(std::move(path)), max_lines_(max_lines ? max_lines : UINT32_MAX),
      max_bytes_(max_lines ? kPieceBytes : SIZE_MAX) {
  if (path_ == "-") {
    name_ = "<stdin>";
    in_ = stdin_stream ? stdin_stream : &std::cin;
    // A closed standard input reads like an empty one: say it, it is no program.
    if (in_ == &std::cin && ::fcntl(STDIN_FILENO, F_GETFD) == -1)
      throw Error(ErrorKind::io, "<stdin>: error: standard input is closed; give a file, or pipe the program in");
    return;
  }
  name_ = path_;
  file_ = std::fopen(path_.c_str(), "rb");
  if (!file_) throw Error(ErrorKind::io, path_ + ": error: cannot open: " + std::strerror(errno));
}

ProgramReader::~ProgramReader() {
  if (file_) std::fclose(file_);
}

bool ProgramReader::fill() {
  if (eof_) return false;
  const std::size_t old = buf_.size();
  buf_.resize(old + kReadBytes);
  std::size_t n = 0;
  if (file_) {
    n = std::fread(buf_.data() + old, 1, kReadBytes, file_);
    if (std::ferror(file_)) throw Error(ErrorKind::io, path_ + ": error: read failed");
  } else {
    in_->read(buf_.data() + old, static_cast<std::streamsize>(kReadBytes));
    n = static_cast<std::size_t>(in_->gcount());
    if (in_->bad()) throw Error(ErrorKind::io, "<stdin>: error: read failed");
  }
  buf_.resize(old + n);
  if (n == 0) eof_ = true;
  return n > 0;
}

SourceText ProgramReader::whole_text() {
  // No line ends to count (SourceText indexes them), no copy.
  while (fill()) {
  }
  SourceText t(name_, std::move(buf_), next_line_);
  buf_.clear();
  return t;
}

SourceText read_source(const std::string& path, std::istream* stdin_stream) {
  return ProgramReader(path, stdin_stream, 0).whole_text();
}

std::unique_ptr<Program> ProgramReader::next() {
  if (max_bytes_ == SIZE_MAX) {
    if (eof_) return nullptr;
    return std::make_unique<Program>(whole_text(), tape_);
  }
  for (;;) {
    // Line ends in the bytes not searched yet, up to the piece's last line.
    while (lines_in_buf_ < max_lines_ && cut_ < max_bytes_) {
      const void* nl = std::memchr(buf_.data() + scanned_, '\n', buf_.size() - scanned_);
      if (!nl) {
        scanned_ = buf_.size();
        break;
      }
      scanned_ = static_cast<const char*>(nl) - buf_.data() + 1;
      cut_ = scanned_;
      ++lines_in_buf_;
    }
    if (lines_in_buf_ >= max_lines_ || cut_ >= max_bytes_) break;
    if (!fill()) {
      cut_ = buf_.size();  // the last piece: the rest, a last line without its line end included
      break;
    }
  }
  if (cut_ == 0 && gave_any_) return nullptr;
  gave_any_ = true;
  std::string piece(buf_, 0, cut_);
  buf_.erase(0, cut_);
  scanned_ -= cut_;
  cut_ = 0;
  lines_in_buf_ = 0;
  auto p = std::make_unique<Program>(SourceText(name_, std::move(piece), next_line_), tape_);
  next_line_ += p->line_count();
  return p;
}

ProgramPasses::ProgramPasses(const std::string& path, std::istream* stdin_stream, std::uint32_t max_lines)
    : path_(path), stdin_(stdin_stream), max_lines_(path == "-" ? 0 : max_lines) {
  ProgramReader r(path_, stdin_, max_lines_);
  name_ = r.name();
  std::unique_ptr<Program> first = r.next();
  if (r.done()) {
    whole_ = std::move(first);  // one piece: held, read once
  } else if (needs_whole_file(path_)) {
    max_lines_ = 0;  // a call jumps anywhere in the file: whole
    whole_ = ProgramReader(path_, stdin_, 0).next();
  }
}

void ProgramPasses::each(const std::function<void(const Program& piece, bool last)>& fn) {
  if (whole_) {
    fn(*whole_, true);
    return;
  }
  ProgramReader r(path_, stdin_, max_lines_);
  std::unique_ptr<Program> p = r.next();
  while (p) {
    std::unique_ptr<Program> next = r.next();  // one piece ahead: is this the last?
    fn(*p, next == nullptr);
    p = std::move(next);
  }
}

namespace {

bool blank(char c) { return c == ' ' || c == '\t'; }

// Whether the word at p (*p is its letter) reads one of `codes` (two digits
// each), the lexer's way: a plus sign, leading zeros and blanks allowed,
// blanks inside the number too (`M9 8` and `M+098` are M98). 1 yes, 0 no, -1 the bytes end first (at the
// end of the file: taken for yes).
int code_at(const char* p, const char* end, const char* codes) {
  const char* q = p + 1;
  while (q < end && blank(*q)) ++q;
  if (q < end && *q == '+') ++q;  // the lexer reads `M+98` as M98 (fuzz finding)
  while (q < end && (*q == '0' || blank(*q))) ++q;
  if (q == end) return -1;
  const char first = *q++;
  while (q < end && blank(*q)) ++q;
  if (q == end) return -1;
  const char second = *q++;
  bool named = false;  // `codes`: pairs of digits, "98" or "4142"
  for (const char* c = codes; c[0] && c[1]; c += 2) named = named || (c[0] == first && c[1] == second);
  if (!named) return 0;
  if (q == end) return -1;
  return *q >= '0' && *q <= '9' ? 0 : 1;
}

// Scans [b, e) for a word that makes the file be read whole: M98 (a call
// jumps anywhere in the file) or G41/G42 (the tool-centre path holds one
// element back, across any cut). Jumps from letter to letter with memchr (a
// G-code file has few M words; G words are many, but the scan still runs at
// memory speed). Returns 1 found, 0 none, or -1 with `from` set to the word
// the bytes end inside of (the caller carries it into the next read).
int scan_whole(const char* b, const char* e, const char*& from) {
  struct Look { char letter; const char* codes; };
  static const Look looks[] = {{'M', "98"}, {'m', "98"}, {'G', "4142"}, {'g', "4142"}};
  const char* cut = nullptr;
  for (const Look& l : looks)
    for (const char* p = b; (p = static_cast<const char*>(std::memchr(p, l.letter, e - p))) != nullptr; ++p) {
      const int r = code_at(p, e, l.codes);
      if (r == 1) return 1;
      if (r < 0) {
        if (!cut || p < cut) cut = p;  // the earliest word cut off: its rest comes with the next read
        break;
      }
    }
  from = cut;
  return cut ? -1 : 0;
}

}  // namespace

bool may_need_whole_file(std::string_view text) {
  const char* from = nullptr;
  return scan_whole(text.data(), text.data() + text.size(), from) != 0;  // cut off at the end: yes
}

bool needs_whole_file(const std::string& path) {
  if (path == "-") return true;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return true;  // the reader says why
  std::vector<char> buf;
  std::size_t carry = 0;  // bytes of an M word cut off by the last read, at the front of buf
  int found = 0;
  for (;;) {
    buf.resize(carry + (1u << 20));
    const std::size_t n = std::fread(buf.data() + carry, 1, buf.size() - carry, f);
    const char* from = nullptr;
    found = scan_whole(buf.data(), buf.data() + carry + n, from);
    if (found == 1 || n == 0) break;  // at the end, a word cut off counts as a call
    carry = found < 0 ? static_cast<std::size_t>(buf.data() + carry + n - from) : 0;
    if (found < 0) std::memmove(buf.data(), from, carry);
  }
  std::fclose(f);
  return found != 0;
}

}  // namespace deflex::gcode
