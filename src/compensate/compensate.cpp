#include "deflex/compensate/compensate.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <numbers>
#include <thread>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/engage/engagement.hpp"
#include "deflex/engage/path.hpp"
#include "deflex/engage/simulator.hpp"
#include "deflex/force/cutter.hpp"
#include "deflex/force/mechanistic.hpp"
#include "deflex/force/tool.hpp"
#include "deflex/stiffness/beam.hpp"

namespace deflex::compensate {
namespace {

// A copy of a Z-map through its public tile interface (a simulation cuts its
// own copy of the initial stock).
stock::ZMap clone(const stock::ZMap& z) {
  stock::ZMap c(z.grid(), stock::no_material, z.base_z_mm());
  const int T = stock::ZMap::tile_cells;
  std::vector<float> cells(static_cast<std::size_t>(T) * T);
  for (std::size_t ty = 0; ty < z.tiles_y(); ++ty)
    for (std::size_t tx = 0; tx < z.tiles_x(); ++tx) {
      for (int j = 0; j < T; ++j)
        for (int i = 0; i < T; ++i) {
          const int gi = static_cast<int>(tx) * T + i, gj = static_cast<int>(ty) * T + j;
          cells[static_cast<std::size_t>(j) * T + i] = z.inside(gi, gj) ? z.at(gi, gj) : stock::no_material;
        }
      c.assign_tile(tx, ty, cells.data());
    }
  return c;
}

// Everything about one tool that the simulation needs, built once.
struct ToolModel {
  stiffness::Tool tool;
  force::CutterSlices slices;
  stiffness::ComplianceTable compliance;
  force::AngleGrid grid;
  // Flat and bull-nose ends (flank cuts): C(z, z') between the slices of the
  // tool chain alone (axisymmetric: the same in any frame turned about Z), and
  // the machine structure's constant 3x3 in series, machine axes, added per
  // point in the feed frame.
  force::SliceCompliance flank_c;
  stiffness::Compliance structure = stiffness::Compliance::Zero();
};

const ToolModel& model_for(std::map<std::string, ToolModel>& cache, const std::string& id, const Physics& ph,
                           const Settings& s) {
  auto it = cache.find(id);
  if (it != cache.end()) return it->second;
  ToolModel m;
  m.tool = stiffness::find_tool(ph.tools, id);
  const force::Cutter c = force::cutter_of(m.tool);
  m.slices = force::make_slices(c, s.slice_mm, m.tool.flute_length_mm);
  m.compliance = stiffness::beam_compliance(m.tool, ph.machine, ph.tool_only);
  if (m.tool.type != stiffness::ToolType::ball) {
    // 150 slices (30 mm of flute at 0.2 mm): 22500 interpolations, a few ms.
    const stiffness::CrossComplianceTable full = stiffness::beam_cross_compliance(m.tool, ph.machine, ph.tool_only);
    const stiffness::CrossComplianceTable chain(full.heights_mm(), full.lateral_mm_per_N(), full.axial_mm_per_N());
    const double h0 = full.heights_mm().front();
    m.structure = full.at(h0, h0) - chain.at(h0, h0);
    m.flank_c = force::slice_compliance(
        m.slices, [&chain](double z, double zp) -> force::Mat3 { return chain.at(z, zp); });
  }
  // Steps a multiple of the flute count: the force model then computes one
  // tooth pitch and repeats it.
  int steps = std::max(s.force_steps / c.flutes, 4) * c.flutes;
  m.grid = force::make_angle_grid(steps);
  return cache.emplace(id, std::move(m)).first->second;
}


// The per-point physics of one CL sample: forces, deflection, surface error.
// Shared by simulate() and the mirror stream, so both report the same numbers.
// m: the motion as run; design: as programmed (the surface normal's).
// a, b: the offsets of the run motion's start and end from the design's, so
// that the design tip of the sample (the surface normal's) is known.
Point point_of(const engage::CLSample& cl, const engage::Metrics& mt, const force::Engagement& eng, const ToolModel& tm,
               const interp::Motion& m, const interp::Motion& design, const V3& a, const V3& b,
               const DesignNormals& normals, const force::Coefficients& k, std::vector<force::Vec3>& rev,
               bool keep_profile = false) {
  Point p;
  p.line = cl.line;
  p.index = cl.index;
  p.count = cl.count;
  p.tip_mm = V3(cl.point.tip_mm[0], cl.point.tip_mm[1], cl.point.tip_mm[2]);
  p.ap_mm = mt.ap_mm;
  p.ae_mm = mt.ae_mm;
  p.cwe_area_mm2 = mt.cwe_area_mm2;
  p.d_eff_mm = mt.d_eff_mm;
  // The engager's MRR is at the feed its Process was made with (the tool's first
  // cut); the motion's own F gives this point's.
  p.mrr_mm3_per_s = mt.section_mm2 * m.feed_mm_per_min / 60;
  p.air = mt.air_cut || eng.empty();
  p.plunge = mt.plunge;
  const double u = cl.count ? static_cast<double>(cl.index) / cl.count : 1.0;
  const SurfaceNormal sn = normals.at(cl, mt, tm.tool, design, p.tip_mm - (a + u * (b - a)));
  p.normal = sn.n;
  p.normal_source = sn.source;
  p.part_gap_mm = sn.part_gap_mm;
  if (p.air || p.plunge) return p;
  const int flutes = tm.slices.cutter.flutes;
  const double rpm = m.spindle_rpm > 0 ? m.spindle_rpm : 0.0;
  if (rpm <= 0) throw Error(Exit::input, "line " + std::to_string(m.line) + ": cutting with no spindle speed (S) set");
  const double fz = m.feed_mm_per_min / (rpm * flutes);
  rev.resize(static_cast<std::size_t>(tm.grid.steps));
  force::revolution_forces(tm.slices, tm.grid, k, fz, eng, rev);
  force::Vec3 f = force::summarize(rev).mean_N;
  for (const force::Vec3& fj : rev) p.peak_N = std::max(p.peak_N, fj.norm());
  // Feed frame X' = feed, Y' = Z x X' -> machine axes.
  const double fx = cl.point.feed_x, fy = cl.point.feed_y;
  p.force_N = V3(f.x() * fx - f.y() * fy, f.x() * fy + f.y() * fx, f.z());
  // Height of the resultant: centre of the engaged edge length along the flutes.
  double wz = 0, w = 0;
  for (std::size_t i = 0; i < eng.slices.size(); ++i) {
    double ang = 0;
    for (const auto& iv : eng.slices[i]) ang += iv.end - iv.start;
    const double wi = ang * tm.slices.slices[i].width_mm;
    wz += wi * tm.slices.slices[i].z_mm;
    w += wi;
  }
  p.height_mm = w > 0 ? wz / w : 0.0;
  p.delta_mm = tm.compliance.at(p.height_mm) * p.force_N;
  p.error_mm = p.delta_mm.dot(p.normal);
  if (tm.flank_c.n && flank_cut(mt, tm.tool)) {
    // The wall profile e(z) (force/flank.hpp), all in the feed frame: the
    // design normal and the structure's compliance turned into it.
    const V3 xf(fx, fy, 0.0), yf(-fy, fx, 0.0);
    force::Mat3 R;
    R.col(0) = xf;
    R.col(1) = yf;
    R.col(2) = V3::UnitZ();
    const V3 nf = R.transpose() * p.normal;
    const force::Mat3 sf = R.transpose() * tm.structure * R;
    const force::MillingMode mode = mt.up_share <= 0.5 ? force::MillingMode::down : force::MillingMode::up;
    thread_local force::GeneratingLoads loads;
    thread_local force::FlankProfile prof;
    const force::FlankInput in{tm.slices, k, fz, eng, force::generating_phi(mode), nf};
    force::flank_error_profile(in, tm.flank_c, loads, prof);
    if (!prof.points.empty()) {
      // The structure translates the whole tool: S times the force of every
      // slice at the instant z is generated.
      for (std::size_t i = 0; i < loads.size(); ++i) {
        force::Vec3 sum = force::Vec3::Zero();
        for (std::size_t j = 0; j < loads.size(); ++j) sum += loads.at(i, j);
        prof.points[i].error_mm += nf.dot(sf * sum);
      }
      force::summarize_profile(nf, prof);
      p.flank = true;
      p.flank_min_mm = prof.min_mm;
      p.flank_max_mm = prof.max_mm;
      p.flank_z_min_mm = prof.z_of_min_mm;
      p.flank_z_max_mm = prof.z_of_max_mm;
      p.error_mm = prof.mid_offset_mm;
      if (keep_profile) p.flank_profile = prof.points;
    }
  }
  return p;
}

// The stock and the tool's simulator along one run through the program.
class Run {
 public:
  // `own` (may be null): the map to cut, else a copy of the physics' stock.
  Run(const Physics& ph, const Settings& s, engage::PointSink sink = {}, std::unique_ptr<stock::ZMap> own = nullptr)
      : ph_(ph), s_(s), sink_(std::move(sink)), z_(std::move(own)) {
    if (!ph.stock) throw Error(Exit::usage, "no stock: give --stock box:X0,Y0,Z0,X1,Y1,Z1 or a solid file");
    if (!z_) z_ = std::make_unique<stock::ZMap>(clone(*ph.stock));
    so_.path.cl_spacing_mm = s.cl_spacing_mm;
    so_.threads = s.threads;
  }
  // Before motion m: false for a rapid before the first cut (not run); a cut
  // with another tool finishes the old simulator and starts the tool's own.
  bool prepare(const interp::Motion& m) {
    if (m.kind == interp::MotionKind::rapid && !sim_) return false;
    const std::string id = tool_id(m, s_);
    if (m.kind != interp::MotionKind::rapid && id != id_) {
      if (sim_) sim_->finish();
      if (m.tool == 0 && s_.tool_override.empty())
        throw Error(Exit::input, "line " + std::to_string(m.line) + ": cutting with no tool (T.. M6) selected; give --tool");
      tm_ = &model_for(models_, id, ph_, s_);
      engage::Process proc;
      proc.spindle_rpm = m.spindle_rpm > 0 ? m.spindle_rpm : 1.0;
      proc.fz_mm = m.feed_mm_per_min / (proc.spindle_rpm * tm_->slices.cutter.flutes);
      sim_ = std::make_unique<engage::Simulator>(*z_, tm_->slices, proc, so_, sink_);
      id_ = id;
      ++tool_changes_;
    }
    return true;
  }
  engage::Simulator& sim() { return *sim_; }
  const stock::ZMap& zmap() const { return *z_; }
  const ToolModel& tool() const { return *tm_; }
  std::size_t tool_changes() const { return tool_changes_; }
  void finish() {
    if (sim_) sim_->finish();
  }

 private:
  const Physics& ph_;
  const Settings& s_;
  engage::PointSink sink_;
  std::unique_ptr<stock::ZMap> z_;
  engage::SimOptions so_;
  std::map<std::string, ToolModel> models_;
  const ToolModel* tm_ = nullptr;
  std::string id_;
  std::unique_ptr<engage::Simulator> sim_;
  std::size_t tool_changes_ = 0;
};

// Point::stock_depth_mm: the highest stock over the leading half of the disc of
// radius r around the tip (centre, rings at r/2 and 0.95 r, every 22.5 deg
// from -90 to +90 deg about the feed direction) above the tip.
double stock_depth(const stock::ZMap& z, const engage::CLSample& cl, double r) {
  const auto& t = cl.point.tip_mm;
  const double fx = cl.point.feed_x, fy = cl.point.feed_y;
  double top = -std::numeric_limits<double>::infinity();
  for (double rr : {0.0, 0.5 * r, 0.95 * r})
    for (int k = -4; k <= 4; ++k) {
      const double a = k * std::numbers::pi / 8, c = std::cos(a), sn = std::sin(a);
      top = std::max(top, static_cast<double>(z.height_at(t[0] + rr * (fx * c - fy * sn), t[1] + rr * (fy * c + fx * sn))));
      if (rr == 0) break;
    }
  return top > t[2] ? top - t[2] : 0.0;
}

// Motion m with its start moved by a and its end (and an arc's centre) by b.
interp::Motion moved(interp::Motion m, const V3& a, const V3& b) {
  for (int c = 0; c < 3; ++c) {
    m.start_mm[c] += a[c];
    m.end_mm[c] += b[c];
    m.center_mm[c] += b[c];
  }
  return m;
}

}  // namespace

std::string tool_id(const interp::Motion& m, const Settings& s) {
  return !s.tool_override.empty() ? s.tool_override : "T" + std::to_string(m.tool);
}

std::unique_ptr<DesignNormals> design_normals(const std::vector<interp::Motion>& motions, const Physics& ph,
                                              const Settings& s) {
  engage::PathOptions po;
  po.cl_spacing_mm = s.cl_spacing_mm;
  return std::make_unique<DesignNormals>(motions, ph.part, ph.tools, po, s.part_reach_mm,
                                         [&s](const interp::Motion& m) { return tool_id(m, s); });
}

std::vector<Point> simulate(const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets,
                            const Physics& ph, const Settings& s, const Progress& progress,
                            const DesignNormals* normals) {
  std::vector<Point> out;
  out.reserve(motions.size() * 2);
  simulate(motions, offsets, ph, s, [&out](const Point& p) { out.push_back(p); }, progress, normals);
  return out;
}

namespace {
// simulate() on `map` (null: a copy of the physics' stock).
void simulate_on(std::unique_ptr<stock::ZMap> map, const std::vector<interp::Motion>& motions,
                 const std::vector<V3>& offsets, const Physics& ph, const Settings& s, const PointSink& out,
                 const Progress& progress, const DesignNormals* normals) {
  std::unique_ptr<DesignNormals> own;
  if (!normals) {
    own = design_normals(motions, ph, s);
    normals = own.get();
  }
  std::vector<force::Vec3> rev;
  // CLSample::motion counts the motions one Simulator has run; ran[] maps it
  // back to the index in `motions` (rapids before the first cut are not run,
  // and a tool change starts a new Simulator).
  std::vector<std::size_t> ran;
  const ToolModel* tm = nullptr;
  const stock::ZMap* zmap = nullptr;
  auto sink = [&](const engage::CLSample& cl, const engage::Metrics& mt, const force::Engagement& eng) {
    if (cl.rapid) return;
    const std::size_t gi = ran.at(cl.motion);
    const interp::Motion& design = motions[gi];
    const V3 a = gi && !offsets.empty() ? offsets[gi - 1] : V3(V3::Zero());
    const V3 b = offsets.empty() ? V3(V3::Zero()) : offsets[gi];
    Point p = point_of(cl, mt, eng, *tm, design, design, a, b, *normals, ph.k, rev, s.flank_profiles);
    p.motion = static_cast<std::uint32_t>(gi);
    if (zmap) p.stock_depth_mm = stock_depth(*zmap, cl, 0.5 * tm->tool.diameter_mm);
    out(p);
  };
  Run run(ph, s, sink, std::move(map));
  zmap = &run.zmap();
  auto offset = [&](std::size_t i) { return offsets.empty() ? V3(V3::Zero()) : offsets[i]; };
  const std::size_t n = motions.size();
  std::size_t changes = 0;
  for (std::size_t i = 0; i < n; ++i) {
    // The motions as the control will run them: each end moved by its offset,
    // each start by the offset of the motion before (arcs are moved whole).
    const interp::Motion m = moved(motions[i], i ? offset(i - 1) : V3(V3::Zero()), offset(i));
    if (run.prepare(m)) {
      if (run.tool_changes() != changes) {
        changes = run.tool_changes();
        ran.clear();
        tm = &run.tool();
      }
      ran.push_back(i);
      run.sim().run(m);
    }
    if (progress && (i % 4096 == 0)) progress("simulating", static_cast<double>(i) / static_cast<double>(n));
  }
  run.finish();
}
}  // namespace

void simulate(const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets, const Physics& ph,
              const Settings& s, const PointSink& out, const Progress& progress, const DesignNormals* normals) {
  std::unique_ptr<stock::ZMap> map;
  if (ph.consumable_stock && ph.consumable_stock == ph.stock)
    map = std::make_unique<stock::ZMap>(std::move(*ph.consumable_stock));
  simulate_on(std::move(map), motions, offsets, ph, s, out, progress, normals);
}

std::vector<bool> movable(const std::vector<interp::Motion>& motions) {
  const std::size_t n = motions.size();
  std::vector<bool> ok(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    const interp::Motion& m = motions[i];
    if (!m.compensable() || !m.plain) continue;
    // The block after a moved point starts from it: the writer re-targets a
    // plain block by its words, but a canned cycle, G28/G30/G53, an M98 call or
    // a G91 move would carry the offset along. Such a point stays as programmed.
    if (i + 1 < n && !motions[i + 1].plain) continue;
    // Nor before a change of work frame (G54..): the offset would travel into
    // the next frame with the axes the next block leaves modal.
    if (i + 1 < n && motions[i + 1].work_offset_mm != m.work_offset_mm) continue;
    ok[i] = true;
  }
  // An arc moves whole (its centre words are relative to its start), so the
  // point before an arc that stays must stay too.
  for (std::size_t i = n; i-- > 1;)
    if (!ok[i] && (motions[i].kind == interp::MotionKind::arc_cw || motions[i].kind == interp::MotionKind::arc_ccw))
      ok[i - 1] = false;
  return ok;
}

namespace {

// The mirror method in one pass through the program. The stock a CL sample
// meets depends only on the path before it (causality), so the fixed point of
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
  Stream(const Physics& ph, const Settings& s, Result& r, const std::vector<bool>& can,
         const std::vector<bool>* splittable, const DesignNormals& normals, const Progress& progress,
         const PointSinks& sinks, std::unique_ptr<stock::ZMap> own)
      : ph_(ph), s_(s), r_(r), can_(can), split_(splittable), normals_(normals), progress_(progress),
        sinks_(sinks), run_(ph, s, {}, std::move(own)) {}

  // Fills r.motions (and the rest of the result) anew; `motions` must not be r.motions.
  void go(const std::vector<interp::Motion>& motions, const std::vector<double>& feeds) {
    r_.motions.clear();
    r_.inserted.clear();
    r_.offsets.clear();
    r_.final.clear();
    r_.feeds_mm_per_min.clear();
    r_.converged = true;
    const std::size_t n = motions.size();
    for (std::size_t i = 0; i < n; ++i) {
      // Run at the planned feed; written down at the programmed one (r.motions
      // are the motions as written, r.feeds_mm_per_min the plan).
      interp::Motion m = motions[i];
      programmed_feed_ = m.feed_mm_per_min;
      m.feed_mm_per_min = feed_ = feeds[i];
      splits_ = 0;
      if (!run_.prepare(m)) {
        emit(m, V3::Zero(), false, false, {}, false);
      } else if (m.kind == interp::MotionKind::rapid || !can_[i]) {
        std::vector<Point> pts;
        if (m.kind != interp::MotionKind::rapid) pts = samples(m, prev_, V3::Zero(), 0);
        emit(m, V3::Zero(), false, false, std::move(pts), true);
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
          r_.nonuniform_arcs.push_back(m.line);
          emit(m, prev_, false, true, std::move(pts), true);
        }
      } else {
        const bool may_split = split_ && (*split_)[i];
        piece(m, 0.0, 1.0, may_split);
      }
      if (progress_ && (i % 4096 == 0)) progress_("compensating", static_cast<double>(i) / static_cast<double>(n));
    }
    run_.finish();
    r_.iterations = max_updates_;
    r_.evaluations = evaluations_;
  }

 private:
  // One CL sample of motion m moved by (a, b).
  Point probe(const interp::Motion& m, const V3& a, const V3& b, int k, const std::vector<engage::Point3>* v = nullptr) {
    const interp::Motion mm = moved(m, a, b);
    std::vector<engage::Point3> own;
    if (!v) {
      own = engage::motion_vertices(mm, run_.sim().options().path);
      v = &own;
    }
    engage::CLSample cl;
    const engage::Metrics mt = run_.sim().probe(mm, *v, k == 0 ? static_cast<int>(v->size()) - 1 : k, cl, eng_);
    ++evaluations_;
    return point_of(cl, mt, eng_, run_.tool(), mm, m, a, b, normals_, ph_.k, rev_);
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
    const auto index = static_cast<std::uint32_t>(r_.motions.size());
    if (cut) run_.sim().run(moved(m, prev_, off));
    r_.motions.push_back(m);
    r_.motions.back().feed_mm_per_min = programmed_feed_;
    r_.inserted.push_back(inserted);
    r_.offsets.push_back(off);
    r_.feeds_mm_per_min.push_back(feed_);
    if (can && capped_) r_.capped_lines.push_back(m.line);
    capped_ = false;
    for (Point& p : pts) {
      p.motion = index;
      if (sinks_.final) {
        const double u = p.count ? static_cast<double>(p.index) / p.count : 1.0;
        sinks_.final(p, V3(prev_ + u * (off - prev_)));
      }
    }
    prev_ = off;
  }

  // An arc as chords whose sagitta is within Settings::chord_tol_mm, each end
  // compensated like a line's; the arc block keeps the last chord's piece of
  // the arc, moved whole with the last chord end (its centre words re-aimed by
  // the writer).
  void linearise(const interp::Motion& m) {
    const stock::Arc a = engage::arc_of(m);
    const int chords = std::max(2, stock::arc_chord_count(a, s_.chord_tol_mm));
    const std::vector<engage::Point3> v = stock::arc_polyline(a, chords);
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
    ++r_.linearised_arcs;
    r_.split_points += static_cast<std::size_t>(chords - 1);
  }

  // The part [u0, u1] of linear motion m (parameters of the whole move), its
  // start at the current offset prev_. Its end offset is solved; where the
  // samples between land outside the tolerance under the straight ramp of the
  // offsets and the move may be split, a vertex goes in at the worst sample and
  // the part before it is done first (at most max_splits_per_move per move).
  void piece(const interp::Motion& m, double u0, double u1, bool may_split, bool inserted = false) {
    const bool last = u1 == 1.0 && !inserted;
    for (;;) {
      interp::Motion part = m;
      for (int c = 0; c < 3; ++c) {
        part.start_mm[c] = m.start_mm[c] + u0 * (m.end_mm[c] - m.start_mm[c]);
        if (u1 != 1.0) part.end_mm[c] = m.start_mm[c] + u1 * (m.end_mm[c] - m.start_mm[c]);
      }
      Point end;
      const V3 off = solve(part, end);
      std::vector<Point> pts = samples(part, prev_, off, end.count);
      double worst = s_.tolerance_mm, at = -1;
      if (may_split && splits_ < s_.max_splits_per_move)
        for (const Point& p : pts) {
          if (p.air || p.plunge) continue;
          const double u = static_cast<double>(p.index) / p.count;
          const double res = std::fabs(landing_error(p, prev_ + u * (off - prev_)));
          if (res > worst) {
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
      ++r_.split_points;
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
    if (!p0.air && !p0.plunge && std::fabs(p0.error_mm) > s_.tolerance_mm) {
      const V3 n = p0.normal;
      const double g = s_.gain, cap = s_.max_offset_mm;
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
        const double e1 = p1.flank ? p1.error_mm : p1.delta_mm.dot(n), h1 = s1 + g * e1;
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
        ++r_.unconverged_points;
        r_.converged = false;
        r_.last_change_mm = std::max(r_.last_change_mm, best);
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
  Result& r_;
  const std::vector<bool>& can_;
  const std::vector<bool>* split_;
  const DesignNormals& normals_;
  const Progress& progress_;
  const PointSinks& sinks_;
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
};

}  // namespace

Result compensate(const std::vector<interp::Motion>& motions, const Physics& ph, const Settings& s,
                  const Progress& progress, const std::vector<bool>* splittable, const PointSinks* sinks) {
  const std::size_t n = motions.size();
  Result r;
  r.motions = motions;
  r.inserted.assign(n, false);
  r.offsets.assign(n, V3::Zero());
  r.feeds_mm_per_min.resize(n);
  for (std::size_t i = 0; i < n; ++i) r.feeds_mm_per_min[i] = motions[i].feed_mm_per_min;
  std::vector<double> feeds = r.feeds_mm_per_min;
  // The program as written is simulated for the report beside the stream, on
  // its own thread, unless the feed limit needs its forces first (or one
  // thread was asked for).
  const std::unique_ptr<DesignNormals> normals = design_normals(motions, ph, s);
  // Without sinks of the caller's the points are kept in the result.
  PointSinks kept;
  if (!sinks) {
    r.nominal.reserve(n * 2);
    kept.nominal = [&r](const Point& p) { r.nominal.push_back(p); };
    kept.final = [&r](const Point& p, const V3&) { r.final.push_back(p); };
    sinks = &kept;
  }
  // The as-written points go to the nominal sink; the feed limit needs their
  // peak force per motion, and with gain 0 and no feed limit they are the
  // final points as well (the same program).
  std::vector<double> peak(s.feed_limit_N > 0 ? n : 0, 0.0);
  const bool same = s.gain == 0.0;
  const PointSink nominal_sink = [&](const Point& p) {
    if (!peak.empty()) peak[p.motion] = std::max(peak[p.motion], p.peak_N);
    if (sinks->nominal) sinks->nominal(p);
    if (same && s.feed_limit_N <= 0 && sinks->final) sinks->final(p, V3::Zero());
  };
  // With a consumable stock the as-written simulation cuts a copy made here,
  // before the mirror pass takes the caller's map over.
  const bool take = ph.consumable_stock && ph.consumable_stock == ph.stock && !same;
  std::unique_ptr<stock::ZMap> nominal_map = take ? std::make_unique<stock::ZMap>(clone(*ph.stock)) : nullptr;
  std::exception_ptr nominal_failed;
  std::thread nominal;
  if (s.feed_limit_N > 0 || same || s.threads == 1) {
    simulate_on(std::move(nominal_map), motions, {}, ph, s, nominal_sink, progress, normals.get());
  } else {
    nominal = std::thread([&] {
      try {
        // One thread of its own: TBB's workers are left to the pass, whose
        // wall time is the run's.
        Settings one = s;
        one.threads = 1;
        simulate_on(std::move(nominal_map), motions, {}, ph, one, nominal_sink, {}, normals.get());
      } catch (...) {
        nominal_failed = std::current_exception();
      }
    });
  }
  struct Join {
    std::thread& t;
    ~Join() {
      if (t.joinable()) t.join();
    }
  } join{nominal};
  if (s.feed_limit_N > 0) {
    // What VERICUT Force does alone: lower the feed of a cutting block whose
    // peak force would exceed the limit. The cutting force grows with the chip
    // (f_z) while the edge force does not, so scaling F by limit/peak brings the
    // peak to the limit or below; the compensation then runs at these feeds.
    for (std::size_t i = 0; i < n; ++i) {
      const interp::Motion& m = motions[i];
      if (!m.plain || m.kind == interp::MotionKind::rapid || peak[i] <= s.feed_limit_N) continue;
      const double f = std::floor(m.feed_mm_per_min * s.feed_limit_N / peak[i] * 10.0) / 10.0;  // 0.1 mm/min, down
      feeds[i] = std::max(f, 0.1);
      r.feed_lowered_lines.push_back(m.line);
    }
  }
  r.feeds_mm_per_min = feeds;
  if (same) {
    // Nothing moves: the final points are those of the program as run (at the
    // lowered feeds where the feed limit lowered them).
    // Without a feed limit nominal_sink passed them on; with one they are
    // simulated again (the nominal points were handed over before the feeds
    // were known).
    if (sinks->final && s.feed_limit_N > 0) {
      std::vector<interp::Motion> planned;  // the program at the planned feeds
      if (!r.feed_lowered_lines.empty()) {
        planned = motions;
        for (std::size_t i = 0; i < n; ++i) planned[i].feed_mm_per_min = feeds[i];
      }
      simulate(planned.empty() ? motions : planned, {}, ph, s, [&](const Point& p) { sinks->final(p, V3::Zero()); },
               progress, normals.get());
    }
    r.converged = true;
    return r;
  }
  const std::vector<bool> can = movable(motions);
  std::unique_ptr<stock::ZMap> mirror_map =
      take ? std::make_unique<stock::ZMap>(std::move(*ph.consumable_stock)) : nullptr;
  Stream(ph, s, r, can, splittable, *normals, progress, *sinks, std::move(mirror_map)).go(motions, feeds);
  if (nominal.joinable()) nominal.join();
  if (nominal_failed) std::rethrow_exception(nominal_failed);
  for (std::size_t i = 0; i < r.motions.size(); ++i)
    if (r.offsets[i].norm() > 0) ++r.compensated_points;
  return r;
}

}  // namespace deflex::compensate
