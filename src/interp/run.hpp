// The interpreter's run state (class Run), shared by interpreter.cpp (words,
// modal settings, motions) and cycles.cpp (canned cycles, subprogram flow).
// Private to src/interp/.
#pragma once
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <vector>

#include "cutter_comp.hpp"
#include "deflex/interp/arc.hpp"
#include "deflex/interp/interpreter.hpp"

namespace deflex::interp::detail {
using gcode::Block;
using gcode::Word;

// Modal groups of Fanuc Series 0i/30i-M G codes (plus the few LinuxCNC codes the
// linuxcnc dialect reads). -1: unknown; -2: known but refused.
enum Group { g_nonmodal = 0, g_motion = 1, g_plane = 2, g_distance = 3, g_feedmode = 5, g_units = 6,
             g_cutcomp = 7, g_length = 8, g_cycle = 9, g_return = 10, g_scale = 11, g_macro = 12,
             g_css = 13, g_wcs = 14, g_path = 15, g_rotation = 16, g_polar = 17, g_arcdist = 18,
             kGroups = 19 };

struct CodeInfo { int group; const char* refusal; };

inline CodeInfo code_info(int c) {
  switch (c) {
    case 0: case 10: case 20: case 30: return {g_motion, nullptr};
    case 330: return {-2, "G33 (thread cutting) is not interpreted"};
    case 40: case 90: case 530: case 280: case 300: return {g_nonmodal, nullptr};
    case 51: case 80: return {g_nonmodal, nullptr};  // G5.1 AI contour control, G8 look-ahead: no motion
    case 50: return {-2, "G5 (high-speed cycle machining) is not interpreted"};
    case 100: return {-2, "G10 (programmable data input) changes offsets deflex cannot follow"};
    case 270: case 290: return {-2, "G27/G29 (reference point check/return) are not interpreted"};
    case 310: return {-2, "G31 (skip) ends where a signal stops it: its end point is unknown"};
    case 520: return {-2, "G52 (local coordinate system) is not interpreted"};
    case 920: return {-2, "G92 (coordinate system setting) depends on where the tool stands: not interpreted"};
    case 650: return {-2, "G65 (macro call) is macro B: not interpreted"};
    case 170: case 180: case 190: return {g_plane, nullptr};
    case 900: case 910: return {g_distance, nullptr};
    case 901: case 911: return {g_arcdist, nullptr};
    case 930: case 940: case 950: return {g_feedmode, nullptr};
    case 200: case 210: return {g_units, nullptr};
    case 400: case 410: case 420: return {g_cutcomp, nullptr};
    case 430: case 440: case 490: return {g_length, nullptr};
    case 730: case 740: case 760: case 800: case 810: case 820: case 830: case 840: case 850: case 860:
    case 890: return {g_cycle, nullptr};
    case 870: return {-2, "G87 (back boring) is not interpreted"};
    case 880: return {-2, "G88 (boring with manual retract) ends at the operator's hand: not interpreted"};
    case 980: case 990: return {g_return, nullptr};
    case 500: return {g_scale, nullptr};
    case 510: return {-2, "G51 (scaling/mirror) is not interpreted"};
    case 660: return {-2, "G66 (modal macro call) is macro B: not interpreted"};
    case 670: return {g_macro, nullptr};
    case 960: case 970: return {g_css, nullptr};
    case 540: case 550: case 560: case 570: case 580: case 590: case 541: case 1540:
    case 591: case 592: case 593: return {g_wcs, nullptr};
    case 610: case 611: case 620: case 630: case 640: return {g_path, nullptr};
    case 680: return {-2, "G68 (coordinate rotation) is not interpreted"};
    case 690: return {g_rotation, nullptr};
    case 150: return {g_polar, nullptr};
    case 160: return {-2, "G16 (polar coordinates) is not interpreted"};
    case 434: case 435: return {-2, "G43.4/G43.5 (5-axis tool centre point) is not a 3-axis code"};
    default: return {-1, nullptr};
  }
}

inline std::string gname(int c10) {
  return "G" + std::to_string(c10 / 10) + (c10 % 10 ? "." + std::to_string(c10 % 10) : "");
}

struct Frame {
  std::uint32_t return_line;  // line after the M98
  std::uint32_t start_line;   // line of the O number
  int repeats_left;
};

class Run {
 public:
  Run(const Options& o, Diagnostics& d, MotionSink& s)
      : opt_(o), d_(o.dialect), diags_(d), sink_(s),
        cc_(s, o.dialect.comp_corner == profile::Dialect::CompCorner::arc ? CutterComp::Corner::arc
                                                                           : CutterComp::Corner::intersection,
            o.dialect.comp_startup == profile::Dialect::CompStartup::offset_line
                ? CutterComp::Startup::offset_line
                : CutterComp::Startup::perpendicular_next) {
    if (o.machine) {
      for (auto& [k, v] : o.machine->reference_points_mm) ref_[k] = {v[0], v[1], v[2]};
    }
    wofs_ = offset_of("G54");
    // Before its first absolute move an axis is taken to stand at the G28
    // reference point (where programs start on a homed machine); nothing that
    // depends on it exactly (G91, arcs, cycles) is allowed until it is known.
    auto it = ref_.find(1);
    Vec3 home = it == ref_.end() ? Vec3{0, 0, 0} : it->second;
    for (int i = 0; i < 3; ++i) pos_[i] = home[i] - wofs_[i];
  }

  // Runs the lines of `piece`: the whole program, or its next piece (the
  // state carries over; a subprogram call cannot leave the piece). `last`: no
  // piece follows.
  void feed(const gcode::Program& piece, bool last) {
    prog_ = &piece;
    base_ = piece.first_line();
    seen_.assign(piece.line_count() + 2, 0);
    // A piece goes on from the one before (a piece numbered from 1 again, as
    // the safety check reads the written program, too).
    std::uint32_t line = piece.first_line();
    const std::uint32_t n = piece.last_line();
    while (line <= n && !stop_ && !ended_ && !diags_.too_many()) {
      next_ = line + 1;
      step(line);
      line = next_;
    }
    next_ = line;
    // The element G41/G42 holds ends with the program.
    if ((ended_ || last) && !stop_) comp_ok(cc_.flush());
    if (last) end_of_file();
    // Lines never executed (after M30, subprograms not called, after a stop)
    // are still read, so every lexical error in the file is reported.
    for (std::uint32_t l = base_; l <= n && !diags_.too_many(); ++l)
      if (!seen(l)) piece.lex(l, blk_, diags_);
    stats_.stopped = stop_;
    stats_.ended = ended_;
    stats_.lines = n;
  }
  // Once, after the last piece (feed(..., true) calls it before it reads the
  // lines never executed, whose messages then come last, as in one piece).
  void end_of_file() {
    if (eof_) return;
    eof_ = true;
    if (!stop_ && !ended_ && !stack_.empty())
      diags_.report(Severity::error, prog_ ? prog_->source().name() : std::string(),
                    "end of file inside a subprogram (no M99)");
  }
  const Stats& stats() const { return stats_; }
  // Records the call structure of the run (call_structure()).
  void record_calls(CallStructure* c) { calls_out_ = c; }
  // Per line of the piece run last: how often it ran (0, 1, 2: more).
  std::uint8_t runs(std::uint32_t line) { return seen(line); }
  bool over() const { return stop_ || ended_; }

 private:
  // ---- diagnostics -------------------------------------------------------
  std::uint32_t col_of(const Word* w) const { return w ? w->begin - blk_.begin + 1 : 1; }
  void warn(const Word* w, std::string msg) {
    if (in_sub_quiet()) return;
    diags_.report(Severity::warning, prog_->source(), blk_.line, col_of(w), std::move(msg));
  }
  // An error that makes every later position unknown: stop interpreting.
  bool refuse(const Word* w, std::string msg) {
    diags_.report(Severity::error, prog_->source(), blk_.line, col_of(w),
                  msg + "; block refused, interpretation stops here");
    stop_ = true;
    stats_.stopped_line = blk_.line;
    return false;
  }
  bool in_sub_quiet() { return seen(blk_.line) > 1; }  // repeated execution of a line
  // A word that names an integer (tool, register, repeat count). Checked as a
  // double first: converting an out-of-range double to int is undefined behaviour.
  bool whole(const Word* w, double lo, double hi, int& out, const std::string& what) {
    if (!(w->value >= lo && w->value <= hi) || w->value != std::floor(w->value))
      return refuse(w, what + " out of range: must be a whole number from " +
                           std::to_string(static_cast<long long>(lo)) + " to " + std::to_string(static_cast<long long>(hi)));
    out = static_cast<int>(w->value);
    return true;
  }
  std::string text_of(const Word& w) const { return std::string(prog_->bytes().substr(w.begin, w.end - w.begin)); }
  // Subprogram and canned-cycle repeats multiply work: a few lines can ask for
  // 9999^8 blocks. Past opt_.max_blocks blocks or motions, stop with an error.
  bool over_budget(std::uint64_t n, const char* what) {
    if (n < opt_.max_blocks) return false;
    if (!stop_)
      refuse(nullptr, "more than " + std::to_string(opt_.max_blocks) + " " + what +
                          " (subprogram and canned-cycle repeats); {max_blocks} raises the limit");
    return true;
  }

  // ---- numbers -----------------------------------------------------------
  double to_mm(double v) const { return inch_ ? v * 25.4 : v; }
  // A length word under the dialect's decimal-point rule (docs/physics.md, 'The decimal point').
  double length_mm(const Word& w) const {
    double v = w.value;
    if (!w.has_point && d_.decimal_rule == profile::DecimalRule::least_input_increment)
      v *= inch_ ? d_.lii_inch : d_.lii_mm;
    return to_mm(v);
  }
  Vec3 offset_of(const std::string& key) const {
    if (opt_.machine) {
      auto it = opt_.machine->work_offsets_mm.find(key);
      if (it != opt_.machine->work_offsets_mm.end()) return {it->second[0], it->second[1], it->second[2]};
    }
    return {0, 0, 0};
  }

  // ---- motions -----------------------------------------------------------
  Fixed fixed_for(MotionKind k, Fixed forced = Fixed::no) const {
    if (k == MotionKind::rapid) return Fixed::rapid;
    // Under G41/G42 the writer moves the programmed contour: a plain block in
    // G90 (the start-up move stays as written).
    if (comp_ != 400 && (!plain_ || !absolute_ || cc_.starting())) return Fixed::cutter_comp;
    if (forced != Fixed::no) return forced;
    if (blk_.block_delete) return Fixed::block_delete;
    if (!stack_.empty() && !runs_once()) return Fixed::subprogram;
    if (!absolute_ && !plain_) return Fixed::incremental;
    return Fixed::no;
  }
  void emit(MotionKind k, const Vec3& end, Fixed forced = Fixed::no, const Vec3* center = nullptr) {
    if (stop_ || over_budget(stats_.motions, "motions")) return;
    Motion m;
    m.kind = k;
    m.fixed = fixed_for(k, forced);
    m.plane = static_cast<std::uint8_t>(plane_);
    m.line = blk_.line;
    m.start_mm = pos_;
    m.end_mm = end;
    if (center) m.center_mm = *center;
    m.feed_mm_per_min = k == MotionKind::rapid ? 0.0 : feed_;
    m.tool = tool_;
    m.spindle_rpm = spindle_rpm_;
    m.inch = inch_;
    m.plain = plain_ && (stack_.empty() || runs_once()) &&
              (comp_ == 400 || absolute_) && !blk_.block_delete;
    m.incremental = !absolute_;
    m.work_offset_mm = wofs_;
    ++stats_.motions;
    if (m.fixed == Fixed::no) ++stats_.compensable;
    if (comp_ != 400) {
      if (!stats_.cutter_comp_motions) stats_.first_cutter_comp_line = blk_.line;
      ++stats_.cutter_comp_motions;
    }
    pos_ = end;
    comp_ok(cc_.add(m));  // the tool-centre path under G41/G42, else m itself
  }
  // Whether the block being run is on a line that runs once in the whole
  // program (Options::repeated_lines).
  bool runs_once() const {
    const auto* r = opt_.repeated_lines;
    return r && blk_.line < r->size() && !(*r)[blk_.line];
  }
  // A cutter-compensation message (empty: none) stops interpretation.
  bool comp_ok(const std::string& err) { return err.empty() || refuse(nullptr, err); }
  bool start_comp(const Word* g, const Word* wD);

  // ---- one line ----------------------------------------------------------
  void step(std::uint32_t line) {
    if (opt_.on_line) opt_.on_line(line);
    if (!stack_.empty() && calls_out_) {
      auto& sub_of = calls_out_->sub_of;
      if (sub_of.size() <= line) sub_of.resize(line + 1, 0);
      sub_of[line] = stack_.back().start_line;
    }
    bool first_time = seen(line) == 0;
    if (seen(line) < 2) ++seen(line);
    bool ok = prog_->lex(line, blk_, first_time ? diags_ : quiet_);
    if (over_budget(steps_++, "blocks executed")) return;
    if (blk_.kind == gcode::LineKind::ignored) { next_ = prog_->last_line() + 1; return; }
    if (blk_.kind == gcode::LineKind::percent) {
      if (prog_->closing_percent_line() == line) ended_ = true;
      return;
    }
    if (blk_.kind == gcode::LineKind::program_number || blk_.kind == gcode::LineKind::blank) {
      if (!ok) refuse(nullptr, "the line could not be read");
      return;
    }
    if (blk_.block_delete && opt_.block_delete_switch) return;
    if (blk_.macro) {
      diags_.report(Severity::error, prog_->source(), line, blk_.macro_col,
                    "macro B (#variables, [ ], IF/GOTO, WHILE/DO/END) is not interpreted; block refused, "
                    "interpretation stops here");
      stop_ = true;
      stats_.stopped_line = line;
      return;
    }
    if (!ok) { refuse(nullptr, "the line could not be read"); return; }
    ++stats_.blocks;
    execute();
  }

  // Runs the block lexed into blk_ (its steps in interpreter.cpp, in the order they run).
  bool execute();
  bool check_words(int codes[kGroups], const Word* code_word[kGroups]);
  struct MCodes { bool m6 = false, m98 = false, m99 = false, end = false; };
  MCodes m_codes() const;
  bool set_units_feed_tool(const int codes[kGroups], bool m6);
  bool set_plane_and_distance(const int codes[kGroups], const Word* const cw[kGroups]);
  bool set_compensation(const int codes[kGroups], const Word* const cw[kGroups]);
  bool set_work_offset(const int codes[kGroups], const Word* const cw[kGroups]);
  bool non_modal(const int codes[kGroups], const Word* const cw[kGroups], bool& axes_taken);
  bool motion_or_cycle(const int codes[kGroups], const Word* const cw[kGroups], bool axes_taken);
  bool do_motion(int mode, bool have_axes);
  bool do_arc(bool cw);
  bool do_cycle();
  bool set_cycle_levels();
  bool hole_position(Vec3& hole, Vec3& xy_step);
  void move_to_hole(const Vec3& hole);
  void cycle_moves(double top);
  Vec3 at_z(double z) const { Vec3 p = pos_; p[2] = z; return p; }  // the tool's XY at height z
  bool do_reference_return(bool g30);
  bool do_machine_move();
  bool axis_target(Vec3& target, bool& any);
  bool flow(bool m98, bool m99, bool end);

  std::uint8_t& seen(std::uint32_t line) { return seen_[line - base_ + 1]; }

  const gcode::Program* prog_ = nullptr;  // the piece being run
  std::uint32_t base_ = 1;                // its first line
  const Options& opt_;
  const profile::Dialect& d_;
  Diagnostics& diags_;
  MotionSink& sink_;
  CutterComp cc_;  // between emit() and sink_
  int d_reg_ = 0;  // the last D word (G41/G42 radius register)
  bool d_given_ = false;
  CallStructure* calls_out_ = nullptr;
  std::vector<std::uint8_t> seen_;  // per line of the piece: 0 never lexed, 1 once, 2 more (subprogram repeats)
  Diagnostics quiet_{nullptr, 0};   // lexes a line again without repeating its messages
  Block blk_;
  std::uint32_t next_ = 1;
  bool stop_ = false, ended_ = false, eof_ = false;
  Stats stats_;

  // Modal state (Fanuc power-on defaults; programs normally set them anyway).
  Vec3 pos_{0, 0, 0};
  bool known_[3] = {false, false, false};  // axis position known (set absolutely)
  Vec3 wofs_{0, 0, 0};
  std::string wcs_ = "G54";
  bool inch_ = false, units_set_ = false, absolute_ = true, ijk_absolute_ = false;
  int plane_ = 17, motion_ = -1, cycle_ = 800, comp_ = 400, length_ = 490, return_ = 980;
  int h_ = 0, tool_ = 0, next_tool_ = 0;
  std::uint64_t steps_ = 0;  // lines executed, repeats included (the --max-blocks budget)
  double feed_ = 0.0, spindle_rpm_ = 0.0;
  // Canned-cycle modal data (work frame, mm).
  double cyc_init_z_ = 0, cyc_r_ = 0, cyc_z_ = 0, cyc_q_ = 0;
  bool cyc_have_z_ = false, cyc_have_r_ = false;
  std::vector<Frame> stack_;
  std::unordered_map<std::int64_t, std::uint32_t> subs_;
  bool subs_indexed_ = false;
  std::unordered_map<int, Vec3> ref_;
  bool warned_units_ = false;
  bool plain_ = false;  // the motion being emitted comes from a plain G0-G3 block
};

}  // namespace deflex::interp::detail
