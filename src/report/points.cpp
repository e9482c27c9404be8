// The per-point table of a report and points.csv (include/deflex/report/points.hpp).
#include "deflex/report/points.hpp"

#include <cstdio>

#include "deflex/report/text_out.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::report {

V3 offset_at(const compensate::Point& p, const std::vector<V3>& offsets) {
  if (offsets.empty()) return V3::Zero();
  const V3 end = offsets[p.motion], start = p.motion ? offsets[p.motion - 1] : V3(V3::Zero());
  const double u = p.count ? static_cast<double>(p.index) / p.count : 1.0;
  return start + u * (end - start);
}

std::vector<double> landing_errors(const std::vector<compensate::Point>& pts, const std::vector<V3>& offsets) {
  std::vector<double> e(pts.size(), kNone);
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (!pts[i].air && !pts[i].plunge) e[i] = compensate::landing_error(pts[i], offset_at(pts[i], offsets));
  return e;
}

namespace {

// Two samples follow each other on the tool's path when no rapid lies between
// them (same motion, or the next one).
bool continuous(const compensate::Point& a, const compensate::Point& b) { return b.motion - a.motion <= 1; }

std::vector<double> path_lengths(const std::vector<compensate::Point>& pts) {
  std::vector<double> s(pts.size(), 0.0);
  for (std::size_t i = 1; i < pts.size(); ++i)
    s[i] = s[i - 1] + (continuous(pts[i - 1], pts[i]) ? (pts[i].tip_mm - pts[i - 1].tip_mm).norm() : 0.0);
  return s;
}

std::vector<process::CuspResult> cusp_of(const std::vector<compensate::Point>& pts,
                                         const std::vector<interp::Motion>& motions, const compensate::Physics& ph,
                                         const compensate::Settings& s) {
  return process::cusp_heights(cusp_samples(pts, motions, ph, s));
}

}  // namespace

std::vector<process::CuspSample> cusp_samples(const std::vector<compensate::Point>& pts,
                                              const std::vector<interp::Motion>& motions,
                                              const compensate::Physics& ph, const compensate::Settings& s) {
  std::vector<process::CuspSample> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const compensate::Point& p = pts[i];
    process::CuspSample& c = out[i];
    c.tip_mm = p.tip_mm;
    c.normal = p.normal;
    c.cutting = !p.air && !p.plunge;
    // Central difference along the path where both neighbours continue it.
    const bool back = i > 0 && continuous(pts[i - 1], p), ahead = i + 1 < pts.size() && continuous(p, pts[i + 1]);
    c.feed_dir = (ahead ? pts[i + 1].tip_mm : p.tip_mm) - (back ? pts[i - 1].tip_mm : p.tip_mm);
    const auto it = ph.tools.tools.find(compensate::tool_id(motions[p.motion], s));
    if (it != ph.tools.tools.end() && it->second.type == stiffness::ToolType::ball)
      c.profile_diameter_mm = it->second.diameter_mm;
  }
  return out;
}

namespace {

// The columns every table has: offsets along n, errors, path length; the cusp
// column sized but empty (its source differs: the points' own, or the
// program as written).
PointTable base_table(std::vector<compensate::Point> pts, const std::vector<V3>& intent) {
  PointTable t;
  t.path_mm = path_lengths(pts);
  t.offset_n_mm.resize(pts.size());
  t.error_mm.assign(pts.size(), kNone);
  t.error_as_written_mm.assign(pts.size(), kNone);
  t.cusp.resize(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const V3 off = offset_at(pts[i], intent);
    t.offset_n_mm[i] = off.dot(pts[i].normal);
    if (!pts[i].air) t.error_mm[i] = compensate::landing_error(pts[i], off);  // plunges too, in points.csv
  }
  t.points = std::move(pts);
  return t;
}

}  // namespace

PointTable table_of_simulation(std::vector<compensate::Point> pts, const std::vector<V3>& intent,
                               const std::vector<interp::Motion>& motions, const compensate::Physics& ph,
                               const compensate::Settings& s) {
  PointTable t = base_table(std::move(pts), intent);
  t.cusp = cusp_of(t.points, motions, ph, s);
  return t;
}

PointTable table_of_compensation(std::vector<compensate::Point> final, const std::vector<compensate::Point>& nominal,
                                 const compensate::Result& r, const std::vector<interp::Motion>& original,
                                 const compensate::Physics& ph, const compensate::Settings& s) {
  PointTable t = base_table(std::move(final), r.offsets);
  t.has_as_written = true;
  // The original move of each motion of the result: an inserted block splits
  // the next motion that is not inserted.
  std::vector<std::size_t> parent(r.motions.size());
  std::size_t o = 0;
  for (std::size_t k = 0; k < r.motions.size(); ++k) {
    parent[k] = o;
    if (!(k < r.inserted.size() && r.inserted[k])) ++o;
  }
  // The as-written samples of each original motion: a contiguous range.
  std::vector<std::size_t> first(original.size() + 1, nominal.size());
  for (std::size_t i = nominal.size(); i-- > 0;) first[nominal[i].motion] = i;
  for (std::size_t m = original.size(); m-- > 0;) first[m] = std::min(first[m], first[m + 1]);
  const std::vector<process::CuspResult> cusp = cusp_of(nominal, original, ph, s);
  // The points of one original move (its inserted pieces first) run along it
  // in order, as its as-written samples do: the nearest sample is found by a
  // cursor that only moves forward, O(n) over the program.
  std::size_t m_cur = original.size(), cur = 0;
  for (std::size_t i = 0; i < t.points.size(); ++i) {
    const compensate::Point& p = t.points[i];
    const std::size_t m = parent[p.motion];
    if (first[m] == first[m + 1]) continue;  // no sample as written
    if (m != m_cur) m_cur = m, cur = first[m];
    const V3 design = p.tip_mm - offset_at(p, r.offsets);
    auto d2 = [&](std::size_t j) { return (nominal[j].tip_mm - design).squaredNorm(); };
    while (cur + 1 < first[m + 1] && d2(cur + 1) < d2(cur)) ++cur;  // a tie keeps the earlier, as a full scan would
    const compensate::Point& q = nominal[cur];
    if (!q.air && !q.plunge) t.error_as_written_mm[i] = q.error_mm;
    t.cusp[i] = cusp[cur];
  }
  return t;
}

void write_points_csv(const std::string& path, const PointTable& t) {
  writer::write_file_atomically(path, "", [&](std::ostream& os) {
    TextOut o(os);
    o << "line,x_mm,y_mm,z_mm,path_mm,ap_mm,ae_mm,d_eff_mm,cwe_area_mm2,mrr_mm3_per_s,Fx_N,Fy_N,Fz_N,dx_mm,dy_mm,"
         "dz_mm,surface_error_mm,surface_error_as_written_mm,offset_mm,nx,ny,nz,normal_source,part_gap_mm,"
         "flank_min_mm,flank_max_mm,flank_z_min_mm,flank_z_max_mm,stepover_mm,cusp_height_mm\n";
    // A field: a comma, then the number (nothing where it is not known: air, no neighbouring pass).
    auto f = [&](double v, int decimals) {
      o << ',';
      if (!std::isnan(v)) o.fixed(v, decimals);
    };
    for (std::size_t i = 0; i < t.points.size(); ++i) {
      const compensate::Point& p = t.points[i];
      if (p.air) continue;
      o.integer(p.line);
      for (int k = 0; k < 3; ++k) f(p.tip_mm[k], 4);
      f(t.path_mm[i], 3);
      f(p.ap_mm, 4), f(p.ae_mm, 4), f(p.d_eff_mm, 4), f(p.cwe_area_mm2, 4), f(p.mrr_mm3_per_s, 2);
      for (int k = 0; k < 3; ++k) f(p.force_N[k], 2);
      for (int k = 0; k < 3; ++k) f(p.delta_mm[k], 6);
      f(t.error_mm[i], 6);
      f(t.has_as_written ? t.error_as_written_mm[i] : t.error_mm[i], 6);
      f(t.offset_n_mm[i], 6);
      for (int k = 0; k < 3; ++k) f(p.normal[k], 6);
      o << ',' << compensate::to_string(p.normal_source);
      f(p.normal_source == compensate::NormalSource::part ? p.part_gap_mm : kNone, 6);
      const double on = t.offset_n_mm[i];
      f(p.flank ? on + p.flank_min_mm : kNone, 6), f(p.flank ? on + p.flank_max_mm : kNone, 6);
      f(p.flank ? p.flank_z_min_mm : kNone, 4), f(p.flank ? p.flank_z_max_mm : kNone, 4);
      f(t.cusp[i].stepover_mm, 4), f(t.cusp[i].height_mm, 6);
      o << '\n';
    }
  });
}

bool write_flank_profile_csv(const std::string& path, const std::vector<compensate::Point>& as_written) {
  bool any = false;
  for (const auto& p : as_written) any = any || (!p.air && p.flank && !p.flank_profile.empty());
  if (!any) return false;
  writer::write_file_atomically(path, "", [&](std::ostream& o) {
    o << "line,x_mm,y_mm,z_tip_mm,z_mm,error_mm\n";
    char buf[200];
    for (const auto& p : as_written) {
      if (p.air || !p.flank) continue;
      for (const auto& q : p.flank_profile) {
        std::snprintf(buf, sizeof buf, "%u,%.4f,%.4f,%.4f,%.4f,%.6f\n", p.line, p.tip_mm.x(), p.tip_mm.y(),
                      p.tip_mm.z(), q.z_mm, q.error_mm);
        o << buf;
      }
    }
  });
  return true;
}

}  // namespace deflex::report
