#include "deflex/compensate/compensate.hpp"

#include "deflex/compensate/contact.hpp"
#include "internal.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
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
#include "deflex/interp/arc.hpp"
#include "deflex/stiffness/beam.hpp"

namespace deflex::compensate {
namespace detail {

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

namespace {

// The speed a stability table reaches when the profile gives no spindle: the
// top speed of the fastest common milling spindles.
constexpr double kDefaultMaxRpm = 30000;

// ToolModel::stability: the tool tip's modes on the machine (or clamped at
// the holder face with tool_only), over the spindle's speed range.
void stability_model(ToolModel& m, const Physics& ph) {
  try {
    const double max_rpm = ph.spindle.set ? ph.spindle.max_rpm : kDefaultMaxRpm;
    if (!m.tool.frf_file.empty()) {
      m.stability = std::make_shared<const stability::LimitCache>(stability::load_frf_csv(m.tool.frf_file), ph.k,
                                                                  m.tool.flutes, max_rpm);
      return;
    }
    const stability::TipModel tip = stability::tip_model(m.tool, ph.machine, ph.tool_only);
    m.stability = std::make_shared<const stability::LimitCache>(tip, ph.k, m.tool.flutes, max_rpm);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::config) throw;
    m.stability_unchecked = e.what();
  }
}

}  // namespace

const ToolModel& model_for(std::map<std::string, ToolModel>& cache, const std::string& id, const Physics& ph,
                           const Settings& s) {
  auto it = cache.find(id);
  if (it != cache.end()) return it->second;
  ToolModel m;
  m.tool = stiffness::find_tool(ph.tools, id);
  const force::Cutter c = force::cutter_of(m.tool);
  m.slices = force::make_slices(c, s.slice_mm, m.tool.flute_length_mm);
  m.compliance = stiffness::beam_compliance(m.tool, ph.machine, ph.tool_only);
  m.assembly = assembly_of(m.tool, ph.machine.holder);
  if (s.geometry_only) return cache.emplace(id, std::move(m)).first->second;  // the sweep alone
  if (m.tool.type != stock::EndShape::ball) {
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
  stability_model(m, ph);
  return cache.emplace(id, std::move(m)).first->second;
}

namespace {

// Height of the resultant: centre of the engaged edge length along the flutes.
double resultant_height_mm(const force::Engagement& eng, const ToolModel& tm) {
  double wz = 0, w = 0;
  for (std::size_t i = 0; i < eng.slices.size(); ++i) {
    double ang = 0;
    for (const auto& iv : eng.slices[i]) ang += iv.end - iv.start;
    const double wi = ang * tm.slices.slices[i].width_mm;
    wz += wi * tm.slices.slices[i].z_mm;
    w += wi;
  }
  return w > 0 ? wz / w : 0.0;
}

// The wall profile e(z) (force/flank.hpp) of a flank cut, all in the feed
// frame: the design normal and the structure's compliance turned into it.
// Sets p's flank figures, and its error to the profile's mid offset.
void flank_profile(Point& p, const engage::CLSample& cl, const engage::Metrics& mt, const force::Engagement& eng,
                   const ToolModel& tm, const force::Coefficients& k, double fz, bool keep_profile) {
  const double fx = cl.point.feed_x, fy = cl.point.feed_y;
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
  if (prof.points.empty()) return;
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

// Point::feed_share: the peak force's share (force::peak_feed_share, from
// the revolution's forces and the edge forces alone) and the torque's (the
// torque's cutting part scales with f_z: s M_c + M_e <= the S1 curve's
// allowance at this speed; P = M w at a fixed S is the same limit).
double feed_share(const ToolModel& tm, const force::Coefficients& k, double fz, const force::Engagement& eng,
                  std::span<const force::Vec3> rev, double peak_N, const force::MeanTorque& torque, double rpm,
                  const FeedLimits& limits) {
  double share = 1;
  if (peak_N > limits.force_N) {
    thread_local std::vector<force::Vec3> edge;
    edge.resize(rev.size());
    force::revolution_forces(tm.slices, tm.grid, k, 0.0, eng, edge);
    share = force::peak_feed_share(rev, edge, limits.force_N);
  }
  if (limits.spindle && limits.spindle->set) {
    const double allowed_Nm = limits.spindle->s1.allowed_torque_Nm(rpm);
    if (torque.total_Nm() > allowed_Nm)
      share = std::min(share, torque.cutting_Nm > 0 ? std::max(0.0, (allowed_Nm - torque.edge_Nm) / torque.cutting_Nm) : 0.0);
  }
  return share;
}

// Point::ap_limit_mm: 0 where nothing is engaged on the cutting side.
double stability_limit(const stability::LimitCache& c, const force::CutterSlices& cs, const force::Engagement& eng,
                       const force::Coefficients& k, double ap_mm, double rpm) {
  const double a = c.ap_limit_mm(stability::directional_matrix_mm(cs, eng, k), ap_mm, rpm);
  return std::isfinite(a) ? a : 0.0;
}

}  // namespace

Point geometry_point(const engage::CLSample& cl, const interp::Motion& design) {
  Point p;
  p.line = cl.line;
  p.tool = design.tool;
  p.fixed = design.fixed;
  p.index = cl.index;
  p.count = cl.count;
  p.tip_mm = V3(cl.point.tip_mm[0], cl.point.tip_mm[1], cl.point.tip_mm[2]);
  return p;
}

FeedLimits feed_limits(const Physics& ph, const Settings& s) {
  return {s.feed_limit_N, ph.spindle.set ? &ph.spindle : nullptr};
}

// The workpiece's share (workpiece.hpp): its displacement where the force
// acts on it - the contact, or for a flank cut the wall at the height of the
// force's resultant - under the force on it (-F) moves the landing by
// -delta_w . n. A flank cut's e(z) shifts by it as a whole: the part's
// compliance at one point, not how the wall bends between heights (a thin
// wall's top gives way more than its foot under the same load).
void add_workpiece(Point& p, const ToolModel& tm, const WorkpieceCompliance& w, std::size_t motion) {
  const V3 at = p.flank ? flank_point(p, tm.tool, p.height_mm) : contact_point(p, tm.tool);
  p.workpiece_delta_mm = w.at(at, p.normal, motion) * V3(-p.force_N);
  const double shift = -p.workpiece_delta_mm.dot(p.normal);
  p.error_mm += shift;
  if (!p.flank) return;
  p.flank_min_mm += shift;
  p.flank_max_mm += shift;
  for (force::FlankPoint& f : p.flank_profile) f.error_mm += shift;
}

Point point_of(const engage::CLSample& cl, const engage::Metrics& mt, const force::Engagement& eng, const ToolModel& tm,
               const interp::Motion& m, const interp::Motion& design, std::size_t index, const V3& a, const V3& b,
               const DesignNormals& normals, const force::Coefficients& k, const FeedLimits& limits,
               const WorkpieceCompliance* workpiece, std::vector<force::Vec3>& rev, bool keep_profile) {
  Point p = geometry_point(cl, design);
  p.ap_mm = mt.ap_mm;
  p.ae_mm = mt.ae_mm;
  p.cwe_area_mm2 = mt.cwe_area_mm2;
  p.d_eff_mm = mt.d_eff_mm;
  // The engager's MRR is at the feed its Process was made with (the tool's first
  // cut); the motion's own F gives this point's.
  p.mrr_mm3_per_s = mt.section_mm2 * m.feed_mm_per_min / 60;
  p.section_mm2 = mt.section_mm2;
  p.air = mt.air_cut || eng.empty();
  p.plunge = mt.plunge;
  const double u = cl.count ? static_cast<double>(cl.index) / cl.count : 1.0;
  const SurfaceNormal sn = normals.at(cl, mt, tm.tool, design, p.tip_mm - (a + u * (b - a)), index);
  p.normal = sn.n;
  p.normal_source = sn.source;
  p.part_gap_mm = sn.part_gap_mm;
  if (p.air || p.plunge) return p;
  const int flutes = tm.slices.cutter.flutes;
  const double rpm = m.spindle_rpm > 0 ? m.spindle_rpm : 0.0;
  if (rpm <= 0) throw Error(ErrorKind::input, "line " + std::to_string(m.line) + ": cutting with no spindle speed (S) set");
  const double fz = m.feed_mm_per_min / (rpm * flutes);
  rev.resize(static_cast<std::size_t>(tm.grid.steps));
  force::revolution_forces(tm.slices, tm.grid, k, fz, eng, rev);
  force::Vec3 f = force::summarize(rev).mean_N;
  for (const force::Vec3& fj : rev) p.peak_N = std::max(p.peak_N, fj.norm());
  // Feed frame X' = feed, Y' = Z x X' -> machine axes.
  const double fx = cl.point.feed_x, fy = cl.point.feed_y;
  p.force_N = V3(f.x() * fx - f.y() * fy, f.x() * fy + f.y() * fx, f.z());
  p.spindle_rpm = rpm;
  const force::MeanTorque torque = force::mean_torque(tm.slices, k, fz, eng);
  p.torque_Nm = torque.total_Nm();
  p.power_kW = profile::power_from_torque_kW(p.torque_Nm, rpm);
  if (limits.force_N > 0) p.feed_share = feed_share(tm, k, fz, eng, rev, p.peak_N, torque, rpm, limits);
  p.ap_limit_mm = !tm.stability ? -1.0 : stability_limit(*tm.stability, tm.slices, eng, k, p.ap_mm, rpm);
  p.height_mm = resultant_height_mm(eng, tm);
  p.delta_mm = tm.compliance.at(p.height_mm) * p.force_N;
  p.error_mm = p.delta_mm.dot(p.normal);
  if (tm.flank_c.n && flank_cut(mt, tm.tool)) flank_profile(p, cl, mt, eng, tm, k, fz, keep_profile);
  if (workpiece) add_workpiece(p, tm, *workpiece, index);
  return p;
}

// The highest stock over the leading half of the disc of radius r around the
// tip (centre, rings at r/2 and 0.95 r, every 22.5 deg from -90 to +90 deg
// about the feed direction), less the tip's height: Point::stock_depth_mm
// above the tip, Point::stock_gap_mm below it.
double stock_above(const stock::ZMap& z, const engage::CLSample& cl, double r) {
  const auto& t = cl.point.tip_mm;
  const double fx = cl.point.feed_x, fy = cl.point.feed_y;
  double top = -std::numeric_limits<double>::infinity();
  for (double rr : {0.0, 0.5 * r, 0.95 * r})
    for (int k = -4; k <= 4; ++k) {
      const double a = k * std::numbers::pi / 8, c = std::cos(a), sn = std::sin(a);
      top = std::max(top, static_cast<double>(z.height_at(t[0] + rr * (fx * c - fy * sn), t[1] + rr * (fy * c + fx * sn))));
      if (rr == 0) break;
    }
  return top - t[2];
}

interp::Motion moved(interp::Motion m, const V3& a, const V3& b) {
  for (int c = 0; c < 3; ++c) {
    m.start_mm[c] += a[c];
    m.end_mm[c] += b[c];
    m.center_mm[c] += b[c];
  }
  return m;
}

}  // namespace detail

using namespace detail;

std::string tool_id(int t_number, const Settings& s) {
  return !s.tool_override.empty() ? s.tool_override : "T" + std::to_string(t_number);
}
std::string tool_id(const interp::Motion& m, const Settings& s) { return tool_id(m.tool, s); }

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

struct Simulation::Impl {
  Impl(const Physics& p, const Settings& st, const DesignNormals& n, PointSink o, std::unique_ptr<stock::ZMap> map,
       Progress pr, std::size_t t)
      : ph(p), s(st), normals(n), out(std::move(o)), progress(std::move(pr)), total(t),
        run(
            p, st, [this](const engage::CLSample& cl, const engage::Metrics&, const force::Engagement&) { emit(cl); },
            std::move(map),
            [this](std::size_t slot, const engage::CLSample& cl, const engage::Metrics& mt,
                   const force::Engagement& eng) { prepare(slot, cl, mt, eng); }) {
    slots.resize(run.options().max_batch);
  }

  // A sample's point (its forces, deflection, normal, the stock around it)
  // depends on its engagement alone: computed for a whole batch at once on
  // the simulator's threads (engage::SampleWork), handed on in program order
  // by emit(). A failure is kept with its sample, so that the first one in
  // program order is the one reported, whatever the threads.
  struct Prepared {
    Point p;
    std::exception_ptr failed;
  };

  void prepare(std::size_t slot, const engage::CLSample& cl, const engage::Metrics& mt, const force::Engagement& eng) {
    Prepared& r = slots[slot];
    r.failed = nullptr;
    if (cl.rapid) return;
    try {
      // A simulator runs every motion from its first one on: its count of
      // motions is the program's index less its first one's.
      const std::size_t gi = sim_base + cl.motion;
      const auto it = std::lower_bound(held.begin(), held.end(), gi,
                                       [](const Held& h, std::size_t i) { return h.index < i; });
      if (it == held.end() || it->index != gi) throw Error(ErrorKind::internal, "simulation: a sample of an unknown motion");
      if (s.geometry_only) {
        r.p = geometry_point(cl, it->design);
        r.p.motion = static_cast<std::uint32_t>(gi);
        return;
      }
      thread_local std::vector<force::Vec3> rev;
      r.p = point_of(cl, mt, eng, *tm, it->design, it->design, gi, it->a, it->b, normals, ph.k, feed_limits(ph, s),
                     ph.workpiece, rev, s.flank_profiles);
      r.p.motion = static_cast<std::uint32_t>(gi);
      const double above_mm = stock_above(run.zmap(), cl, 0.5 * tm->tool.diameter_mm);
      r.p.stock_depth_mm = std::max(0.0, above_mm);
      r.p.stock_gap_mm = std::max(0.0, -above_mm);
    } catch (...) {
      r.failed = std::current_exception();
    }
  }

  void emit(const engage::CLSample& cl) {
    if (cl.rapid) return;
    Prepared& r = slots[run.sim().sink_slot()];
    if (r.failed) std::rethrow_exception(r.failed);
    // The motions before are done with.
    while (!held.empty() && held.front().index < r.p.motion) held.pop_front();
    // The assembly reads the stock as far as the holder's radius, beyond the
    // tiles an evaluation waits for (Simulator::read_box): here, in the sink,
    // the commit beside it has ended, so the stock read is the same whatever
    // the threads, and no tile is being written. The sweeps the sample's
    // evaluation saw pending count too: a plunge deeper than the flutes has
    // cut the bore its shank follows into.
    const Interference hit = interference(run.sim().sink_view(), r.p.tip_mm, tm->assembly);
    r.p.collision_mm = hit.depth_mm;
    r.p.collision_part = hit.part;
    out(r.p);
  }

  void add(const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets) {
    for (std::size_t i = 0; i < motions.size(); ++i, ++next) {
      // The motions as the control will run them: each end moved by its offset,
      // each start by the offset of the motion before (arcs are moved whole).
      const V3 b = offsets.empty() ? V3(V3::Zero()) : offsets[i];
      const interp::Motion m = moved(motions[i], prev, b);
      if (run.prepare(m)) {
        if (run.tool_changes() != changes) {
          changes = run.tool_changes();
          sim_base = next;
          tm = &run.tool();
        }
        // Rapids are cut, not sampled: only cutting motions wait for their samples.
        if (m.kind != interp::MotionKind::rapid) held.push_back({next, motions[i], prev, b});
        run.sim().run(m);
      }
      prev = b;
      if (progress && (next % 4096 == 0))
        progress("simulating", total ? static_cast<double>(next) / static_cast<double>(total) : 0.0);
    }
  }

  struct Held {  // a motion run whose samples may still come (a batch late at most)
    std::size_t index;
    interp::Motion design;
    V3 a, b;
  };
  const Physics& ph;
  const Settings& s;
  const DesignNormals& normals;
  PointSink out;
  Progress progress;
  std::size_t total;
  std::deque<Held> held;
  std::size_t next = 0;      // program index of the next motion added
  std::size_t sim_base = 0;  // program index of the current simulator's first motion
  std::size_t changes = 0;
  V3 prev = V3::Zero();      // offset of the last motion added
  const ToolModel* tm = nullptr;
  std::vector<Prepared> slots;  // the points of the batch in the simulator's work, by slot (max_batch)
  Run run;
};

Simulation::Simulation(const Physics& ph, const Settings& s, const DesignNormals& normals, PointSink sink,
                       std::unique_ptr<stock::ZMap> map, Progress progress, std::size_t total)
    : impl_(std::make_unique<Impl>(ph, s, normals, std::move(sink), std::move(map), std::move(progress), total)) {}
Simulation::~Simulation() = default;
void Simulation::add(const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets) {
  impl_->add(motions, offsets);
}
void Simulation::finish() { impl_->run.finish(); }

void simulate(const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets, const Physics& ph,
              const Settings& s, const PointSink& out, const Progress& progress, const DesignNormals* normals) {
  std::unique_ptr<stock::ZMap> map;
  if (ph.consumable_stock && ph.consumable_stock == ph.stock)
    map = std::make_unique<stock::ZMap>(std::move(*ph.consumable_stock));
  std::unique_ptr<DesignNormals> own;
  if (!normals) {
    own = design_normals(motions, ph, s);
    normals = own.get();
  }
  Simulation sim(ph, s, *normals, out, std::move(map), progress, motions.size());
  sim.add(motions, offsets);
  sim.finish();
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
    if (!ok[i] && interp::is_arc(motions[i]))
      ok[i - 1] = false;
  return ok;
}

}  // namespace deflex::compensate
