// Reading a program in pieces, so that memory does not grow with its length.
//
// A piece is a run of whole lines (at most max_lines, and about 8 MiB unless a
// single line is longer; max_lines 0: the whole file) that keeps its line numbers in the file; the pieces
// read in order make the program, and every command that can read in pieces
// gives the same output and diagnostics as when it reads the whole file.
// The interpreter carries its state from one piece to the next
// (interp::Interpreter). Subprogram calls jump anywhere in the file: a file
// that may call one (needs_whole_file), or that uses G41/G42, is read whole, as is standard input
// where a command needs two passes.
#pragma once
#include <cstdint>
#include <cstdio>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>

#include "deflex/gcode/program.hpp"

namespace deflex::gcode {

// Lines per piece unless DEFLEX_CHUNK_LINES says otherwise (cli): about 0.5 MB
// of a CAM program. compensate cuts its pieces after as many motions: on the
// 1M-block raster 16,384 took 36.1 s and 473 MB, 65,536 37 s and 547 MB (what
// each piece holds: its motions as read and written, the check's line facts),
// 8,192 40.7 s and 464 MB.
inline constexpr std::uint32_t kPieceLines = 1u << 14;

class ProgramReader {
 public:
  // "-" reads `stdin_stream` (std::cin when null). max_lines = 0: the whole
  // file as one piece. Throws Error(io) as read_source does.
  ProgramReader(std::string path, std::istream* stdin_stream, std::uint32_t max_lines);
  ~ProgramReader();
  ProgramReader(const ProgramReader&) = delete;
  ProgramReader& operator=(const ProgramReader&) = delete;
  // The next piece, or null after the last one. A file with no bytes gives one
  // empty piece (line_count() 0), as read_source gives an empty program.
  std::unique_ptr<Program> next();
  // max_lines 0: all of the input at once (read_source()).
  SourceText whole_text();
  // True once the piece next() gave last was the file's last.
  bool done() const { return eof_ && buf_.empty(); }
  const std::string& name() const { return name_; }

 private:
  bool fill();  // reads more bytes into buf_; false at the end of the input
  std::string path_, name_;
  std::istream* in_ = nullptr;
  std::FILE* file_ = nullptr;
  std::uint32_t max_lines_;
  std::size_t max_bytes_;      // a piece ends at the first line end past this
  std::string buf_;            // bytes read and not yet handed out
  std::size_t scanned_ = 0;    // bytes of buf_ already searched for line ends
  std::uint32_t lines_in_buf_ = 0;  // line ends found in buf_[0, scanned_)
  std::size_t cut_ = 0;        // just past the last line end found
  std::uint32_t next_line_ = 1;
  bool eof_ = false, gave_any_ = false;
  Tape tape_;
};

// A program read once per pass of a command, in pieces or whole: whole when
// it is one piece anyway (then read once), when it may call subprograms, and
// from standard input; in pieces of max_lines lines otherwise (0: whole).
class ProgramPasses {
 public:
  ProgramPasses(const std::string& path, std::istream* stdin_stream, std::uint32_t max_lines);
  // Calls fn(piece, last) for each piece in order (a new read of the file
  // each pass, unless it is held whole). A piece lives during its call only.
  void each(const std::function<void(const Program& piece, bool last)>& fn);
  bool whole() const { return whole_ != nullptr; }
  const Program* whole_program() const { return whole_.get(); }  // null when read in pieces
  std::unique_ptr<Program> take_whole() { return std::move(whole_); }
  const std::string& path() const { return path_; }
  std::uint32_t max_lines() const { return max_lines_; }
  const std::string& name() const { return name_; }

 private:
  std::string path_, name_;
  std::istream* stdin_;
  std::uint32_t max_lines_;
  std::unique_ptr<Program> whole_;
};

// Whether the file must be read whole: it may call a subprogram (an M98
// word: a call jumps anywhere in the file) or use cutter compensation (a G41
// or G42 word: the tool-centre path holds a move back until the next one
// comes, across any cut). A cheap byte scan that errs towards yes (comments
// not told apart). "-" (standard input) answers yes: it cannot be read twice.
bool needs_whole_file(const std::string& path);
// The same scan of a text in memory.
bool may_need_whole_file(std::string_view text);

}  // namespace deflex::gcode
