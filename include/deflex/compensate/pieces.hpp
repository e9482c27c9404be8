// A long program cut into pieces the compensation takes one at a time, so
// that memory does not grow with the program (the pipeline of compensate:
// read, interpret, simulate and compensate, write, read back, in bounded
// pieces; compensate.hpp's Compensation, apply.hpp's WriteState and ReadBack).
//
// A piece ends right before a line whose block is a plain G0 or G1 that
// keeps the work frame: nothing that decides a motion of the piece looks past
// it then (movable() looks one motion ahead, and through arcs only). The
// piece's text comes with up to kContextLines lines before and after it (the
// N numbers of inserted blocks are chosen from the numbered blocks nearby).
// Once the program has ended (M2/M30, the tape end) the rest is one piece.
#pragma once
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/gcode/program.hpp"
#include "deflex/gcode/reader.hpp"
#include "deflex/interp/interpreter.hpp"

namespace deflex::diag {
class BackgroundJob;  // diag/parallel_trace.hpp
}

namespace deflex::compensate {

inline constexpr std::uint32_t kContextLines = 200;

struct ProgramPiece {
  gcode::Program text{SourceText()};      // lines first_line..last_line and their context, numbered in the file
  std::uint32_t first_line = 1, last_line = 0;
  std::vector<interp::Motion> motions;    // of its lines, in order
  std::size_t first_motion = 0;           // program index of motions[0]
  bool inch_after = false;                // the motion after the piece was read in G20
  gcode::Tape tape;                       // before first_line (what a piece numbered from 1 needs)
  gcode::Program own{SourceText()};       // its own lines numbered from 1 (the safety check's view)
};

class PieceCutter {
 public:
  // Reads `path` (a file: two passes are made of it, the checks' and this
  // one) `lines_per_read` lines at a time; a piece ends after at least
  // `motions_per_piece` motions. `fix` (may be empty) is applied to each motion
  // as interpreted (what the checks applied: --spindle and --feed defaults;
  // it may run on another thread). With `read_ahead` the piece after the one
  // handed out is read and interpreted on a thread of its own meanwhile.
  PieceCutter(const std::string& path, std::uint32_t lines_per_read, const interp::Options& opt,
              std::size_t motions_per_piece, std::function<void(interp::Motion&)> fix = {},
              bool read_ahead = false);
  ~PieceCutter();
  // The next piece, null after the last.
  std::unique_ptr<ProgramPiece> next();

 private:
  struct Sink : interp::MotionSink {
    PieceCutter* cut = nullptr;
    void motion(const interp::Motion& m) override;
  };
  std::unique_ptr<ProgramPiece> make();  // the next piece, read here
  bool read_more();
  std::size_t find_cut();
  std::string bytes_of(std::uint32_t first, std::uint32_t last) const;

  gcode::ProgramReader reader_;
  interp::Options opt_;
  Diagnostics quiet_{nullptr, 0};
  Sink sink_;
  interp::Interpreter it_;
  std::size_t per_piece_;
  std::function<void(interp::Motion&)> fix_;
  std::deque<std::unique_ptr<gcode::Program>> held_;  // the pieces read whose lines are still needed
  std::deque<interp::Motion> motions_;                // interpreted, not handed out yet
  std::size_t search_from_ = 1;                       // where find_cut() looks next
  std::size_t handed_ = 0;                            // motions handed out
  std::uint32_t next_line_ = 1, read_to_ = 0;         // first line not handed out; last line read
  bool eof_ = false, done_ = false;
  gcode::Tape tape_;                                  // of the pieces handed out
  bool read_ahead_ = false;
  // The piece being read ahead (last: it ends before what make() uses).
  std::unique_ptr<diag::BackgroundJob> ahead_job_;
  std::future<std::unique_ptr<ProgramPiece>> ahead_;
};

}  // namespace deflex::compensate
