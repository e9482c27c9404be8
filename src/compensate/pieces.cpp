#include "deflex/compensate/pieces.hpp"

#include <algorithm>

#include "deflex/diag/parallel_trace.hpp"

namespace deflex::compensate {

PieceCutter::PieceCutter(const std::string& path, std::uint32_t lines_per_read, const interp::Options& opt,
                         std::size_t motions_per_piece, std::function<void(interp::Motion&)> fix, bool read_ahead)
    : reader_(path, nullptr, lines_per_read), opt_(opt), it_(opt_, quiet_, sink_),
      per_piece_(std::max<std::size_t>(motions_per_piece, 1)), fix_(std::move(fix)), read_ahead_(read_ahead) {
  sink_.cut = this;
}

PieceCutter::~PieceCutter() {
  if (!ahead_.valid()) return;
  try {
    ahead_.get();
  } catch (...) {  // the caller stopped reading; a failure ahead is not its
  }
}

std::unique_ptr<ProgramPiece> PieceCutter::next() {
  std::unique_ptr<ProgramPiece> p;
  if (ahead_.valid())
    diag::traced_wait(ahead_job_.get(), [&] { p = ahead_.get(); });
  else
    p = make();
  // The piece after it is read while the caller works on this one: reading
  // and interpreting depend on nothing the caller does.
  if (p && !done_ && read_ahead_) {
    ahead_job_ = diag::parallel_trace_on() ? std::make_unique<diag::BackgroundJob>() : nullptr;
    ahead_ = std::async(std::launch::async, [this] {
      const diag::AsyncScope background(ahead_job_.get());
      diag::TracedLoop loop;  // one task: its whole time is on the job's path
      std::unique_ptr<ProgramPiece> r;
      loop.task([&] { r = make(); });
      return r;
    });
  }
  return p;
}

void PieceCutter::Sink::motion(const interp::Motion& m) {
  cut->motions_.push_back(m);
  if (cut->fix_) cut->fix_(cut->motions_.back());
}

bool PieceCutter::read_more() {
  if (eof_) return false;
  std::unique_ptr<gcode::Program> p = reader_.next();
  if (!p) {
    eof_ = true;
    return false;
  }
  // The interpreter reads a piece at a time (it must live until the next).
  it_.feed(*p);
  read_to_ = p->last_line();
  held_.push_back(std::move(p));
  return true;
}

// The first motion at or past per_piece_ that is a plain G0/G1, the first
// motion of its line, in the work frame of the motion before it.
std::size_t PieceCutter::find_cut() {
  for (std::size_t c = std::max(search_from_, per_piece_); c < motions_.size(); ++c) {
    const interp::Motion &m = motions_[c], &b = motions_[c - 1];
    if (m.plain && (m.kind == interp::MotionKind::linear || m.kind == interp::MotionKind::rapid) &&
        m.line != b.line && m.work_offset_mm == b.work_offset_mm)
      return c;
  }
  search_from_ = std::max<std::size_t>(motions_.size(), 1);
  return 0;
}

std::string PieceCutter::bytes_of(std::uint32_t first, std::uint32_t last) const {
  std::string out;
  if (last < first) return out;
  for (const auto& p : held_) {
    if (p->line_count() == 0 || p->last_line() < first || p->first_line() > last) continue;
    const std::uint32_t a = std::max(first, p->first_line()), b = std::min(last, p->last_line());
    const SourceText& s = p->source();
    out.append(s.bytes(), s.line_begin(a), s.line_end_with_eol(b) - s.line_begin(a));
  }
  return out;
}

std::unique_ptr<ProgramPiece> PieceCutter::make() {
  if (done_) return nullptr;
  std::size_t c = 0;
  for (;;) {
    // Once the program is over no motion follows: the rest is one piece.
    c = it_.over() ? 0 : find_cut();
    if (c && (eof_ || read_to_ >= motions_[c].line - 1 + kContextLines)) break;
    if (!read_more()) break;
  }
  auto piece = std::make_unique<ProgramPiece>();
  piece->first_line = next_line_;
  piece->last_line = c ? motions_[c].line - 1 : read_to_;
  piece->inch_after = c && motions_[c].inch;
  const std::size_t n = c ? c : motions_.size();
  piece->motions.assign(motions_.begin(), motions_.begin() + static_cast<std::ptrdiff_t>(n));
  motions_.erase(motions_.begin(), motions_.begin() + static_cast<std::ptrdiff_t>(n));
  piece->first_motion = handed_;
  handed_ += n;
  search_from_ = 1;
  if (!c) done_ = true;
  const std::uint32_t from = piece->first_line > kContextLines ? piece->first_line - kContextLines : 1;
  const std::uint32_t to = std::min(read_to_, piece->last_line + kContextLines);
  std::uint32_t closing = 0;
  for (const auto& p : held_)
    if (!closing && p->closing_percent_line() && p->closing_percent_line() <= to) closing = p->closing_percent_line();
  piece->text = gcode::Program(SourceText(reader_.name(), bytes_of(from, to), from), closing);
  piece->tape = tape_;
  piece->own = gcode::Program(SourceText(reader_.name(), bytes_of(piece->first_line, piece->last_line), 1), tape_);
  next_line_ = piece->last_line + 1;
  // The pieces read whose lines no later piece's context reaches are done.
  while (held_.size() > 1 && held_.front()->last_line() + kContextLines < next_line_) held_.pop_front();
  return piece;
}

}  // namespace deflex::compensate
