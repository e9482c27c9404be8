// Fanuc/ISO modal interpreter. Structure: for each line, lex -> check words and
// modal groups -> apply modal settings in the control's order -> non-modal
// codes -> motion or canned cycle -> program flow (M98/M99/M30).
#include "run.hpp"

namespace deflex::interp {

const char* to_string(MotionKind k) {
  static const char* n[] = {"G0", "G1", "G2", "G3"};
  return n[static_cast<int>(k)];
}

const char* to_string(Fixed f) {
  switch (f) {
    case Fixed::no: return "compensable";
    case Fixed::rapid: return "rapid";
    case Fixed::cutter_comp: return "cutter compensation start-up, or under it in G91";
    case Fixed::canned_cycle: return "canned cycle";
    case Fixed::subprogram: return "in a subprogram";
    case Fixed::incremental: return "incremental (G91)";
    case Fixed::machine_frame: return "machine coordinates (G53/G28/G30)";
    case Fixed::block_delete: return "block delete '/'";
    case Fixed::held: return "ends where a block deflex cannot move starts";
    case Fixed::no_normal: return "surface normal not determined";
    case Fixed::gouge: return "cuts into the part (gouge check)";
  }
  return "?";
}

namespace detail {

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
  const MCodes m = m_codes();
  // Modal settings in the control's order, units first: every length in this
  // block is read in the new units.
  if (!set_units_feed_tool(codes, m.m6) || !set_plane_and_distance(codes, cw) || !set_compensation(codes, cw) ||
      !set_work_offset(codes, cw))
    return false;
  if (codes[g_return] >= 0) return_ = codes[g_return];
  bool axes_taken = false;
  if (!non_modal(codes, cw, axes_taken) || !motion_or_cycle(codes, cw, axes_taken)) return false;
  return flow(m.m98, m.m99, m.end);
}

Run::MCodes Run::m_codes() const {
  MCodes m;
  for (const Word& w : blk_.words) {
    if (w.letter != 'M') continue;
    int c = w.code10();
    if (c == 60) m.m6 = true;
    else if (c == 980) m.m98 = true;
    else if (c == 990) m.m99 = true;
    else if (c == 20 || c == 300) m.end = true;
  }
  return m;
}

// G20/G21, then F, T, S and M6 (which take the new units and tool number).
bool Run::set_units_feed_tool(const int codes[kGroups], bool m6) {
  if (codes[g_units] >= 0) { inch_ = codes[g_units] == 200; units_set_ = true; }
  if (!units_set_ && !warned_units_) {
    for (const Word& w : blk_.words)
      if (w.letter == 'X' || w.letter == 'Y' || w.letter == 'Z') {
        warn(&w, "no G20/G21 before the first coordinate: read as G21 (mm), the usual power-on state");
        warned_units_ = true;
        break;
      }
  }
  if (const Word* wF = blk_.find('F')) {
    if (wF->value < 0) return refuse(wF, "negative feed rate");
    feed_ = to_mm(wF->value);
  }
  const Word* wT = blk_.find('T');
  if (wT && !whole(wT, 0, 99999999, next_tool_, "tool number T")) return false;
  if (const Word* wS = blk_.find('S')) spindle_rpm_ = wS->value;
  if (m6) tool_ = next_tool_;
  return true;
}

// G17/G18/G19, G90/G91 and G90.1/G91.1.
bool Run::set_plane_and_distance(const int codes[kGroups], const Word* const cw[kGroups]) {
  if (codes[g_plane] >= 0) {
    if (cc_.on() && codes[g_plane] != plane_ * 10)
      return refuse(cw[g_plane], "a plane change under cutter compensation: cancel it with G40 first");
    plane_ = codes[g_plane] / 10;
  }
  if (codes[g_distance] >= 0) absolute_ = codes[g_distance] == 900;
  if (codes[g_arcdist] >= 0) ijk_absolute_ = codes[g_arcdist] == 901;
  return true;
}

// D, G40/G41/G42, then G43/G44/G49 with H.
bool Run::set_compensation(const int codes[kGroups], const Word* const cw[kGroups]) {
  if (const Word* wD = blk_.find('D')) {
    const int before = d_reg_;
    if (!whole(wD, 0, 9999, d_reg_, "offset register D")) return false;
    // A new radius under compensation needs its own start-up (LinuxCNC
    // refuses it; Fanuc changes the offset vector at the block's end).
    if (cc_.on() && d_given_ && d_reg_ != before && codes[g_cutcomp] < 0)
      return refuse(wD, "a change of D under cutter compensation is not interpreted: cancel it with G40 first");
    d_given_ = true;
  }
  if (codes[g_cutcomp] >= 0) {
    comp_ = codes[g_cutcomp];
    if (comp_ == 400 ? !comp_ok(cc_.stop()) : !start_comp(cw[g_cutcomp], blk_.find('D'))) return false;
  }
  if (codes[g_length] >= 0) {
    length_ = codes[g_length];
    // H may stand anywhere in the block (docs/physics.md, 'H anywhere'); it names an offset register.
    const Word* wH = blk_.find('H');
    if (wH && !whole(wH, 0, 99999999, h_, "offset register H")) return false;
    if (length_ != 490 && !wH) warn(cw[g_length], gname(length_) + " without H: offset H" + std::to_string(h_) + " stays active");
  }
  return true;
}

// G54..G59, G54.1 P / G154 P and G59.x.
bool Run::set_work_offset(const int codes[kGroups], const Word* const cw[kGroups]) {
  if (codes[g_wcs] < 0) return true;
  int c = codes[g_wcs];
  std::string key;
  if (c == 541 || c == 1540) {
    const Word* wP = blk_.find('P');
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
  return true;
}

// Non-modal codes that take the axis words (`axes_taken`: the block's X Y Z
// are theirs, not a motion's).
bool Run::non_modal(const int codes[kGroups], const Word* const cw[kGroups], bool& axes_taken) {
  int nm = codes[g_nonmodal];
  if (nm == 40) {  // dwell: X or P is a time, not a position
    if (codes[g_motion] >= 0 || codes[g_cycle] >= 0) return refuse(cw[g_nonmodal], "G4 with a motion code in one block");
  } else if (nm == 280 || nm == 300) {
    if (!do_reference_return(nm == 300)) return false;
  } else if (nm == 530) {
    if (!do_machine_move()) return false;
  }
  axes_taken = nm == 40 || nm == 280 || nm == 300 || nm == 530;
  return true;
}

// Motion group: G0..G3 cancel a canned cycle; G80 cancels it explicitly.
bool Run::motion_or_cycle(const int codes[kGroups], const Word* const cw[kGroups], bool axes_taken) {
  if (codes[g_motion] >= 0 && codes[g_cycle] >= 0 && codes[g_cycle] != 800)
    return refuse(cw[g_cycle], gname(codes[g_motion]) + " and canned cycle " + gname(codes[g_cycle]) + " in one block");
  if (codes[g_motion] >= 0) { motion_ = codes[g_motion]; cycle_ = 800; }
  if (codes[g_cycle] == 800) { cycle_ = 800; cyc_have_z_ = cyc_have_r_ = false; }
  if (codes[g_cycle] >= 0 && codes[g_cycle] != 800) {
    if (cycle_ == 800) { cyc_init_z_ = pos_[2]; cyc_have_z_ = cyc_have_r_ = false; }
    cycle_ = codes[g_cycle];
  }
  bool have_axes = false;
  for (const Word& w : blk_.words)
    if (w.letter == 'X' || w.letter == 'Y' || w.letter == 'Z') have_axes = true;
  if (axes_taken) return true;
  if (cycle_ != 800) {
    bool have_r = blk_.find('R') != nullptr;
    if (have_axes || have_r) return do_cycle();
    return true;
  }
  return do_motion(motion_, have_axes);
}

// G41/G42: the radius of the D register (LinuxCNC without any D: the tool's).
bool Run::start_comp(const Word* g, const Word* wD) {
  if (plane_ != 17 && !cc_.on())
    return refuse(g, "cutter compensation in " + gname(plane_ * 10) + " is not interpreted (G17 only)");
  int reg = d_reg_;
  if (!d_given_ && d_.name == "linuxcnc") reg = tool_;
  double r = 0;
  if (reg == 0) {
    if (!d_given_ && d_.name != "linuxcnc")
      warn(g, gname(comp_) + " without a D word: D0, radius 0 (the control does not offset the path)");
  } else {
    std::optional<double> found = opt_.cutter_radius_mm ? opt_.cutter_radius_mm(reg) : std::nullopt;
    if (!found)
      return refuse(wD ? wD : g, "D" + std::to_string(reg) + ": no radius for cutter compensation (no tool_offsets "
                                 "entry " + std::to_string(reg) + " in the machine profile and no tool T" +
                                 std::to_string(reg) + " in the tool library)");
    r = *found;
  }
  if (r < 0) return refuse(wD ? wD : g, "D" + std::to_string(reg) + ": negative radius (radius plus wear)");
  return comp_ok(cc_.start(comp_ == 410 ? 1 : -1, r));
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
    // and clockwise each flip the side (docs/physics.md, 'R-form arcs').
    double side = (cw ? -1.0 : 1.0) * (r < 0 ? -1.0 : 1.0);
    ca = sa + dx / 2 - side * h * dy / chord;
    cb = sb + dy / 2 + side * h * dx / chord;
  } else {
    if (!wa && !wb) return refuse(nullptr, "arc with neither I/J/K nor R");
    if (ijk_absolute_) {
      ca = wa ? length_mm(*wa) : sa;
      cb = wb ? length_mm(*wb) : sb;
    } else {
      // I/J/K are incremental from the start point in G90 and G91 alike (docs/physics.md, 'Arcs and planes').
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
  if (cc_.on()) return refuse(nullptr, "G28/G30 under cutter compensation: cancel it with G40 first");
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
  if (cc_.on()) return refuse(nullptr, "G53 under cutter compensation: cancel it with G40 first");
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

}  // namespace detail

Stats interpret(const gcode::Program& prog, const Options& opt, Diagnostics& diags, MotionSink& sink) {
  detail::Run r(opt, diags, sink);
  r.feed(prog, true);
  return r.stats();
}

namespace {
struct NoMotions : MotionSink {
  void motion(const Motion&) override {}
};
}  // namespace

CallStructure call_structure(const gcode::Program& whole, const Options& opt, Diagnostics& diags) {
  CallStructure c;
  NoMotions none;
  detail::Run r(opt, diags, none);
  r.record_calls(&c);
  r.feed(whole, true);
  c.repeated.assign(whole.last_line() + 1, 0);
  for (std::uint32_t l = whole.first_line(); l <= whole.last_line(); ++l) c.repeated[l] = r.runs(l) > 1;
  c.sub_of.resize(whole.last_line() + 1, 0);
  return c;
}

std::string CallStructure::name_of(std::uint32_t o_line, const gcode::Program& prog) const {
  const std::string_view t = prog.source().line_text(o_line);
  const std::size_t b = t.find_first_not_of(" \t");
  if (b == std::string_view::npos) return "O?";
  const std::size_t e = t.find_first_of(" \t(;", b);
  return std::string(t.substr(b, e == std::string_view::npos ? e : e - b));
}

Interpreter::Interpreter(const Options& opt, Diagnostics& diags, MotionSink& sink)
    : run_(std::make_unique<detail::Run>(opt, diags, sink)) {}
Interpreter::~Interpreter() = default;
void Interpreter::feed(const gcode::Program& piece, bool last) { run_->feed(piece, last); }
bool Interpreter::over() const { return run_->over(); }
Stats Interpreter::finish() {
  run_->end_of_file();
  return run_->stats();
}

}  // namespace deflex::interp
