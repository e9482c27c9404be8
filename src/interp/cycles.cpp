// Canned cycles (G73-G89, expanded into G0/G1 moves) and program flow
// (M98/M99 subprograms, M2/M30): the parts of a run that repeat blocks, and
// so where the --max-blocks budget and the repeat limits apply.
#include "run.hpp"

namespace deflex::interp::detail {

// Canned cycles in G17 (drilling along Z), Fanuc semantics: position in XY at
// the current level, rapid to R, the cycle's own moves to Z, retract to the
// initial level (G98) or R (G99). In G91, R is measured from the initial level
// and Z from R. Repeats (K or L, per dialect) step the XY increment in G91.
bool Run::do_cycle() {
  if (plane_ != 17) return refuse(nullptr, "canned cycles outside G17 are not interpreted");
  if (comp_ != 400) return refuse(nullptr, "canned cycle under cutter compensation");
  int repeats = 1;
  if (const Word* wk = blk_.find(d_.cycle_repeat_word)) {
    if (!whole(wk, 0, 9999, repeats, "repeat count")) return false;
  }
  if (!set_cycle_levels()) return false;
  const double top = return_ == 980 ? std::max(cyc_init_z_, cyc_r_) : cyc_r_;
  Vec3 xy_step{0, 0, 0};
  Vec3 hole = pos_;
  if (!hole_position(hole, xy_step)) return false;
  // A tiny Q would make pecks without end (depth - Q == depth in doubles).
  if ((cycle_ == 730 || cycle_ == 830) && (cyc_r_ - cyc_z_) / cyc_q_ > static_cast<double>(opt_.max_blocks))
    return refuse(blk_.find('Q'), "peck depth Q gives more than " + std::to_string(opt_.max_blocks) +
                                      " pecks; {max_blocks} raises the limit");
  for (int k = 0; k < repeats && !stop_; ++k) {
    if (!absolute_) { hole[0] = pos_[0] + xy_step[0]; hole[1] = pos_[1] + xy_step[1]; }
    move_to_hole(hole);
    cycle_moves(top);
  }
  return true;
}

// The cycle's R level, bottom Z and peck depth Q from the block, or the ones
// before (modal); false when they make no cycle.
bool Run::set_cycle_levels() {
  const Word* wz = blk_.find('Z');
  const Word* wr = blk_.find('R');
  const Word* wq = blk_.find('Q');
  if (!known_[2]) return refuse(wz, "canned cycle before the Z position is known");
  // R and Z: incremental R is from the initial level, incremental Z from R.
  if (wr) { cyc_r_ = absolute_ ? length_mm(*wr) : cyc_init_z_ + length_mm(*wr); cyc_have_r_ = true; }
  if (wz) { cyc_z_ = absolute_ ? length_mm(*wz) : cyc_r_ + length_mm(*wz); cyc_have_z_ = true; }
  if (!cyc_have_r_) { cyc_r_ = pos_[2]; cyc_have_r_ = true; }
  if (!cyc_have_z_) return refuse(nullptr, gname(cycle_) + " without a Z depth");
  if (wq) cyc_q_ = std::fabs(length_mm(*wq));
  if ((cycle_ == 730 || cycle_ == 830) && cyc_q_ <= 0) return refuse(wq, gname(cycle_) + " needs a peck depth Q > 0");
  if (cycle_ == 760 && d_.fine_boring_shift.empty())
    return refuse(nullptr, "G76 shift direction is a machine parameter the " + d_.name + " dialect does not give");
  if (cyc_z_ > cyc_r_) return refuse(wz, "canned cycle bottom Z above the R level");
  if (return_ == 980 && cyc_init_z_ < cyc_r_)
    warn(nullptr, "G98 with the initial level below R: retracting to R");
  return true;
}

// XY of the hole: absolute once (into `hole`), or incremental per repeat (into `xy_step`).
bool Run::hole_position(Vec3& hole, Vec3& xy_step) {
  static const char axes[] = {'X', 'Y'};
  for (int i = 0; i < 2; ++i) {
    const Word* w = blk_.find(axes[i]);
    if (!w) continue;
    if (absolute_) { hole[i] = length_mm(*w); known_[i] = true; }
    else {
      if (!known_[i]) return refuse(w, "incremental hole position before the position is known");
      xy_step[i] = length_mm(*w);
    }
  }
  if (!known_[0] || !known_[1]) return refuse(nullptr, "canned cycle before the X/Y position is known");
  return true;
}

// Rapids over the hole and down to R (up to R first where the dialect's
// control positions only above it).
void Run::move_to_hole(const Vec3& hole) {
  const Fixed cc = Fixed::canned_cycle;
  if (!d_.cycle_positions_before_raise && pos_[2] < cyc_r_) emit(MotionKind::rapid, at_z(cyc_r_), cc);
  Vec3 p = pos_;
  p[0] = hole[0];
  p[1] = hole[1];
  if (p != pos_) emit(MotionKind::rapid, p, cc);
  if (pos_[2] != cyc_r_) emit(MotionKind::rapid, at_z(cyc_r_), cc);
}

// The cycle's own moves from R to the bottom and back up to `top`.
void Run::cycle_moves(double top) {
  const Fixed cc = Fixed::canned_cycle;
  double z = cyc_z_, r = cyc_r_;
  switch (cycle_) {
    case 810: case 820:
      emit(MotionKind::linear, at_z(z), cc);
      emit(MotionKind::rapid, at_z(top), cc);
      break;
    case 860:
      emit(MotionKind::linear, at_z(z), cc);
      emit(MotionKind::rapid, at_z(top), cc);
      break;
    case 840: case 740: case 850: case 890:
      emit(MotionKind::linear, at_z(z), cc);
      emit(MotionKind::linear, at_z(r), cc);
      if (top != r) emit(MotionKind::rapid, at_z(top), cc);
      break;
    case 730: case 830: {
      // G73: retract d after each peck; G83: back to R, then rapid to d above the last depth.
      double d = d_.peck_retract_mm, depth = r;
      while (!stop_) {
        depth = std::max(depth - cyc_q_, z);
        emit(MotionKind::linear, at_z(depth), cc);
        if (depth <= z) break;
        if (cycle_ == 830) emit(MotionKind::rapid, at_z(r), cc);
        emit(MotionKind::rapid, at_z(std::min(depth + d, r)), cc);
      }
      emit(MotionKind::rapid, at_z(top), cc);
      break;
    }
    case 760: {
      emit(MotionKind::linear, at_z(z), cc);
      Vec3 s = pos_;
      int ax = d_.fine_boring_shift[1] == 'X' ? 0 : 1;
      double sign = d_.fine_boring_shift[0] == '-' ? -1.0 : 1.0;
      s[ax] += sign * cyc_q_;
      emit(MotionKind::rapid, s, cc);
      emit(MotionKind::rapid, at_z(top), cc);
      Vec3 back = pos_;
      back[ax] -= sign * cyc_q_;
      emit(MotionKind::rapid, back, cc);
      break;
    }
  }
}

bool Run::flow(bool m98, bool m99, bool end) {
  if (end) {
    if (m98 || m99) return refuse(nullptr, "M2/M30 with M98/M99 in one block");
    ended_ = true;
    return true;
  }
  if (m98) {
    const Word* wp = blk_.find('P');
    if (!wp) return refuse(nullptr, "M98 without P (subprogram number)");
    std::int64_t p = static_cast<std::int64_t>(wp->value);
    int digits = 0;
    for (std::uint32_t i = wp->num_begin; i < wp->end; ++i) digits += std::isdigit(static_cast<unsigned char>(prog_->bytes()[i])) != 0;
    int repeats = 1;
    if (const Word* wl = blk_.find('L')) {
      if (wl->value > 9999) return refuse(wl, "subprogram repeat count over 9999");
      if (!whole(wl, 0, 9999, repeats, "subprogram repeat count L")) return false;
    } else if (digits > 4) {  // Fanuc P rrrr nnnn; checked before narrowing, which would wrap
      if (p / 10000 > 9999) return refuse(wp, "subprogram repeat count over 9999");
      repeats = static_cast<int>(p / 10000);
      p %= 10000;
    }
    if (repeats < 1) return true;
    if (!subs_indexed_) {
      Diagnostics quiet(nullptr, 0);
      gcode::Block b;
      for (std::uint32_t l = prog_->first_line(); l <= prog_->last_line(); ++l) {
        std::string_view t = prog_->source().line_text(l);
        std::size_t k = t.find_first_not_of(" \t");
        if (k == std::string_view::npos || (t[k] != 'O' && t[k] != 'o' && t[k] != ':')) continue;
        prog_->lex(l, b, quiet);
        if (b.kind == gcode::LineKind::program_number && !subs_.count(b.program_number)) subs_[b.program_number] = l;
      }
      subs_indexed_ = true;
    }
    auto it = subs_.find(p);
    if (it == subs_.end()) return refuse(wp, "subprogram O" + std::to_string(p) + " is not in this file");
    if (stack_.size() >= 8) return refuse(wp, "subprograms nested deeper than 8 (recursion?)");
    stack_.push_back({next_, it->second, repeats});
    if (calls_out_) {
      auto& c = calls_out_->calls[it->second];
      if (std::find(c.begin(), c.end(), blk_.line) == c.end()) c.push_back(blk_.line);
    }
    next_ = it->second + 1;
    return true;
  }
  if (m99) {
    if (blk_.find('P')) return refuse(blk_.find('P'), "M99 P (return to a sequence number) is not interpreted");
    if (stack_.empty()) {
      warn(nullptr, "M99 in the main program restarts it forever on the control; deflex ends here");
      ended_ = true;
      return true;
    }
    Frame& f = stack_.back();
    if (--f.repeats_left > 0) { next_ = f.start_line + 1; return true; }
    next_ = f.return_line;
    stack_.pop_back();
  }
  return true;
}

}  // namespace deflex::interp::detail
