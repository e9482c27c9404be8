#include "deflex/gcode/reader.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <iostream>
#include <unistd.h>
#include <vector>

namespace deflex::gcode {
namespace {

constexpr std::size_t kReadBytes = 1u << 20;   // one read
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
      throw Error(Exit::io, "<stdin>: error: standard input is closed; give a file, or pipe the program in");
    return;
  }
  name_ = path_;
  file_ = std::fopen(path_.c_str(), "rb");
  if (!file_) throw Error(Exit::io, path_ + ": error: cannot open: " + std::strerror(errno));
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
    if (std::ferror(file_)) throw Error(Exit::io, path_ + ": error: read failed");
  } else {
    in_->read(buf_.data() + old, static_cast<std::streamsize>(kReadBytes));
    n = static_cast<std::size_t>(in_->gcount());
    if (in_->bad()) throw Error(Exit::io, "<stdin>: error: read failed");
  }
  buf_.resize(old + n);
  if (n == 0) eof_ = true;
  return n > 0;
}

std::unique_ptr<Program> ProgramReader::next() {
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
  std::string piece = buf_.substr(0, cut_);
  buf_.erase(0, cut_);
  scanned_ -= cut_;
  cut_ = 0;
  lines_in_buf_ = 0;
  auto p = std::make_unique<Program>(SourceText(name_, std::move(piece), next_line_), tape_);
  next_line_ += p->line_count();
  return p;
}

ProgramPasses::ProgramPasses(const std::string& path, std::istream* stdin_stream, std::uint32_t max_lines)
    : path_(path), stdin_(stdin_stream), max_lines_(calls_subprograms(path) ? 0 : max_lines) {
  ProgramReader r(path_, stdin_, max_lines_);
  name_ = r.name();
  std::unique_ptr<Program> first = r.next();
  if (r.done()) whole_ = std::move(first);  // one piece: held, read once
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
// An M word whose number reads 98 (leading zeros and blanks allowed, blanks
// inside it too: the lexer reads `M9 8` as M98); the state carries from one
// buffer to the next.
struct M98Scan {
  enum { none, letter, digit9, digit98 } st = none;
  bool found = false;
  void add(const char* p, std::size_t n) {
    for (std::size_t i = 0; i < n && !found; ++i) {
      const char c = p[i];
      switch (st) {
        case none: st = (c == 'M' || c == 'm') ? letter : none; break;
        case letter: st = c == '9' ? digit9 : (c == '0' || c == ' ' || c == '\t') ? letter : none; break;
        case digit9: st = c == '8' ? digit98 : (c == ' ' || c == '\t') ? digit9 : none; break;
        case digit98: found = !(c >= '0' && c <= '9'); st = none; break;
      }
      if (st == none && (c == 'M' || c == 'm')) st = letter;
    }
  }
  bool done() const { return found || st == digit98; }  // M98 at the very end
};
}  // namespace

bool may_call_subprograms(std::string_view text) {
  M98Scan scan;
  scan.add(text.data(), text.size());
  return scan.done();
}

bool calls_subprograms(const std::string& path) {
  if (path == "-") return true;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return true;  // the reader says why
  M98Scan scan;
  std::vector<char> buf(1 << 16);
  std::size_t n;
  while (!scan.found && (n = std::fread(buf.data(), 1, buf.size(), f)) > 0) scan.add(buf.data(), n);
  std::fclose(f);
  return scan.done();
}

}  // namespace deflex::gcode
