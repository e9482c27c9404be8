#include "deflex/compensate/compensate.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/engage/engagement.hpp"
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
  // Steps a multiple of the flute count: the force model then computes one
  // tooth pitch and repeats it.
  int steps = std::max(s.force_steps / c.flutes, 4) * c.flutes;
  m.grid = force::make_angle_grid(steps);
  return cache.emplace(id, std::move(m)).first->second;
}

std::string tool_id(const interp::Motion& m, const Settings& s) {
  return !s.tool_override.empty() ? s.tool_override : "T" + std::to_string(m.tool);
}

// The outward normal of the surface generated at a CL point (see compensate.hpp).
V3 surface_normal(const engage::CLSample& cl, const engage::Metrics& mt, const stiffness::Tool& t) {
  const auto& p = cl.point;
  const V3 yf(-p.feed_y, p.feed_x, 0.0);  // Y' of the feed frame
  const bool flank = t.type != stiffness::ToolType::ball &&
                     mt.ap_mm > std::max(0.5 * t.corner_radius_mm, 0.2) && mt.ae_mm < 0.95 * t.diameter_mm;
  if (flank) return mt.up_share > 0.5 ? V3(-yf) : yf;  // wall on the side that cuts
  V3 dir(p.dir[0], p.dir[1], p.dir[2]);
  V3 n = V3::UnitZ() - dir.dot(V3::UnitZ()) * dir;
  double len = n.norm();
  return len > 1e-9 ? V3(n / len) : V3::UnitZ();
}

}  // namespace

std::vector<Point> simulate(const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets,
                            const Physics& ph, const Settings& s, const Progress& progress) {
  if (!ph.stock) throw Error(Exit::usage, "no stock: give --stock box:X0,Y0,Z0,X1,Y1,Z1 or a solid file");
  stock::ZMap z = clone(*ph.stock);
  std::map<std::string, ToolModel> models;
  std::vector<Point> out;
  out.reserve(motions.size() * 2);

  const ToolModel* cur = nullptr;
  std::unique_ptr<engage::Simulator> sim;
  std::vector<force::Vec3> rev;
  // The motions as the control will run them: each end moved by its offset,
  // each start by the offset of the motion before (arcs are moved whole).
  std::vector<interp::Motion> moved;
  auto offset = [&](std::size_t i) { return offsets.empty() ? V3(V3::Zero()) : offsets[i]; };

  // CLSample::motion counts the motions one Simulator has run; ran[] maps it
  // back to the index in `motions` (rapids before the first cut are not run,
  // and a tool change starts a new Simulator).
  std::vector<std::size_t> ran;
  auto sink = [&](const engage::CLSample& cl, const engage::Metrics& mt, const force::Engagement& eng) {
    if (cl.rapid) return;
    const std::size_t gi = ran.at(cl.motion);
    const interp::Motion& m = motions[gi];
    Point p;
    p.line = cl.line;
    p.motion = static_cast<std::uint32_t>(gi);
    p.index = cl.index;
    p.count = cl.count;
    p.tip_mm = V3(cl.point.tip_mm[0], cl.point.tip_mm[1], cl.point.tip_mm[2]);
    p.ap_mm = mt.ap_mm;
    p.ae_mm = mt.ae_mm;
    p.air = mt.air_cut || eng.empty();
    p.plunge = mt.plunge;
    p.normal = surface_normal(cl, mt, cur->tool);
    if (!p.air && !p.plunge) {
      const int flutes = cur->slices.cutter.flutes;
      const double rpm = m.spindle_rpm > 0 ? m.spindle_rpm : 0.0;
      if (rpm <= 0) throw Error(Exit::input, "line " + std::to_string(m.line) + ": cutting with no spindle speed (S) set");
      const double fz = m.feed_mm_per_min / (rpm * flutes);
      rev.resize(static_cast<std::size_t>(cur->grid.steps));
      force::revolution_forces(cur->slices, cur->grid, ph.k, fz, eng, rev);
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
        const double wi = ang * cur->slices.slices[i].width_mm;
        wz += wi * cur->slices.slices[i].z_mm;
        w += wi;
      }
      p.height_mm = w > 0 ? wz / w : 0.0;
      p.delta_mm = cur->compliance.at(p.height_mm) * p.force_N;
      p.error_mm = p.delta_mm.dot(p.normal);
    }
    out.push_back(p);
  };

  engage::SimOptions so;
  so.path.cl_spacing_mm = s.cl_spacing_mm;
  so.threads = s.threads;
  std::string cur_id;
  const std::size_t n = motions.size();
  for (std::size_t i = 0; i < n; ++i) {
    interp::Motion m = motions[i];
    const V3 o = offset(i), o_prev = i ? offset(i - 1) : V3(V3::Zero());
    for (int a = 0; a < 3; ++a) {
      m.start_mm[a] += o_prev[a];
      m.end_mm[a] += o[a];
      m.center_mm[a] += o[a];
    }
    if (m.kind != interp::MotionKind::rapid || sim) {
      const std::string id = tool_id(m, s);
      if (m.kind != interp::MotionKind::rapid && id != cur_id) {
        if (sim) sim->finish();
        if (m.tool == 0 && s.tool_override.empty())
          throw Error(Exit::input, "line " + std::to_string(m.line) + ": cutting with no tool (T.. M6) selected; give --tool");
        cur = &model_for(models, id, ph, s);
        engage::Process proc;
        proc.spindle_rpm = m.spindle_rpm > 0 ? m.spindle_rpm : 1.0;
        proc.fz_mm = m.feed_mm_per_min / (proc.spindle_rpm * cur->slices.cutter.flutes);
        sim = std::make_unique<engage::Simulator>(z, cur->slices, proc, so, sink);
        ran.clear();
        cur_id = id;
      }
      ran.push_back(i);
      sim->run(m);
    }
    if (progress && (i % 4096 == 0)) progress("simulating", static_cast<double>(i) / static_cast<double>(n));
  }
  if (sim) sim->finish();
  return out;
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
  return ok;
}

namespace {

// End-point error vector e n per motion (the CL sample that is its end).
void end_errors(const std::vector<Point>& pts, std::size_t n, std::vector<V3>& e, std::vector<bool>& has) {
  e.assign(n, V3::Zero());
  has.assign(n, false);
  for (const Point& p : pts)
    if (p.index == p.count && !p.air && !p.plunge) {
      e[p.motion] = p.error_mm * p.normal;
      has[p.motion] = true;
    }
}

struct Loop {
  const Physics& ph;
  const Settings& s;
  const Progress& progress;
  Result& r;
  std::vector<bool> can, active, capped;

  // Mirror iterations from the current offsets (r.final must hold the
  // simulation at them) to the fixed point.
  void run(int max_iterations) {
    const std::size_t n = r.motions.size();
    std::vector<V3> e;
    std::vector<bool> has;
    end_errors(r.final, n, e, has);
    for (int it = 1; it <= max_iterations; ++it) {
      // A point that was inside the band as written but left it once its
      // neighbours were compensated (the stock it meets changed) joins in.
      for (std::size_t i = 0; i < n; ++i)
        if (can[i] && has[i] && !active[i] && (e[i] + r.offsets[i]).norm() > s.tolerance_mm) active[i] = true;
      std::vector<V3> next(n, V3::Zero());
      for (std::size_t i = 0; i < n; ++i)
        if (active[i] && has[i]) next[i] = -s.gain * e[i];  // Smaoui 2011 §4: the mirror image
      for (std::size_t i = 0; i < n; ++i) {
        const double len = next[i].norm();
        if (len > s.max_offset_mm) {
          next[i] *= s.max_offset_mm / len;
          capped[i] = true;
        }
      }
      // No jerk: bound the change of offset from one point to the next.
      for (int pass = 0; pass < 2; ++pass)
        for (std::size_t k = 1; k < n; ++k) {
          const std::size_t i = pass == 0 ? k : n - 1 - k, j = pass == 0 ? k - 1 : n - k;
          if (!can[i] || !can[j]) continue;
          const V3 d = next[i] - next[j];
          const double len = d.norm();
          if (len > s.max_step_mm) next[i] = next[j] + d * (s.max_step_mm / len);
        }
      // Arcs move whole: their end takes the offset of their start.
      for (std::size_t i = 0; i < n; ++i) {
        const auto k = r.motions[i].kind;
        if (!can[i] || (k != interp::MotionKind::arc_cw && k != interp::MotionKind::arc_ccw)) continue;
        const V3 start = i ? next[i - 1] : V3(V3::Zero());
        if ((next[i] - start).norm() > s.tolerance_mm && it == max_iterations) r.nonuniform_arcs.push_back(r.motions[i].line);
        next[i] = start;
      }
      double change = 0;
      for (std::size_t i = 0; i < n; ++i) change = std::max(change, (next[i] - r.offsets[i]).norm());
      r.offsets = next;
      ++r.iterations;
      r.last_change_mm = change;
      if (progress) progress("iteration " + std::to_string(r.iterations), 0.0);
      r.final = simulate(r.motions, r.offsets, ph, s, progress);
      if (change <= 0.01 * s.tolerance_mm) { r.converged = true; return; }
      r.converged = false;
      end_errors(r.final, n, e, has);
    }
  }

  // Inserts vertices into moves whose samples, under the straight ramp of the
  // offsets of their ends, land outside the tolerance. Returns how many.
  std::size_t split(const std::vector<bool>& splittable_by_motion) {
    const std::size_t n = r.motions.size();
    std::vector<std::vector<const Point*>> by_motion(n);
    for (const Point& p : r.final)
      if (!p.air && !p.plunge && p.index < p.count) by_motion[p.motion].push_back(&p);
    struct Vertex { double u; V3 offset; };
    std::vector<std::vector<Vertex>> add(n);
    std::size_t total = 0;
    for (std::size_t i = 1; i < n; ++i) {
      if (!can[i] || !splittable_by_motion[i] || r.motions[i].kind != interp::MotionKind::linear) continue;
      const auto& pts = by_motion[i];
      if (pts.empty()) continue;
      // Knots of the ramp: (u, offset), starting with the two ends.
      std::vector<Vertex> knots{{0.0, r.offsets[i - 1]}, {1.0, r.offsets[i]}};
      auto ramp = [&](double u) {
        std::size_t k = 1;
        while (k + 1 < knots.size() && knots[k].u < u) ++k;
        const double t = (u - knots[k - 1].u) / (knots[k].u - knots[k - 1].u);
        return V3(knots[k - 1].offset + t * (knots[k].offset - knots[k - 1].offset));
      };
      // The sample was simulated under the old ramp (its commanded offset is
      // the straight ramp of the ends); its deflection is kept for the estimate.
      for (int sp = 0; sp < s.max_splits_per_move; ++sp) {
        double worst = s.tolerance_mm;
        const Point* at = nullptr;
        for (const Point* p : pts) {
          const double u = static_cast<double>(p->index) / p->count;
          const double res = std::fabs((ramp(u) + p->delta_mm).dot(p->normal));
          if (res > worst) { worst = res; at = p; }
        }
        if (!at) break;
        const double u = static_cast<double>(at->index) / at->count;
        V3 want = -s.gain * at->error_mm * at->normal;
        if (want.norm() > s.max_offset_mm) want *= s.max_offset_mm / want.norm();
        knots.insert(std::upper_bound(knots.begin(), knots.end(), u, [](double v, const Vertex& k) { return v < k.u; }),
                     Vertex{u, want});
        add[i].push_back({u, want});
      }
      std::sort(add[i].begin(), add[i].end(), [](const Vertex& a, const Vertex& b) { return a.u < b.u; });
      total += add[i].size();
    }
    if (!total) return 0;
    // Rebuild the motion list with the new vertices.
    std::vector<interp::Motion> m2;
    std::vector<bool> ins2, can2, act2, cap2;
    std::vector<V3> off2;
    std::vector<double> feeds2;
    for (std::size_t i = 0; i < n; ++i) {
      const interp::Motion& m = r.motions[i];
      interp::Vec3 prev = m.start_mm;
      for (const Vertex& v : add[i]) {
        interp::Motion piece = m;
        for (int a = 0; a < 3; ++a) piece.end_mm[a] = m.start_mm[a] + v.u * (m.end_mm[a] - m.start_mm[a]);
        piece.start_mm = prev;
        prev = piece.end_mm;
        m2.push_back(piece);
        feeds2.push_back(r.feeds_mm_per_min[i]);
        ins2.push_back(true);
        can2.push_back(true);
        act2.push_back(true);
        cap2.push_back(false);
        off2.push_back(v.offset);
      }
      interp::Motion rest = m;
      rest.start_mm = prev;
      m2.push_back(rest);
      feeds2.push_back(r.feeds_mm_per_min[i]);
      ins2.push_back(r.inserted[i]);
      can2.push_back(can[i]);
      act2.push_back(active[i]);
      cap2.push_back(capped[i]);
      off2.push_back(r.offsets[i]);
    }
    r.motions = std::move(m2);
    r.inserted = std::move(ins2);
    can = std::move(can2);
    active = std::move(act2);
    capped = std::move(cap2);
    r.offsets = std::move(off2);
    r.feeds_mm_per_min = std::move(feeds2);
    return total;
  }
};

}  // namespace

Result compensate(const std::vector<interp::Motion>& motions, const Physics& ph, const Settings& s,
                  const Progress& progress, const std::vector<bool>* splittable) {
  const std::size_t n = motions.size();
  Result r;
  r.motions = motions;
  r.inserted.assign(n, false);
  r.offsets.assign(n, V3::Zero());
  r.nominal = simulate(motions, {}, ph, s, progress);
  r.final = r.nominal;
  r.feeds_mm_per_min.resize(n);
  for (std::size_t i = 0; i < n; ++i) r.feeds_mm_per_min[i] = motions[i].feed_mm_per_min;
  if (s.feed_limit_N > 0) {
    // What VERICUT Force does alone: lower the feed of a cutting block whose
    // peak force would exceed the limit. The cutting force grows with the chip
    // (f_z) while the edge force does not, so scaling F by limit/peak brings the
    // peak to the limit or below; the compensation then simulates these feeds.
    std::vector<double> peak(n, 0.0);
    for (const Point& p : r.nominal) peak[p.motion] = std::max(peak[p.motion], p.peak_N);
    for (std::size_t i = 0; i < n; ++i) {
      const interp::Motion& m = motions[i];
      if (!m.plain || m.kind == interp::MotionKind::rapid || peak[i] <= s.feed_limit_N) continue;
      const double f = std::floor(m.feed_mm_per_min * s.feed_limit_N / peak[i] * 10.0) / 10.0;  // 0.1 mm/min, down
      r.feeds_mm_per_min[i] = std::max(f, 0.1);
      r.motions[i].feed_mm_per_min = r.feeds_mm_per_min[i];
      r.feed_lowered_lines.push_back(m.line);
    }
    if (!r.feed_lowered_lines.empty()) r.final = simulate(r.motions, {}, ph, s, progress);
  }
  if (s.gain == 0.0) {
    r.converged = true;
    return r;
  }
  Loop loop{ph, s, progress, r, movable(motions), std::vector<bool>(n, false), std::vector<bool>(n, false)};
  // Points inside the tolerance band stay as programmed (decided on the program as written).
  std::vector<V3> e0;
  std::vector<bool> has0;
  end_errors(r.final, n, e0, has0);  // as written, at the feeds that will run
  for (std::size_t i = 0; i < n; ++i) loop.active[i] = loop.can[i] && has0[i] && e0[i].norm() > s.tolerance_mm;
  loop.run(s.max_iterations);
  if (splittable) {
    // Moves whose error changes along them: split them, then find the fixed point again.
    std::vector<bool> split_ok(n, false);
    for (std::size_t i = 0; i < n; ++i) split_ok[i] = (*splittable)[i];
    r.split_points = loop.split(split_ok);
    if (r.split_points) {
      r.final = simulate(r.motions, r.offsets, ph, s, progress);
      loop.run(s.max_iterations);
    }
  }
  for (std::size_t i = 0; i < r.motions.size(); ++i) {
    if (loop.capped[i]) r.capped_lines.push_back(r.motions[i].line);
    if (r.offsets[i].norm() > 0) ++r.compensated_points;
  }
  return r;
}

}  // namespace deflex::compensate
