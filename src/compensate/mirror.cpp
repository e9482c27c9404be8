// The mirror pass (compensate.hpp): the one-pass fixed point through the program.
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <thread>

#include "deflex/compensate/compensate.hpp"
#include "deflex/engage/path.hpp"
#include "deflex/interp/arc.hpp"
#include "internal.hpp"

namespace deflex::compensate {
using namespace detail;

namespace {

// The mirror method in one pass through the program. The stock a CL sample
// meets depends only on the path before it (causality), so the fixed point of
// Under G41/G42, the contour's point whose offset is `centre` on line m: the
// centre line is the contour's shifted by the radius to the tool's side.
interp::Vec3 contour_point(const interp::Motion& m, const interp::Vec3& centre) {
  const double dx = m.end_mm[0] - m.start_mm[0], dy = m.end_mm[1] - m.start_mm[1], len = std::hypot(dx, dy);
  const double nx = -m.comp * dy / len, ny = m.comp * dx / len;  // left of the travel for G41
  return {centre[0] - m.comp_radius_mm * nx, centre[1] - m.comp_radius_mm * ny, centre[2]};
}

// Under G41/G42, whether the point at parameter u of centre line m offsets a
// point of its programmed segment (0.01 mm inside it): where the control
// extends the line round an outside corner (Fanuc), or trims it at an
// inside one, a point put into the contour there would turn it back.
bool on_contour(const interp::Motion& m, double u) {
  const double dx = m.end_mm[0] - m.start_mm[0], dy = m.end_mm[1] - m.start_mm[1], len = std::hypot(dx, dy);
  const double ux = dx / len, uy = dy / len;
  const double at = (m.start_mm[0] + u * dx) * ux + (m.start_mm[1] + u * dy) * uy;
  const double from = m.contour_start_mm[0] * ux + m.contour_start_mm[1] * uy;
  const double to = m.contour_end_mm[0] * ux + m.contour_end_mm[1] * uy;
  return at > from + 0.01 && at < to - 0.01;
}

// Whether a point may go into line m under G41/G42 at parameter u of its
// part [u0, u1]: on its programmed segment, and both new parts at least
// sqrt(10 r max_step) long. The control meets the offset lines of the
// contour's parts; a kink phi between them (an offset change of up to
// max_step over a part of length L: phi <= 2 max_step / L) moves where they
// meet along the wall by about r phi, which must stay well inside the part
// (r phi <= L / 5), or the control's path would run back (a gouge alarm).
bool comp_split_ok(const interp::Motion& m, double u0, double u1, double u, double max_step_mm) {
  if (!on_contour(m, u)) return false;
  // The parts as the contour has them: the centre line runs on past the
  // programmed segment round a Fanuc outside corner.
  const double dx = m.end_mm[0] - m.start_mm[0], dy = m.end_mm[1] - m.start_mm[1], len = std::hypot(dx, dy);
  const double ux = dx / len, uy = dy / len;
  const double from = m.contour_start_mm[0] * ux + m.contour_start_mm[1] * uy;
  const double to = m.contour_end_mm[0] * ux + m.contour_end_mm[1] * uy;
  auto along = [&](double v) {  // the contour's point at centre parameter v, along the line
    const double a = (m.start_mm[0] + v * dx) * ux + (m.start_mm[1] + v * dy) * uy;
    return std::clamp(a, from, to);
  };
  const double min_len_mm = std::sqrt(10.0 * m.comp_radius_mm * max_step_mm);
  return along(u) - along(u0) >= min_len_mm && along(u1) - along(u) >= min_len_mm;
}

// The part [u0, u1] of motion m (parameters of the whole move); the whole
// move for [0, 1], by the same arithmetic (so that a point evaluated ahead of
// the whole move is the one its solve asks for).
interp::Motion part_of(const interp::Motion& m, double u0, double u1) {
  interp::Motion part = m;
  for (int c = 0; c < 3; ++c) {
    part.start_mm[c] = m.start_mm[c] + u0 * (m.end_mm[c] - m.start_mm[c]);
    if (u1 != 1.0) part.end_mm[c] = m.start_mm[c] + u1 * (m.end_mm[c] - m.start_mm[c]);
  }
  if (m.comp && u1 != 1.0) part.contour_end_mm = contour_point(m, part.end_mm);
  return part;
}

// Whether two motions are the same move, bit for bit where the probe reads it.
bool same_move(const interp::Motion& a, const interp::Motion& b) {
  return a.kind == b.kind && a.start_mm == b.start_mm && a.end_mm == b.end_mm && a.center_mm == b.center_mm &&
         a.feed_mm_per_min == b.feed_mm_per_min && a.line == b.line;
}

// P_comp = P_nom - gain e(P_comp) n over the whole program is reached by going
// through it once, in order: at each motion end, with every earlier motion
// already at its compensated position and cut into the stock, the offset along
// the surface normal is the root of h(s) = s + gain e(s) (e the surface error
// with the end moved by s n), found by secant steps, each step one engagement
// evaluation at the trial position (Simulator::probe, nothing is cut); then the
// motion is cut at its offset and the stream moves on. Re-simulating the whole
// program per mirror iteration would reach the same point, slower.
class Stream {
 public:
  Stream(const Physics& ph, const Settings& s, const DesignNormals& normals, const Progress& progress,
         std::size_t total, const PointSinks& sinks, std::unique_ptr<stock::ZMap> own)
      : ph_(ph), s_(s), normals_(normals), progress_(progress), total_(total), sinks_(sinks),
        run_(ph, s, {}, std::move(own)) {}

  // The next motions of the program into `r` (its motions, inserted, offsets,
  // feeds and lists for these motions; `motions` must not be r.motions): per
  // motion, the planned feed, whether it may move (movable()) and may be split.
  void go(const std::vector<interp::Motion>& motions, const std::vector<double>& feeds, const std::vector<bool>& can,
          const std::vector<bool>* splittable, Result& r) {
    r_ = &r;
    can_ = &can;
    split_ = splittable;
    r.converged = true;
    const std::size_t n = motions.size();
    for (std::size_t i = 0; i < n; ++i, ++done_) {
      // Run at the planned feed; written down at the programmed one (r.motions
      // are the motions as written, r.feeds_mm_per_min the plan).
      interp::Motion m = motions[i];
      programmed_feed_ = m.feed_mm_per_min;
      m.feed_mm_per_min = feed_ = feeds[i];
      splits_ = 0;
      const bool prepared = run_.prepare(m);
      if (prepared) ahead(motions, feeds, i);
      const std::size_t written = written_;
      if (!prepared) {
        emit(m, V3::Zero(), false, false, {}, false);
      } else if (m.kind == interp::MotionKind::rapid || !(*can_)[i]) {
        std::vector<Point> pts;
        if (m.kind != interp::MotionKind::rapid) pts = samples(m, prev_, V3::Zero(), 0);
        // A compensable move whose end cannot move: its points say why (the
        // run's [left_alone] accounting).
        if (m.fixed == interp::Fixed::no)
          for (Point& p : pts) p.fixed = interp::Fixed::held;
        emit(m, V3::Zero(), false, false, std::move(pts), true);
      } else if (m.corner || (m.comp && !m.moves_xy())) {
        // Under G41/G42, a piece the control adds at a corner, or a Z move
        // at one, has no point of its own in the program: the control puts it
        // where the corner's programmed point went, so it moves with the
        // motion before.
        emit(m, prev_, false, true, samples(m, prev_, prev_, 0), true);
      } else if (m.kind != interp::MotionKind::linear) {
        // Arcs move whole: their end takes the offset of their start. Where
        // the error along one then leaves the tolerance, it is linearised if
        // its block allows (compensate::splittable), else kept and reported.
        std::vector<Point> pts = samples(m, prev_, prev_, 0);
        double worst = 0;
        for (const Point& p : pts)
          if (!p.air && !p.plunge) worst = std::max(worst, std::fabs(landing_error(p, prev_)));
        if (worst <= s_.tolerance_mm) {
          emit(m, prev_, false, true, std::move(pts), true);
        } else if (split_ && (*split_)[i]) {
          linearise(m);
        } else {
          r_->nonuniform_arcs.push_back(m.line);
          emit(m, prev_, false, true, std::move(pts), true);
        }
      } else {
        const bool may_split = split_ && (*split_)[i];
        piece(m, 0.0, 1.0, may_split);
      }
      // What was evaluated ahead assumed this motion ran as written.
      if (written_ != written + 1 || !prev_.isZero()) drop_ahead();
      if (progress_ && (done_ % 4096 == 0))
        progress_("compensating", total_ ? static_cast<double>(done_) / static_cast<double>(total_) : 0.0);
    }
  }

  // After the last motions: the stock as cut, the counts of the whole run.
  void finish(Result& r) {
    run_.finish();
    r.iterations = max_updates_;
    r.evaluations = evaluations_;
  }

 private:
  // One CL sample of motion m moved by (a, b).
  Point probe(const interp::Motion& m, const V3& a, const V3& b, int k, const std::vector<engage::Point3>* v = nullptr) {
    if (const Point* p = ahead_point(m, a, b, k)) {
      ++evaluations_;
      return *p;
    }
    const interp::Motion mm = moved(m, a, b);
    std::vector<engage::Point3> own;
    if (!v) {
      own = engage::motion_vertices(mm, run_.sim().options().path);
      v = &own;
    }
    engage::CLSample cl;
    const engage::Metrics mt = run_.sim().probe(mm, *v, k == 0 ? static_cast<int>(v->size()) - 1 : k, cl, eng_);
    ++evaluations_;
    return point_of(cl, mt, eng_, run_.tool(), mm, m, done_, a, b, normals_, ph_.k, feed_limits(ph_, s_), ph_.workpiece,
                    rev_);
  }

  // The motion the mirror pass probes for motion i of the piece at no
  // offset: a plain cut's whole part (piece()), else the motion itself.
  interp::Motion probed(const interp::Motion& m, std::size_t i) const {
    const bool plain_cut = m.kind == interp::MotionKind::linear && (*can_)[i] && !m.corner &&
                           !(m.comp && !m.moves_xy());
    return plain_cut ? part_of(m, 0.0, 1.0) : m;
  }

  // Where the pass stands at no offset, the points of the motions ahead as
  // they run as written, evaluated at once (Simulator::probe_ahead) rather
  // than one probe at a time: every motion the pass leaves as written - most
  // of a program - then costs no sequential evaluation. A motion that moves
  // or splits drops what was evaluated past it (the stock changed), and the
  // window shrinks, growing again while the guesses hold.
  void ahead(const std::vector<interp::Motion>& motions, const std::vector<double>& feeds, std::size_t i) {
    if (!prev_.isZero() || (done_ >= ahead_first_ && done_ < ahead_first_ + ahead_.size())) return;
    // The last window held to its end: the next may be larger.
    if (!ahead_.empty() && done_ == ahead_first_ + ahead_.size()) window_ = std::min(kMaxWindow, 2 * window_);
    ahead_.clear();
    ahead_design_.clear();
    ahead_first_ = done_;
    std::vector<interp::Motion> run;
    for (std::size_t j = i; j < motions.size() && run.size() < window_; ++j) {
      interp::Motion m = motions[j];
      m.feed_mm_per_min = feeds[j];
      if (!run_.keeps(m)) break;
      ahead_design_.push_back(probed(m, j));
      run.push_back(moved(ahead_design_.back(), V3::Zero(), V3::Zero()));
      const std::size_t n = engage::motion_vertices(run.back(), run_.sim().options().path).size() - 1;
      ahead_.emplace_back(m.kind == interp::MotionKind::rapid ? 0 : n);
    }
    const FeedLimits limits = feed_limits(ph_, s_);
    const std::size_t covered = run_.sim().probe_ahead(
        run, [&](std::size_t j, int k, const engage::CLSample& cl, const engage::Metrics& mt,
                 const force::Engagement& eng) {
          thread_local std::vector<force::Vec3> rev;
          try {
            ahead_[j][static_cast<std::size_t>(k - 1)] = point_of(cl, mt, eng, run_.tool(), run[j], ahead_design_[j],
                                                                  done_ + j, V3::Zero(), V3::Zero(), normals_, ph_.k,
                                                                  limits, ph_.workpiece, rev);
          } catch (...) {  // probe() reports it in order when the pass gets there
          }
        });
    ahead_.resize(covered);
    ahead_design_.resize(covered);
  }

  // Motion done_ did not run as written: the points evaluated past it are
  // stale, and where there were some the window shrinks.
  void drop_ahead() {
    if (done_ + 1 < ahead_first_ + ahead_.size()) window_ = std::max<std::size_t>(1, window_ / 4);
    ahead_.clear();
    ahead_design_.clear();
  }

  // The point evaluated ahead for sample k (0: the last) of m at no offset, if
  // m is the move evaluated for the current motion.
  const Point* ahead_point(const interp::Motion& m, const V3& a, const V3& b, int k) const {
    if (!a.isZero() || !b.isZero() || done_ < ahead_first_ || done_ >= ahead_first_ + ahead_.size()) return nullptr;
    const std::size_t j = done_ - ahead_first_;
    if (!same_move(m, ahead_design_[j])) return nullptr;
    const std::vector<std::optional<Point>>& pts = ahead_[j];
    const std::size_t kk = k == 0 ? pts.size() : static_cast<std::size_t>(k);
    return kk >= 1 && kk <= pts.size() && pts[kk - 1] ? &*pts[kk - 1] : nullptr;
  }

  // Samples 1..count of motion m moved by (a, b), but the one at `skip` (0: none).
  std::vector<Point> samples(const interp::Motion& m, const V3& a, const V3& b, int skip) {
    const interp::Motion mm = moved(m, a, b);
    const std::vector<engage::Point3> v = engage::motion_vertices(mm, run_.sim().options().path);
    std::vector<Point> pts;
    const int n = static_cast<int>(v.size()) - 1;
    for (int k = 1; k <= n; ++k)
      if (k != skip) pts.push_back(probe(m, a, b, k, &v));
    return pts;
  }

  // Appends a motion as written, with its offset and samples, and cuts it.
  void emit(const interp::Motion& m, const V3& off, bool inserted, bool can, std::vector<Point> pts, bool cut) {
    const auto index = static_cast<std::uint32_t>(written_++);
    if (cut) run_.sim().run(moved(m, prev_, off));
    r_->motions.push_back(m);
    r_->motions.back().feed_mm_per_min = programmed_feed_;
    r_->inserted.push_back(inserted);
    r_->offsets.push_back(off);
    r_->feeds_mm_per_min.push_back(feed_);
    if (can && capped_) r_->capped_lines.push_back(m.line);
    capped_ = false;
    for (Point& p : pts) {
      p.motion = index;
      if (sinks_.final) {
        const double u = p.count ? static_cast<double>(p.index) / p.count : 1.0;
        sinks_.final(p, V3(prev_ + u * (off - prev_)), done_);
      }
    }
    prev_ = off;
  }

  // An arc as chords whose sagitta is within Settings::chord_tol_mm, each end
  // compensated like a line's; the arc block keeps the last chord's piece of
  // the arc, moved whole with the last chord end (its centre words re-aimed by
  // the writer).
  void linearise(const interp::Motion& m) {
    const interp::Arc a = interp::arc_of(m);
    const int chords = std::max(2, interp::arc_chord_count(a, s_.chord_tol_mm));
    const std::vector<engage::Point3> v = interp::arc_polyline(a, chords);
    for (int c = 1; c < chords; ++c) {
      interp::Motion chord = m;
      chord.kind = interp::MotionKind::linear;
      chord.start_mm = v[static_cast<std::size_t>(c - 1)];
      chord.end_mm = v[static_cast<std::size_t>(c)];
      piece(chord, 0.0, 1.0, false, true);
    }
    interp::Motion rest = m;
    rest.start_mm = v[static_cast<std::size_t>(chords - 1)];
    std::vector<Point> pts = samples(rest, prev_, prev_, 0);
    emit(rest, prev_, false, true, std::move(pts), true);
    ++r_->linearised_arcs;
    r_->split_points += static_cast<std::size_t>(chords - 1);
  }

  // The largest |offset| along a normal: max_offset_mm less what rounding the
  // written coordinates may add (half their last decimal on sqrt(3) axes).
  double cap_mm(const interp::Motion& m) const {
    const double rounding = m.inch ? s_.rounding_inch_mm : s_.rounding_mm;
    return std::max(0.0, s_.max_offset_mm - std::sqrt(3.0) * rounding);
  }

  // How far a vertex at sample p could move its landing error from what the
  // ramp `ramp` gives it: the offset along p's normal that zeroes the error,
  // held to the cap. A split where this is small changes nothing: the ramp is
  // not the cause, the offset is at its cap already. (The step limit is left
  // out: where it holds a vertex back, the vertices before it, which the
  // split brings, let the ramp start earlier.)
  double split_reach_mm(const interp::Motion& m, const Point& p, const V3& ramp) const {
    const double r = ramp.dot(p.normal), cap = cap_mm(m);
    return std::fabs(std::clamp(r - landing_error(p, ramp), -cap, cap) - r);
  }

  // The part [u0, u1] of linear motion m (parameters of the whole move), its
  // start at the current offset prev_. Its end offset is solved; where the
  // samples between land outside the tolerance under the straight ramp of the
  // offsets and the move may be split, a vertex goes in at the worst sample a
  // vertex could bring at least half a tolerance closer, and the part before
  // it is done first (at most max_splits_per_move per move).
  void piece(const interp::Motion& m, double u0, double u1, bool may_split, bool inserted = false) {
    const bool last = u1 == 1.0 && !inserted;
    for (;;) {
      const interp::Motion part = part_of(m, u0, u1);
      Point end;
      const V3 off = solve(part, end);
      std::vector<Point> pts = samples(part, prev_, off, end.count);
      double worst = s_.tolerance_mm, at = -1;
      if (may_split && splits_ < s_.max_splits_per_move)
        for (const Point& p : pts) {
          if (p.air || p.plunge) continue;
          const double u = static_cast<double>(p.index) / p.count;
          if (m.comp && !comp_split_ok(m, u0, u1, u0 + u * (u1 - u0), s_.max_step_mm)) continue;
          const V3 ramp = prev_ + u * (off - prev_);
          const double res = std::fabs(landing_error(p, ramp));
          if (res > worst && split_reach_mm(m, p, ramp) >= 0.5 * s_.tolerance_mm) {
            worst = res;
            at = u0 + u * (u1 - u0);
          }
        }
      if (at < 0) {
        pts.push_back(end);
        emit(part, off, !last, true, std::move(pts), true);
        return;
      }
      ++splits_;
      ++r_->split_points;
      piece(m, u0, at, may_split, true);
      u0 = at;
    }
  }

  // The end offset of a cutting move from the current offset prev_: zero when
  // the error there, as programmed, is inside the tolerance; else the mirror
  // fixed point, capped at max_offset_mm, its change from prev_ bounded by
  // max_step_mm. `end` receives the end sample at the returned offset.
  V3 solve(const interp::Motion& m, Point& end) {
    Point p0 = probe(m, prev_, V3::Zero(), 0);
    V3 off = V3::Zero();
    Point at = p0;  // the sample at `off`
    // A normal the program's points do not determine moves nothing.
    if (!p0.air && !p0.plunge && p0.normal_source != NormalSource::undetermined &&
        std::fabs(p0.error_mm) > s_.tolerance_mm) {
      const V3 n = p0.normal;
      const double g = s_.gain, cap = cap_mm(m);
      // Root of h(s) = s + g e(s) by secant steps from s0 = 0 and a first step
      // that uses the slope de/ds of the previous point (neighbours cut alike).
      // The force model is piecewise smooth (a slice entering the cut adds its
      // edge at once), so h can jump across its root: once a sign change is
      // bracketed, steps stay inside the bracket (bisection when the secant
      // leaves it) and a bracket narrower than 1% of the tolerance is the fixed
      // point as well as the model defines one. The trial with the smallest
      // |h| is the one kept.
      const double tol = 0.01 * s_.tolerance_mm;
      double s0 = 0, h0 = g * p0.error_mm;
      double lo = 0, hi = 0;  // s where h < 0 and h > 0 (valid when the flags say so)
      bool have_lo = h0 < 0, have_hi = h0 > 0;
      double s1 = -g * p0.error_mm / (1 + g * slope_);
      double best = std::numeric_limits<double>::infinity();  // |h| of the trial kept
      bool done = false;
      int updates = 0;
      for (int it = 0; it < s_.max_iterations && !done; ++it) {
        if (std::fabs(s1) >= cap) {
          s1 = std::copysign(cap, s1);
          capped_ = true;
          done = true;  // at the cap: nothing further to find
        }
        const Point p1 = probe(m, prev_, s1 * n, 0);
        ++updates;
        // Flank: the mid-range of e(z) along p1.normal, which is n (the same design tip).
        const double e1 = p1.flank ? p1.error_mm : (p1.delta_mm - p1.workpiece_delta_mm).dot(n), h1 = s1 + g * e1;
        if (s1 != s0) slope_ = std::clamp((e1 - (h0 - s0) / g) / (s1 - s0), -0.8, 0.8);
        if (std::fabs(h1) < best) {
          best = std::fabs(h1);
          off = s1 * n;
          at = p1;
        }
        if (h1 < 0 && (!have_lo || s1 > lo)) lo = s1, have_lo = true;
        if (h1 > 0 && (!have_hi || s1 < hi)) hi = s1, have_hi = true;
        const bool bracket = have_lo && have_hi;
        if (std::fabs(h1) <= tol || (bracket && std::fabs(hi - lo) <= tol)) done = true;
        if (done) break;
        const double d = h1 - h0;
        double s2 = std::fabs(d) > 1e-15 ? s1 - h1 * (s1 - s0) / d : s1 - h1;
        if (!std::isfinite(s2) || std::fabs(s2 - s1) > 4 * std::fabs(h1)) s2 = s1 - h1;  // plain mirror step
        if (bracket && !(s2 > std::min(lo, hi) && s2 < std::max(lo, hi))) s2 = 0.5 * (lo + hi);
        s0 = s1;
        h0 = h1;
        s1 = s2;
      }
      if (!done) {
        ++r_->unconverged_points;
        r_->converged = false;
        r_->last_change_mm = std::max(r_->last_change_mm, best);
      }
      max_updates_ = std::max(max_updates_, updates);
    }
    // No jerk: the offset moves at most max_step_mm from the point before.
    const V3 d = off - prev_;
    if (d.norm() > s_.max_step_mm) {
      off = prev_ + d * (s_.max_step_mm / d.norm());
      at = probe(m, prev_, off, 0);
    }
    end = at;
    return off;
  }

  const Physics& ph_;
  const Settings& s_;
  const DesignNormals& normals_;
  const Progress& progress_;
  std::size_t total_;            // the program's motions (progress), 0: unknown
  const PointSinks& sinks_;
  Result* r_ = nullptr;          // the piece being written
  const std::vector<bool>* can_ = nullptr;
  const std::vector<bool>* split_ = nullptr;
  std::size_t done_ = 0;         // motions of the program gone through
  std::size_t written_ = 0;      // motions written (inserted ones too): Point::motion
  Run run_;
  force::Engagement eng_;
  std::vector<force::Vec3> rev_;
  V3 prev_ = V3::Zero();       // offset of the last motion written
  double feed_ = 0;            // planned feed of the motion being written, mm/min
  double programmed_feed_ = 0; // its programmed feed, mm/min
  double slope_ = 0;           // de/ds at the last solved point
  bool capped_ = false;
  int splits_ = 0;
  int max_updates_ = 0;
  std::size_t evaluations_ = 0;
  // The points evaluated ahead: ahead_[j] samples 1..n of motion
  // ahead_first_ + j as run as written (ahead_design_[j] the move), empty
  // where the evaluation failed; window_ motions are evaluated at once.
  static constexpr std::size_t kMaxWindow = 64;
  std::size_t ahead_first_ = 0;
  std::vector<std::vector<std::optional<Point>>> ahead_;
  std::vector<interp::Motion> ahead_design_;
  std::size_t window_ = kMaxWindow;
};

}  // namespace

struct Compensation::Impl {
  Impl(const Physics& p, const Settings& st, const DesignNormals& n, PointSinks sk, Progress pr, std::size_t t,
       bool as_written)
      : ph(p), s(st), one(st), normals(n), sinks(std::move(sk)), progress(std::move(pr)), total(t) {
    same = s.gain == 0.0;
    if (!as_written) {  // the caller simulated the program as written already
      if (same) throw Error(ErrorKind::internal, "compensate: gain 0 without the program as written");
      std::unique_ptr<stock::ZMap> map;
      if (ph.consumable_stock && ph.consumable_stock == ph.stock)
        map = std::make_unique<stock::ZMap>(std::move(*ph.consumable_stock));
      stream = std::make_unique<Stream>(ph, s, normals, progress, total, sinks, std::move(map));
      return;
    }
    // The program as written is simulated for the report beside the stream,
    // on its own thread, unless the feed limit needs its forces first (or one
    // thread was asked for).
    threaded = !(s.feed_limit_N > 0 || same || s.threads == 1);
    // One thread of its own: TBB's workers are left to the pass, whose wall
    // time is the run's.
    if (threaded) one.threads = 1;
    // With a consumable stock the as-written simulation cuts a copy made
    // here, before the mirror pass takes the caller's map over.
    const bool take = ph.consumable_stock && ph.consumable_stock == ph.stock && !same;
    std::unique_ptr<stock::ZMap> nominal_map = take ? std::make_unique<stock::ZMap>(clone(*ph.stock)) : nullptr;
    nominal = std::make_unique<Simulation>(ph, one, normals, [this](const Point& p) { nominal_point(p); },
                                           std::move(nominal_map), same ? progress : Progress(), total);
    if (!same) {
      std::unique_ptr<stock::ZMap> mirror_map =
          take ? std::make_unique<stock::ZMap>(std::move(*ph.consumable_stock)) : nullptr;
      stream = std::make_unique<Stream>(ph, s, normals, progress, total, sinks, std::move(mirror_map));
    }
  }

  // The as-written points go to the nominal sink; the feed limit needs their
  // least feed share per motion, and with gain 0 and no feed limit they are the
  // final points as well (the same program).
  void nominal_point(const Point& p) {
    if (!share.empty()) share.at(p.motion) = std::min(share.at(p.motion), p.feed_share);
    if (sinks.nominal) sinks.nominal(p);
    if (same && s.feed_limit_N <= 0 && sinks.final) sinks.final(p, V3::Zero(), p.motion);
  }

  Result add(const std::vector<interp::Motion>& motions, const std::vector<bool>& can,
             const std::vector<bool>* splittable, const std::vector<double>* planned) {
    const std::size_t n = motions.size();
    if (!nominal) return add_planned(motions, can, splittable, planned);
    if (s.feed_limit_N > 0 && pieces++)
      throw Error(ErrorKind::internal, "compensate: the feed limit takes the program in one piece");
    Result r;
    r.motions = motions;
    r.inserted.assign(n, false);
    r.offsets.assign(n, V3::Zero());
    r.feeds_mm_per_min.resize(n);
    for (std::size_t i = 0; i < n; ++i) r.feeds_mm_per_min[i] = motions[i].feed_mm_per_min;
    std::vector<double> feeds = r.feeds_mm_per_min;
    if (s.feed_limit_N > 0) share.assign(n, 1.0);
    std::exception_ptr failed;
    std::thread t;
    if (threaded) {
      t = std::thread([&] {
        try {
          nominal->add(motions);
        } catch (...) {
          failed = std::current_exception();
        }
      });
    } else {
      nominal->add(motions);
      if (s.feed_limit_N > 0) nominal->finish();  // every share before the feeds
    }
    struct Join {
      std::thread& t;
      ~Join() {
        if (t.joinable()) t.join();
      }
    } join{t};
    if (s.feed_limit_N > 0) lower_feeds(motions, feeds, r);
    r.feeds_mm_per_min = feeds;
    if (same) {
      final_at_planned_feeds(motions, feeds, r);
      r.converged = true;
    } else {
      // The stream writes the motions down anew (with those it inserts).
      r.motions.clear();
      r.inserted.clear();
      r.offsets.clear();
      r.feeds_mm_per_min.clear();
      stream->go(motions, feeds, can, splittable, r);
    }
    if (t.joinable()) t.join();
    if (failed) std::rethrow_exception(failed);
    for (const V3& o : r.offsets)
      if (o.norm() > 0) ++r.compensated_points;
    merge(r);
    return r;
  }

  // The mirror pass alone, at the feeds planned by the caller (null: as programmed).
  Result add_planned(const std::vector<interp::Motion>& motions, const std::vector<bool>& can,
                     const std::vector<bool>* splittable, const std::vector<double>* planned) {
    Result r;
    std::vector<double> feeds(motions.size());
    for (std::size_t i = 0; i < motions.size(); ++i)
      feeds[i] = planned ? (*planned)[i] : motions[i].feed_mm_per_min;
    stream->go(motions, feeds, can, splittable, r);
    for (const V3& o : r.offsets)
      if (o.norm() > 0) ++r.compensated_points;
    merge(r);
    return r;
  }

  // --feed-limit: the blocks whose peak force, torque or power would exceed
  // the limits run at lowered_feed().
  void lower_feeds(const std::vector<interp::Motion>& motions, std::vector<double>& feeds, Result& r) const {
    for (std::size_t i = 0; i < motions.size(); ++i) {
      const interp::Motion& m = motions[i];
      if (!m.plain || m.kind == interp::MotionKind::rapid || share[i] >= 1) continue;
      feeds[i] = lowered_feed(m.feed_mm_per_min, share[i]);
      r.feed_lowered_lines.push_back(m.line);
    }
  }

  // Gain 0: nothing moves, the final points are those of the program as run
  // (at the lowered feeds where the feed limit lowered them). Without a feed
  // limit nominal_point passed them on; with one they are simulated again (the
  // nominal points were handed over before the feeds were known).
  void final_at_planned_feeds(const std::vector<interp::Motion>& motions, const std::vector<double>& feeds,
                              const Result& r) {
    if (!sinks.final || s.feed_limit_N <= 0) return;
    std::vector<interp::Motion> planned;  // the program at the planned feeds
    if (!r.feed_lowered_lines.empty()) {
      planned = motions;
      for (std::size_t i = 0; i < planned.size(); ++i) planned[i].feed_mm_per_min = feeds[i];
    }
    simulate(planned.empty() ? motions : planned, {}, ph, s, [&](const Point& p) { sinks.final(p, V3::Zero(), p.motion); },
             progress, &normals);
  }

  // The totals of the run so far.
  void merge(const Result& r) {
    auto append = [](std::vector<std::uint32_t>& to, const std::vector<std::uint32_t>& from) {
      to.insert(to.end(), from.begin(), from.end());
    };
    append(totals.capped_lines, r.capped_lines);
    append(totals.nonuniform_arcs, r.nonuniform_arcs);
    append(totals.feed_lowered_lines, r.feed_lowered_lines);
    totals.linearised_arcs += r.linearised_arcs;
    totals.split_points += r.split_points;
    totals.compensated_points += r.compensated_points;
    totals.unconverged_points += r.unconverged_points;
    totals.last_change_mm = std::max(totals.last_change_mm, r.last_change_mm);
    totals.converged = totals.converged && r.converged;
  }

  Result finish() {
    if (nominal) nominal->finish();
    if (stream) stream->finish(totals);
    return totals;
  }

  const Physics& ph;
  const Settings& s;
  Settings one;  // the as-written simulation's
  const DesignNormals& normals;
  PointSinks sinks;
  Progress progress;
  std::size_t total;
  bool same = false, threaded = false;
  std::size_t pieces = 0;
  std::vector<double> share;  // --feed-limit: the least Point::feed_share per motion
  std::unique_ptr<Simulation> nominal;
  std::unique_ptr<Stream> stream;
  Result totals = [] {
    Result r;
    r.converged = true;
    return r;
  }();
};

Compensation::Compensation(const Physics& ph, const Settings& s, const DesignNormals& normals, PointSinks sinks,
                           Progress progress, std::size_t total, bool as_written)
    : impl_(std::make_unique<Impl>(ph, s, normals, std::move(sinks), std::move(progress), total, as_written)) {}
Compensation::~Compensation() = default;
Result Compensation::add(const std::vector<interp::Motion>& motions, const std::vector<bool>& can,
                         const std::vector<bool>* splittable, const std::vector<double>* planned_feeds) {
  return impl_->add(motions, can, splittable, planned_feeds);
}
Result Compensation::finish() { return impl_->finish(); }

Result compensate(const std::vector<interp::Motion>& motions, const Physics& ph, const Settings& s,
                  const Progress& progress, const std::vector<bool>* splittable, const PointSinks* sinks) {
  const std::unique_ptr<DesignNormals> normals = design_normals(motions, ph, s);
  // Without sinks of the caller's the points are kept in the result.
  std::vector<Point> nominal, final;
  PointSinks kept;
  if (!sinks) {
    nominal.reserve(motions.size() * 2);
    kept.nominal = [&nominal](const Point& p) { nominal.push_back(p); };
    kept.final = [&final](const Point& p, const V3&, std::size_t) { final.push_back(p); };
  }
  Compensation c(ph, s, *normals, sinks ? *sinks : kept, progress, motions.size());
  Result piece = c.add(motions, movable(motions), splittable);
  Result r = c.finish();
  r.motions = std::move(piece.motions);
  r.inserted = std::move(piece.inserted);
  r.offsets = std::move(piece.offsets);
  r.feeds_mm_per_min = std::move(piece.feeds_mm_per_min);
  r.nominal = std::move(nominal);
  r.final = std::move(final);
  return r;
}

}  // namespace deflex::compensate
