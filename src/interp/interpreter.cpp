// Fanuc/ISO modal interpreter. Structure: for each line, lex -> check words and
// modal groups -> apply modal settings in the control's order -> non-modal
// codes -> motion or canned cycle -> program flow (M98/M99/M30).
#include "deflex/interp/interpreter.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_map>

namespace deflex::interp {

const char* to_string(MotionKind k) {
  static const char* n[] = {"G0", "G1", "G2", "G3"};
  return n[static_cast<int>(k)];
}

const char* to_string(Fixed f) {
  switch (f) {
    case Fixed::no: return "compensable";
    case Fixed::rapid: return "rapid";
    case Fixed::cutter_comp: return "under cutter compensation (G41/G42)";
    case Fixed::canned_cycle: return "canned cycle";
    case Fixed::subprogram: return "in a subprogram";
    case Fixed::incremental: return "incremental (G91)";
    case Fixed::machine_frame: return "machine coordinates (G53/G28/G30)";
    case Fixed::block_delete: return "block delete '/'";
  }
  return "?";
}

namespace {

using gcode::Block;
using gcode::Word;

// Modal groups of Fanuc Series 0i/30i-M G codes (plus the few LinuxCNC codes the
// linuxcnc dialect reads). -1: unknown; -2: known but refused.
enum Group { g_nonmodal = 0, g_motion = 1, g_plane = 2, g_distance = 3, g_feedmode = 5, g_units = 6,
             g_cutcomp = 7, g_length = 8, g_cycle = 9, g_return = 10, g_scale = 11, g_macro = 12,
             g_css = 13, g_wcs = 14, g_path = 15, g_rotation = 16, g_polar = 17, g_arcdist = 18,
             kGroups = 19 };

struct CodeInfo { int group; const char* refusal; };

CodeInfo code_info(int c) {
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

std::string gname(int c10) {
  return "G" + std::to_string(c10 / 10) + (c10 % 10 ? "." + std::to_string(c10 % 10) : "");
}

struct Frame {
  std::uint32_t return_line;  // line after the M98
  std::uint32_t start_line;   // line of the O number
  int repeats_left;
};

// Plane axes: (first, second, normal) indices for G17/G18/G19.
struct PlaneAxes { int a, b, n; };
PlaneAxes plane_axes(int plane) {
  if (plane == 18) return {2, 0, 1};
  if (plane == 19) return {1, 2, 0};
  return {0, 1, 2};
}

class Run {
 public:
  Run(const gcode::Program& p, const Options& o, Diagnostics& d, MotionSink& s)
      : prog_(p), opt_(o), d_(o.dialect), diags_(d), sink_(s), seen_(p.line_count() + 2, 0) {
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

  Stats go() {
    std::uint32_t line = 1;
    const std::uint32_t n = prog_.line_count();
    while (line <= n && !stop_ && !ended_ && !diags_.too_many()) {
      next_ = line + 1;
      step(line);
      line = next_;
    }
    if (!stop_ && !ended_ && !stack_.empty())
      diags_.report(Severity::error, prog_.source().name(), "end of file inside a subprogram (no M99)");
    // Lines never executed (after M30, subprograms not called, after a stop)
    // are still read, so every lexical error in the file is reported.
    for (std::uint32_t l = 1; l <= n && !diags_.too_many(); ++l)
      if (!seen_[l]) prog_.lex(l, blk_, diags_);
    stats_.stopped = stop_;
    stats_.ended = ended_;
    stats_.lines = n;
    return stats_;
  }

 private:
  // ---- diagnostics -------------------------------------------------------
  std::uint32_t col_of(const Word* w) const { return w ? w->begin - blk_.begin + 1 : 1; }
  void warn(const Word* w, std::string msg) {
    if (in_sub_quiet()) return;
    diags_.report(Severity::warning, prog_.source(), blk_.line, col_of(w), std::move(msg));
  }
  // An error that makes every later position unknown: stop interpreting.
  bool refuse(const Word* w, std::string msg) {
    diags_.report(Severity::error, prog_.source(), blk_.line, col_of(w),
                  msg + "; block refused, interpretation stops here");
    stop_ = true;
    stats_.stopped_line = blk_.line;
    return false;
  }
  bool in_sub_quiet() const { return seen_[blk_.line] > 1; }  // repeated execution of a line
  // A word that names an integer (tool, register, repeat count). Checked as a
  // double first: converting an out-of-range double to int is undefined behaviour.
  bool whole(const Word* w, double lo, double hi, int& out, const std::string& what) {
    if (!(w->value >= lo && w->value <= hi) || w->value != std::floor(w->value))
      return refuse(w, what + " out of range: must be a whole number from " +
                           std::to_string(static_cast<long long>(lo)) + " to " + std::to_string(static_cast<long long>(hi)));
    out = static_cast<int>(w->value);
    return true;
  }
  std::string text_of(const Word& w) const { return std::string(prog_.bytes().substr(w.begin, w.end - w.begin)); }
  // Subprogram and canned-cycle repeats multiply work: a few lines can ask for
  // 9999^8 blocks. Past opt_.max_blocks blocks or motions, stop with an error.
  bool over_budget(std::uint64_t n, const char* what) {
    if (n < opt_.max_blocks) return false;
    if (!stop_)
      refuse(nullptr, "more than " + std::to_string(opt_.max_blocks) + " " + what +
                          " (subprogram and canned-cycle repeats); --max-blocks raises the limit");
    return true;
  }

  // ---- numbers -----------------------------------------------------------
  double to_mm(double v) const { return inch_ ? v * 25.4 : v; }
  // A length word under the dialect's decimal-point rule (REFERENCE §2.1).
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
    if (comp_ != 400) return Fixed::cutter_comp;
    if (forced != Fixed::no) return forced;
    if (blk_.block_delete) return Fixed::block_delete;
    if (!stack_.empty()) return Fixed::subprogram;
    if (!absolute_) return Fixed::incremental;
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
    m.plain = plain_ && absolute_ && stack_.empty() && comp_ == 400 && !blk_.block_delete;
    m.work_offset_mm = wofs_;
    ++stats_.motions;
    if (m.fixed == Fixed::no) ++stats_.compensable;
    if (m.fixed == Fixed::cutter_comp) {
      if (!stats_.cutter_comp_motions) stats_.first_cutter_comp_line = blk_.line;
      ++stats_.cutter_comp_motions;
    }
    sink_.motion(m);
    pos_ = end;
  }

  // ---- one line ----------------------------------------------------------
  void step(std::uint32_t line) {
    bool first_time = seen_[line] == 0;
    if (seen_[line] < 2) ++seen_[line];
    bool ok = prog_.lex(line, blk_, first_time ? diags_ : quiet_);
    if (over_budget(steps_++, "blocks executed")) return;
    if (blk_.kind == gcode::LineKind::ignored) { next_ = prog_.line_count() + 1; return; }
    if (blk_.kind == gcode::LineKind::percent) {
      if (prog_.closing_percent_line() == line) ended_ = true;
      return;
    }
    if (blk_.kind == gcode::LineKind::program_number || blk_.kind == gcode::LineKind::blank) {
      if (!ok) refuse(nullptr, "the line could not be read");
      return;
    }
    if (blk_.block_delete && opt_.block_delete_switch) return;
    if (blk_.macro) {
      diags_.report(Severity::error, prog_.source(), line, blk_.macro_col,
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

  bool execute();
  bool check_words(int codes[kGroups], const Word* code_word[kGroups]);
  bool do_motion(int mode, bool have_axes);
  bool do_arc(bool cw);
  bool do_cycle();
  bool do_reference_return(bool g30);
  bool do_machine_move();
  bool axis_target(Vec3& target, bool& any);
  bool flow(bool m98, bool m99, bool end);

  const gcode::Program& prog_;
  const Options& opt_;
  const profile::Dialect& d_;
  Diagnostics& diags_;
  MotionSink& sink_;
  std::vector<std::uint8_t> seen_;  // 0 never lexed, 1 once, 2 more (subprogram repeats)
  Diagnostics quiet_{nullptr, 0};   // lexes a line again without repeating its messages
  Block blk_;
  std::uint32_t next_ = 1;
  bool stop_ = false, ended_ = false;
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

bool Run::check_words(int codes[kGroups], const Word* code_word[kGroups]) {
  std::uint32_t letters_seen = 0;
  for (const Word& w : blk_.words) {
    switch (w.letter) {
      case 'G': {
        int c = w.code10();
        if (c < 0) return refuse(&w, text_of(w) + " is not a G code (too large, negative or more than one decimal)");
        CodeInfo info = c < 0 ? CodeInfo{-1, nullptr} : code_info(c);
        if (info.group == -2) return refuse(&w, info.refusal);
        bool linuxcnc_only = c == 591 || c == 592 || c == 593 || c == 611 || c == 901 || c == 911;
        bool ext_ok = (c == 541 && d_.extended_offsets == profile::ExtendedOffsets::g54_1) ||
                      (c == 1540 && d_.extended_offsets == profile::ExtendedOffsets::g154) ||
                      ((c >= 591 && c <= 593) && d_.extended_offsets == profile::ExtendedOffsets::g59_x);
        if (info.group == -1 || (linuxcnc_only && c != 611 && !ext_ok && c != 901 && c != 911) ||
            ((c == 541 || c == 1540) && !ext_ok))
          return refuse(&w, "unknown G code " + gname(c < 0 ? 0 : c) + " for the " + d_.name + " dialect");
        if (code_word[info.group] && info.group != g_nonmodal)
          return refuse(&w, gname(c) + " and " + gname(codes[info.group]) +
                                " are in the same modal group: one code per group in a block");
        if (code_word[info.group] && info.group == g_nonmodal)
          return refuse(&w, gname(c) + " and " + gname(codes[info.group]) + " in one block: one non-modal code per block");
        codes[info.group] = c;
        code_word[info.group] = &w;
        break;
      }
      case 'M':
        if (w.code10() < 0) return refuse(&w, text_of(w) + " is not an M code (too large, negative or more than one decimal)");
        break;
      case 'N': case 'O': break;
      case 'X': case 'Y': case 'Z': case 'I': case 'J': case 'K': case 'R': case 'F': case 'S': case 'T':
      case 'H': case 'D': case 'P': case 'Q': case 'L': {
        std::uint32_t bit = 1u << (w.letter - 'A');
        if (letters_seen & bit) return refuse(&w, std::string("two ") + w.letter + " words in one block");
        letters_seen |= bit;
        break;
      }
      case 'A': case 'B': case 'C': case 'U': case 'V': case 'W':
        return refuse(&w, std::string("axis ") + w.letter + ": deflex reads 3-axis programs (X Y Z)");
      default:
        return refuse(&w, std::string("address '") + w.letter + "' has no meaning on a 3-axis mill");
    }
  }
  return true;
}

bool Run::execute() {
  int codes[kGroups];
  const Word* cw[kGroups] = {};
  for (int& c : codes) c = -1;
  if (!check_words(codes, cw)) return false;

  // M codes of the block.
  bool m6 = false, m98 = false, m99 = false, end = false;
  for (const Word& w : blk_.words) {
    if (w.letter != 'M') continue;
    int m = w.code10();
    if (m == 60) m6 = true;
    else if (m == 980) m98 = true;
    else if (m == 990) m99 = true;
    else if (m == 20 || m == 300) end = true;
  }
  const Word* wF = blk_.find('F');
  const Word* wT = blk_.find('T');
  const Word* wH = blk_.find('H');
  const Word* wP = blk_.find('P');

  // Units first: every length in this block is read in the new units.
  if (codes[g_units] >= 0) { inch_ = codes[g_units] == 200; units_set_ = true; }
  if (!units_set_ && !warned_units_) {
    for (const Word& w : blk_.words)
      if (w.letter == 'X' || w.letter == 'Y' || w.letter == 'Z') {
        warn(&w, "no G20/G21 before the first coordinate: read as G21 (mm), the usual power-on state");
        warned_units_ = true;
        break;
      }
  }
  if (wF) {
    if (wF->value < 0) return refuse(wF, "negative feed rate");
    feed_ = to_mm(wF->value);
  }
  if (wT && !whole(wT, 0, 99999999, next_tool_, "tool number T")) return false;
  if (const Word* wS = blk_.find('S')) spindle_rpm_ = wS->value;
  if (m6) tool_ = next_tool_;
  if (codes[g_plane] >= 0) plane_ = codes[g_plane] / 10;
  if (codes[g_distance] >= 0) absolute_ = codes[g_distance] == 900;
  if (codes[g_arcdist] >= 0) ijk_absolute_ = codes[g_arcdist] == 901;
  if (codes[g_cutcomp] >= 0) comp_ = codes[g_cutcomp];
  if (codes[g_length] >= 0) {
    length_ = codes[g_length];
    // H may stand anywhere in the block (REFERENCE §2.6); it names an offset register.
    if (wH && !whole(wH, 0, 99999999, h_, "offset register H")) return false;
    if (length_ != 490 && !wH) warn(cw[g_length], gname(length_) + " without H: offset H" + std::to_string(h_) + " stays active");
  }
  if (codes[g_wcs] >= 0) {
    int c = codes[g_wcs];
    std::string key;
    if (c == 541 || c == 1540) {
      if (!wP) return refuse(cw[g_wcs], gname(c) + " needs P (extended work offset number)");
      int p = 0;
      if (!whole(wP, 1, c == 541 ? 48 : 99, p, "extended work offset P")) return false;
      key = "G54.1P" + std::to_string(p);
    } else {
      key = gname(c);
    }
    Vec3 o = offset_of(key);
    // The tool stays where it is; its coordinates change with the frame.
    for (int i = 0; i < 3; ++i) pos_[i] += wofs_[i] - o[i];
    wofs_ = o;
    wcs_ = key;
  }
  if (codes[g_return] >= 0) return_ = codes[g_return];

  // Non-modal codes that take the axis words.
  int nm = codes[g_nonmodal];
  if (nm == 40) {  // dwell: X or P is a time, not a position
    if (codes[g_motion] >= 0 || codes[g_cycle] >= 0) return refuse(cw[g_nonmodal], "G4 with a motion code in one block");
  } else if (nm == 280 || nm == 300) {
    if (!do_reference_return(nm == 300)) return false;
  } else if (nm == 530) {
    if (!do_machine_move()) return false;
  }
  bool axes_taken = nm == 40 || nm == 280 || nm == 300 || nm == 530;

  // Motion group: G0..G3 cancel a canned cycle; G80 cancels it explicitly.
  if (codes[g_motion] >= 0 && codes[g_cycle] >= 0 && codes[g_cycle] != 800)
    return refuse(cw[g_cycle], gname(codes[g_motion]) + " and canned cycle " + gname(codes[g_cycle]) + " in one block");
  if (codes[g_motion] >= 0) { motion_ = codes[g_motion]; cycle_ = 800; }
  if (codes[g_cycle] == 800) { cycle_ = 800; cyc_have_z_ = cyc_have_r_ = false; }
  bool new_cycle = false;
  if (codes[g_cycle] >= 0 && codes[g_cycle] != 800) {
    new_cycle = cycle_ == 800;
    if (new_cycle) { cyc_init_z_ = pos_[2]; cyc_have_z_ = cyc_have_r_ = false; }
    cycle_ = codes[g_cycle];
  }
  bool have_axes = false;
  for (const Word& w : blk_.words)
    if (w.letter == 'X' || w.letter == 'Y' || w.letter == 'Z') have_axes = true;
  if (!axes_taken) {
    if (cycle_ != 800) {
      bool have_r = blk_.find('R') != nullptr;
      if (have_axes || have_r) { if (!do_cycle()) return false; }
    } else if (!do_motion(motion_, have_axes)) {
      return false;
    }
  }
  return flow(m98, m99, end);
}

bool Run::axis_target(Vec3& t, bool& any) {
  t = pos_;
  any = false;
  static const char axes[] = {'X', 'Y', 'Z'};
  for (int i = 0; i < 3; ++i) {
    const Word* w = blk_.find(axes[i]);
    if (!w) continue;
    any = true;
    double v = length_mm(*w);
    if (absolute_) {
      t[i] = v;
      known_[i] = true;
    } else {
      if (!known_[i]) return refuse(w, std::string("incremental ") + axes[i] + " move before the " + axes[i] +
                                           " position is known (no absolute move on that axis yet)");
      t[i] = pos_[i] + v;
    }
  }
  return true;
}

bool Run::do_motion(int mode, bool have_axes) {
  bool arc = mode == 20 || mode == 30;
  bool have_ijk = blk_.find('I') || blk_.find('J') || blk_.find('K');
  if (!arc) {
    for (char c : {'I', 'J', 'K', 'R'})
      if (const Word* w = blk_.find(c)) warn(w, std::string(1, c) + " has no effect outside an arc or a canned cycle");
  }
  if (!have_axes && !(arc && have_ijk)) return true;
  if (mode < 0) {
    const Word* w = blk_.find('X') ? blk_.find('X') : blk_.find('Y') ? blk_.find('Y') : blk_.find('Z');
    return refuse(w, "axis words but no motion mode yet (G0/G1/G2/G3)");
  }
  if (arc) return do_arc(mode == 20);
  Vec3 t;
  bool any;
  if (!axis_target(t, any)) return false;
  if (mode == 10 && feed_ <= 0) return refuse(blk_.find('X'), "G1 move with no feed rate (F) set");
  plain_ = true;
  emit(mode == 0 ? MotionKind::rapid : MotionKind::linear, t);
  plain_ = false;
  return true;
}

bool Run::do_arc(bool cw) {
  PlaneAxes p = plane_axes(plane_);
  if (feed_ <= 0) return refuse(nullptr, "arc with no feed rate (F) set");
  for (int i = 0; i < 3; ++i)
    if (i != p.n && !known_[i]) return refuse(nullptr, "arc from a position that is not known yet");
  Vec3 end;
  bool any;
  if (!axis_target(end, any)) return false;
  static const char ijk[] = {'I', 'J', 'K'};
  const Word* wr = blk_.find('R');
  const Word* wo = blk_.find(ijk[p.n]);
  if (wo) return refuse(wo, std::string(1, ijk[p.n]) + " is not in the " + gname(plane_ * 10) + " plane");
  if (const Word* wp = blk_.find('P')) return refuse(wp, "P (turns) in an arc is not interpreted");
  const Word* wa = blk_.find(ijk[p.a]);
  const Word* wb = blk_.find(ijk[p.b]);
  double sa = pos_[p.a], sb = pos_[p.b], ea = end[p.a], eb = end[p.b];
  double ca, cb;
  double tol = d_.arc_radius_tolerance_mm;
  if (wr) {
    if (wa || wb) return refuse(wr, "arc with both R and I/J/K");
    double r = length_mm(*wr);
    double dx = ea - sa, dy = eb - sb, chord = std::hypot(dx, dy);
    if (chord < 1e-9) return refuse(wr, "R-form arc whose end is its start: a full circle cannot be written with R");
    double half = chord / 2, ar = std::fabs(r);
    if (ar < 1e-9) return refuse(wr, "arc radius R0");
    if (half > ar + tol) {
      char buf[128];
      std::snprintf(buf, sizeof buf, "R%.4f mm is too small for the %.4f mm chord", ar, chord);
      return refuse(wr, buf);
    }
    double h = half >= ar ? 0.0 : std::sqrt(ar * ar - half * half);
    // Centre left of the chord for a short counter-clockwise arc; R<0 (> 180°)
    // and clockwise each flip the side (REFERENCE §2.4).
    double side = (cw ? -1.0 : 1.0) * (r < 0 ? -1.0 : 1.0);
    ca = sa + dx / 2 - side * h * dy / chord;
    cb = sb + dy / 2 + side * h * dx / chord;
  } else {
    if (!wa && !wb) return refuse(nullptr, "arc with neither I/J/K nor R");
    if (ijk_absolute_) {
      ca = wa ? length_mm(*wa) : sa;
      cb = wb ? length_mm(*wb) : sb;
    } else {
      // I/J/K are incremental from the start point in G90 and G91 alike (REFERENCE §2.3).
      ca = sa + (wa ? length_mm(*wa) : 0.0);
      cb = sb + (wb ? length_mm(*wb) : 0.0);
    }
    double r1 = std::hypot(sa - ca, sb - cb), r2 = std::hypot(ea - ca, eb - cb);
    if (r1 < 1e-9) return refuse(wa ? wa : wb, "arc centre at its start point (radius 0)");
    if (std::fabs(r1 - r2) > tol) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "arc end off the radius by %.4f mm (start radius %.4f, end radius %.4f; tolerance %.4f)",
                    std::fabs(r1 - r2), r1, r2, tol);
      return refuse(wa ? wa : wb, buf);
    }
  }
  Vec3 c = pos_;
  c[p.a] = ca;
  c[p.b] = cb;
  plain_ = !ijk_absolute_;  // G90.1 centres are absolute: moving the arc would need new I/J
  emit(cw ? MotionKind::arc_cw : MotionKind::arc_ccw, end, Fixed::no, &c);
  plain_ = false;
  return true;
}

bool Run::do_reference_return(bool g30) {
  int refno = 1;
  const Word* wp = blk_.find('P');
  if (g30) {
    refno = 2;
    if (wp && !whole(wp, 2, 4, refno, "G30 P")) return false;
  }
  Vec3 ref{0, 0, 0};  // G28: the reference point is machine zero unless the profile says otherwise
  auto it = ref_.find(refno);
  if (it != ref_.end()) ref = it->second;
  else if (g30)
    return refuse(nullptr, "G30 P" + std::to_string(refno) + ": the machine profile has no reference_points_mm." +
                               std::to_string(refno));
  Vec3 mid;
  bool any;
  if (!axis_target(mid, any)) return false;
  if (!any) {
    warn(nullptr, std::string(g30 ? "G30" : "G28") + " without axis words moves no axis on a Fanuc control");
    return true;
  }
  emit(MotionKind::rapid, mid, Fixed::machine_frame);
  Vec3 t = pos_;
  static const char axes[] = {'X', 'Y', 'Z'};
  for (int i = 0; i < 3; ++i)
    if (blk_.find(axes[i])) { t[i] = ref[i] - wofs_[i]; known_[i] = true; }
  emit(MotionKind::rapid, t, Fixed::machine_frame);
  return true;
}

bool Run::do_machine_move() {
  if (!absolute_) return refuse(blk_.words.empty() ? nullptr : &blk_.words[0], "G53 in G91 (incremental) mode");
  if (motion_ != 0 && motion_ != 10) return refuse(nullptr, "G53 needs G0 or G1 as the motion mode");
  Vec3 t = pos_;
  static const char axes[] = {'X', 'Y', 'Z'};
  bool any = false;
  for (int i = 0; i < 3; ++i)
    if (const Word* w = blk_.find(axes[i])) { t[i] = length_mm(*w) - wofs_[i]; known_[i] = true; any = true; }
  if (any) emit(motion_ == 0 ? MotionKind::rapid : MotionKind::linear, t, Fixed::machine_frame);
  return true;
}

// Canned cycles in G17 (drilling along Z), Fanuc semantics: position in XY at
// the current level, rapid to R, the cycle's own moves to Z, retract to the
// initial level (G98) or R (G99). In G91, R is measured from the initial level
// and Z from R. Repeats (K or L, per dialect) step the XY increment in G91.
bool Run::do_cycle() {
  if (plane_ != 17) return refuse(nullptr, "canned cycles outside G17 are not interpreted");
  if (comp_ != 400) return refuse(nullptr, "canned cycle under cutter compensation");
  const Word* wz = blk_.find('Z');
  const Word* wr = blk_.find('R');
  const Word* wq = blk_.find('Q');
  const Word* wk = blk_.find(d_.cycle_repeat_word);
  int repeats = 1;
  if (wk) {
    if (!whole(wk, 0, 9999, repeats, "repeat count")) return false;
  }
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
  double top = return_ == 980 ? std::max(cyc_init_z_, cyc_r_) : cyc_r_;

  // XY of the hole: absolute once, or incremental per repeat.
  Vec3 xy_step{0, 0, 0};
  Vec3 hole = pos_;
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
  const Fixed cc = Fixed::canned_cycle;
  auto at = [&](double z) { Vec3 p = pos_; p[2] = z; return p; };
  // A tiny Q would make pecks without end (depth - Q == depth in doubles).
  if ((cycle_ == 730 || cycle_ == 830) && (cyc_r_ - cyc_z_) / cyc_q_ > static_cast<double>(opt_.max_blocks))
    return refuse(wq, "peck depth Q gives more than " + std::to_string(opt_.max_blocks) +
                          " pecks; --max-blocks raises the limit");
  for (int k = 0; k < repeats && !stop_; ++k) {
    if (!absolute_) { hole[0] = pos_[0] + xy_step[0]; hole[1] = pos_[1] + xy_step[1]; }
    if (!d_.cycle_positions_before_raise && pos_[2] < cyc_r_) emit(MotionKind::rapid, at(cyc_r_), cc);
    Vec3 p = pos_;
    p[0] = hole[0];
    p[1] = hole[1];
    if (p != pos_) emit(MotionKind::rapid, p, cc);
    if (pos_[2] != cyc_r_) emit(MotionKind::rapid, at(cyc_r_), cc);
    double z = cyc_z_, r = cyc_r_;
    switch (cycle_) {
      case 810: case 820:
        emit(MotionKind::linear, at(z), cc);
        emit(MotionKind::rapid, at(top), cc);
        break;
      case 860:
        emit(MotionKind::linear, at(z), cc);
        emit(MotionKind::rapid, at(top), cc);
        break;
      case 840: case 740: case 850: case 890:
        emit(MotionKind::linear, at(z), cc);
        emit(MotionKind::linear, at(r), cc);
        if (top != r) emit(MotionKind::rapid, at(top), cc);
        break;
      case 730: case 830: {
        // G73: retract d after each peck; G83: back to R, then rapid to d above the last depth.
        double d = d_.peck_retract_mm, depth = r;
        while (!stop_) {
          depth = std::max(depth - cyc_q_, z);
          emit(MotionKind::linear, at(depth), cc);
          if (depth <= z) break;
          if (cycle_ == 830) emit(MotionKind::rapid, at(r), cc);
          emit(MotionKind::rapid, at(std::min(depth + d, r)), cc);
        }
        emit(MotionKind::rapid, at(top), cc);
        break;
      }
      case 760: {
        emit(MotionKind::linear, at(z), cc);
        Vec3 s = pos_;
        int ax = d_.fine_boring_shift[1] == 'X' ? 0 : 1;
        double sign = d_.fine_boring_shift[0] == '-' ? -1.0 : 1.0;
        s[ax] += sign * cyc_q_;
        emit(MotionKind::rapid, s, cc);
        emit(MotionKind::rapid, at(top), cc);
        Vec3 back = pos_;
        back[ax] -= sign * cyc_q_;
        emit(MotionKind::rapid, back, cc);
        break;
      }
    }
  }
  return true;
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
    for (std::uint32_t i = wp->num_begin; i < wp->end; ++i) digits += std::isdigit(static_cast<unsigned char>(prog_.bytes()[i])) != 0;
    int repeats = 1;
    if (const Word* wl = blk_.find('L')) {
      if (wl->value > 9999) return refuse(wl, "subprogram repeat count over 9999");
      if (!whole(wl, 0, 9999, repeats, "subprogram repeat count L")) return false;
    } else if (digits > 4) { repeats = static_cast<int>(p / 10000); p %= 10000; }  // Fanuc P rrrr nnnn
    if (repeats > 9999) return refuse(wp, "subprogram repeat count over 9999");
    if (repeats < 1) return true;
    if (!subs_indexed_) {
      Diagnostics quiet(nullptr, 0);
      gcode::Block b;
      for (std::uint32_t l = 1; l <= prog_.line_count(); ++l) {
        std::string_view t = prog_.source().line_text(l);
        std::size_t k = t.find_first_not_of(" \t");
        if (k == std::string_view::npos || (t[k] != 'O' && t[k] != 'o' && t[k] != ':')) continue;
        prog_.lex(l, b, quiet);
        if (b.kind == gcode::LineKind::program_number && !subs_.count(b.program_number)) subs_[b.program_number] = l;
      }
      subs_indexed_ = true;
    }
    auto it = subs_.find(p);
    if (it == subs_.end()) return refuse(wp, "subprogram O" + std::to_string(p) + " is not in this file");
    if (stack_.size() >= 8) return refuse(wp, "subprograms nested deeper than 8 (recursion?)");
    stack_.push_back({next_, it->second, repeats});
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

}  // namespace

Stats interpret(const gcode::Program& prog, const Options& opt, Diagnostics& diags, MotionSink& sink) {
  Run r(prog, opt, diags, sink);
  return r.go();
}

}  // namespace deflex::interp
