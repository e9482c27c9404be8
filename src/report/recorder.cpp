// The report's rows as the points stream by (include/deflex/report/recorder.hpp).
#include "deflex/report/recorder.hpp"

#include "deflex/compensate/contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "deflex/report/text_out.hpp"
#include "page.hpp"

namespace deflex::report {
namespace {

constexpr std::size_t kNoSample = std::numeric_limits<std::size_t>::max();

// What the rows need of a point as written (or of a simulated point, in
// simulate) once its cusp is known.
struct Source {
  std::uint32_t motion;
  V3 tip_mm;
  bool cutting;
  double error_mm;  // as written (NaN: not cutting)
};

struct Row {
  compensate::Point p;
  V3 offset;
  std::size_t key;  // compensate: the original motion; simulate: the point's own source index
};

// Two samples follow each other on the tool's path when no rapid lies between
// them (same motion, or the next one).
bool continuous(std::uint32_t a, std::uint32_t b) { return b - a <= 1; }

}  // namespace

const char* const kPointsCsvHeader =
    "line,x_mm,y_mm,z_mm,path_mm,ap_mm,ae_mm,d_eff_mm,cwe_area_mm2,mrr_mm3_per_s,Fx_N,Fy_N,Fz_N,dx_mm,dy_mm,"
    "dz_mm,surface_error_mm,surface_error_as_written_mm,offset_mm,nx,ny,nz,normal_source,part_gap_mm,"
    "flank_min_mm,flank_max_mm,flank_z_min_mm,flank_z_max_mm,stepover_mm,cusp_height_mm,power_kW,torque_Nm,ap_limit_mm,"
    "workpiece_dx_mm,workpiece_dy_mm,workpiece_dz_mm\n";

struct Recorder::Impl {
  explicit Impl(RecorderOptions o)
      : opt(std::move(o)),
        cusp(opt.cusp_block),
        err(opt.tolerance_mm, opt.percentiles, opt.spill_dir),
        err_as_written(opt.tolerance_mm, opt.percentiles && opt.as_written, opt.spill_dir) {
    if (opt.page)
      page = std::make_unique<PageSink>(opt.spill_dir, opt.as_written ? 2 : 1, opt.tolerance_mm,
                                        opt.spindle && opt.spindle->set ? opt.spindle : nullptr);
    if (opt.points_csv) *opt.points_csv << kPointsCsvHeader;
    if (opt.flank_csv) *opt.flank_csv << "line,x_mm,y_mm,z_tip_mm,z_mm,error_mm\n";
  }

  // --- the program as written (compensate) or the points themselves (simulate)

  void add_source(const compensate::Point& p) {
    const bool cutting = !p.air && !p.plunge;
    if (opt.as_written && cutting) err_as_written.add(p.error_mm);
    flank_rows(p);
    if (!opt.cusp) return;
    process::CuspSample c;
    c.tip_mm = p.tip_mm;
    c.normal = p.normal;
    c.normal_known = p.normal_source != compensate::NormalSource::undetermined;
    c.cutting = cutting;
    const stiffness::Tool* t = tool(p.tool);
    if (t && t->type == stock::EndShape::ball) c.profile_diameter_mm = t->diameter_mm;
    // The direction of travel: a central difference where both neighbours
    // continue the path, so a sample waits for the next.
    if (have_pending) push_pending(continuous(pending_motion, p.motion) ? &p.tip_mm : nullptr);
    pending = c;
    pending_motion = p.motion;
    have_pending = true;
    sources.push_back({p.motion, p.tip_mm, cutting, cutting ? p.error_mm : kNone});
  }

  void push_pending(const V3* ahead) {
    const V3 back = have_back ? back_tip : pending.tip_mm;
    pending.feed_dir = (ahead ? *ahead : pending.tip_mm) - back;
    have_back = ahead != nullptr;
    back_tip = pending.tip_mm;
    cusp.add(pending);
    have_pending = false;
  }

  void end_sources() {
    if (have_pending) push_pending(nullptr);
    cusp.finish();
    sources_done = true;
  }

  const Source& source(std::size_t i) const { return sources[i - sources_base]; }
  std::size_t source_end() const { return sources_base + sources.size(); }

  // --- the rows

  void add_row(const compensate::Point& p, const V3& offset, std::size_t original) {
    if (!opt.cusp) {  // the figures only: no row waits, nothing is copied
      write_row(p, offset, kNoSample);
      return;
    }
    if (!opt.as_written) {
      add_source(p);
      original = source_end() - 1;
    }
    rows.push_back({p, offset, original});
  }

  // Writes the rows whose sample as written and cusp are known.
  void drain() {
    while (!rows.empty()) {
      Row& r = rows.front();
      std::size_t q = kNoSample;
      if (!opt.as_written) {
        if (cusp.ready() <= r.key) break;
        q = r.key;
        cursor = q;
      } else {
        if (!range_of(r.key)) break;
        if (range_end > cusp.ready()) break;
        q = nearest(r);
      }
      write_row(r.p, r.offset, q);
      rows.pop_front();
    }
    // The samples before the cursor are not asked for again.
    const std::size_t keep = std::min(cursor, cusp.ready());
    cusp.forget_before(keep);
    while (sources_base < keep && !sources.empty()) {
      sources.pop_front();
      ++sources_base;
    }
  }

  // The samples as written of original motion m: [range_first, range_end);
  // false while they may still come. The scan goes on where it stopped.
  bool range_of(std::size_t m) {
    if (have_range && range_motion == m) return true;
    if (!scanning || scan_motion != m) {
      scanning = true;
      scan_motion = m;
      scan_first = scan_end = std::max(have_range ? range_end : 0, sources_base);
    }
    while (scan_first == scan_end && scan_first < source_end() && source(scan_first).motion < m) scan_end = ++scan_first;
    while (scan_end < source_end() && source(scan_end).motion == m) ++scan_end;
    if (scan_end == source_end() && !sources_done) return false;
    scanning = false;
    have_range = true;
    range_motion = m;
    range_first = cursor = scan_first;
    range_end = scan_end;
    return true;
  }

  // The sample of the range nearest to the row's design point, by a cursor
  // that only moves forward (the points of one original move, its inserted
  // pieces first, run along it in order, as its samples as written do); a tie
  // keeps the earlier, as a full scan would.
  std::size_t nearest(const Row& r) {
    if (range_first == range_end) return kNoSample;
    const V3 design = r.p.tip_mm - r.offset;
    auto d2 = [&](std::size_t j) { return (source(j).tip_mm - design).squaredNorm(); };
    while (cursor + 1 < range_end && d2(cursor + 1) < d2(cursor)) ++cursor;
    return cursor;
  }

  void write_row(const compensate::Point& p, const V3& offset, std::size_t q) {
    if (have_last) path_mm += continuous(last_motion, p.motion) ? (p.tip_mm - last_tip).norm() : 0.0;
    have_last = true;
    last_motion = p.motion;
    last_tip = p.tip_mm;
    const double error = p.air ? kNone : compensate::landing_error(p, offset);
    double as_written = error;
    process::CuspResult c;
    if (q != kNoSample) {
      c = cusp.result(q);
      if (opt.as_written) as_written = source(q).error_mm;
    } else if (opt.as_written) {
      as_written = kNone;  // no sample as written on its move (or no pairing asked for)
    }
    const double offset_n = offset.dot(p.normal);
    if ((opt.points_csv || opt.rows) && !p.air) csv_row(p, error, as_written, offset_n, c);
    if (p.air || p.plunge) return;
    err.add(error);
    const interp::Fixed why =
        p.normal_source == compensate::NormalSource::undetermined ? interp::Fixed::no_normal : p.fixed;
    if (why != interp::Fixed::no && std::fabs(error) > opt.tolerance_mm) {
      RunFigures::LeftAlone& l = left_alone[why];
      if (!l.points++) l.first_line = p.line;
      l.largest_mm = std::max(l.largest_mm, std::fabs(error));
    }
    cusp_stats.add(c.height_mm);
    ++cutting;
    const double f = p.force_N.norm();
    peak_force_N = std::max(peak_force_N, p.peak_N);
    force_sum += f;
    peak_deflection_mm = std::max(peak_deflection_mm, p.delta_mm.norm());
    if (opt.workpiece) {
      const double w = -p.workpiece_delta_mm.dot(p.normal);
      keep_larger(workpiece_share, w, p.line);
      keep_larger(tool_share, p.error_mm - w, p.line);
    }
    peak_mrr = std::max(peak_mrr, p.mrr_mm3_per_s);
    peak_power_kW = std::max(peak_power_kW, p.power_kW);
    peak_torque_Nm = std::max(peak_torque_Nm, p.torque_Nm);
    if (p.ap_limit_mm > 0) {
      ++stability_checked;
      const double ratio = p.ap_mm / p.ap_limit_mm;
      worst_ap_over_limit = std::max(worst_ap_over_limit, ratio);
      above_limit += ratio > 1;
    }
    d_eff_sum += p.d_eff_mm;
    area_sum += p.cwe_area_mm2;
    if (page) page->add(p, contact(p), path_mm, error, as_written, c);
  }

  static void keep_larger(RunFigures::Share& s, double v_mm, std::uint32_t line) {
    if (std::fabs(v_mm) > std::fabs(s.largest_mm)) s.largest_mm = v_mm, s.line = line;
  }

  void csv_row(const compensate::Point& p, double error, double as_written, double on, const process::CuspResult& c) {
    PointRow r;
    r.line = p.line;
    r.tip_mm = p.tip_mm;
    r.path_mm = path_mm;
    r.ap_mm = p.ap_mm, r.ae_mm = p.ae_mm, r.d_eff_mm = p.d_eff_mm, r.cwe_area_mm2 = p.cwe_area_mm2;
    r.mrr_mm3_per_s = p.mrr_mm3_per_s;
    r.force_N = p.force_N, r.delta_mm = p.delta_mm;
    r.surface_error_mm = error, r.surface_error_as_written_mm = as_written, r.offset_mm = on;
    r.normal = p.normal;
    r.normal_source = compensate::to_string(p.normal_source);
    if (p.normal_source == compensate::NormalSource::part) r.part_gap_mm = p.part_gap_mm;
    if (p.flank) {
      r.flank_min_mm = on + p.flank_min_mm, r.flank_max_mm = on + p.flank_max_mm;
      r.flank_z_min_mm = p.flank_z_min_mm, r.flank_z_max_mm = p.flank_z_max_mm;
    }
    r.stepover_mm = c.stepover_mm, r.cusp_height_mm = c.height_mm;
    r.power_kW = p.power_kW, r.torque_Nm = p.torque_Nm;
    if (p.ap_limit_mm > 0) r.ap_limit_mm = p.ap_limit_mm;
    if (opt.workpiece) r.workpiece_delta_mm = p.workpiece_delta_mm;
    if (opt.rows) opt.rows(r);
    if (opt.points_csv) write_csv(r);
  }

  void write_csv(const PointRow& r) {
    TextOut o(*opt.points_csv);
    auto f = [&](double v, int decimals) {
      o << ',';
      if (!std::isnan(v)) o.fixed(v, decimals);
    };
    o.integer(r.line);
    for (int k = 0; k < 3; ++k) f(r.tip_mm[k], 4);
    f(r.path_mm, 3);
    f(r.ap_mm, 4), f(r.ae_mm, 4), f(r.d_eff_mm, 4), f(r.cwe_area_mm2, 4), f(r.mrr_mm3_per_s, 2);
    for (int k = 0; k < 3; ++k) f(r.force_N[k], 2);
    for (int k = 0; k < 3; ++k) f(r.delta_mm[k], 6);
    f(r.surface_error_mm, 6);
    f(r.surface_error_as_written_mm, 6);
    f(r.offset_mm, 6);
    for (int k = 0; k < 3; ++k) f(r.normal[k], 6);
    o << ',' << r.normal_source;
    f(r.part_gap_mm, 6);
    f(r.flank_min_mm, 6), f(r.flank_max_mm, 6);
    f(r.flank_z_min_mm, 4), f(r.flank_z_max_mm, 4);
    f(r.stepover_mm, 4), f(r.cusp_height_mm, 6);
    f(r.power_kW, 4), f(r.torque_Nm, 3);
    f(r.ap_limit_mm, 4);
    for (int k = 0; k < 3; ++k) f(r.workpiece_delta_mm[k], 6);
    o << '\n';
  }

  void flank_rows(const compensate::Point& p) {
    if (!opt.flank_csv || p.air || !p.flank) return;
    char buf[200];
    for (const auto& fp : p.flank_profile) {
      std::snprintf(buf, sizeof buf, "%u,%.4f,%.4f,%.4f,%.4f,%.6f\n", p.line, p.tip_mm.x(), p.tip_mm.y(), p.tip_mm.z(),
                    fp.z_mm, fp.error_mm);
      *opt.flank_csv << buf;
      any_flank = true;
    }
  }

  const stiffness::Tool* tool(int t) {
    if (!opt.tool_of) return nullptr;
    if (!have_tool || t != tool_number) {
      tool_number = t;
      tool_ptr = opt.tool_of(t);
      have_tool = true;
    }
    return tool_ptr;
  }

  // Where the cutter touches the design surface (compensate/contact.hpp).
  V3 contact(const compensate::Point& p) {
    const stiffness::Tool* t = tool(p.tool);
    return t ? compensate::contact_point(p, *t) : p.tip_mm;
  }

  RunFigures figures() {
    RunFigures f;
    f.error = err.stats();
    f.error_as_written = opt.as_written ? err_as_written.stats() : f.error;
    f.cusp = cusp_stats.stats();
    f.peak_force_N = peak_force_N;
    f.peak_deflection_mm = peak_deflection_mm;
    f.workpiece_share = workpiece_share;
    f.tool_share = tool_share;
    f.peak_mrr_mm3_per_s = peak_mrr;
    f.peak_power_kW = peak_power_kW;
    f.peak_torque_Nm = peak_torque_Nm;
    f.worst_ap_over_limit = worst_ap_over_limit;
    f.above_limit = above_limit;
    f.stability_checked = stability_checked;
    if (cutting) {
      const double n = static_cast<double>(cutting);
      f.mean_force_N = force_sum / n;
      f.mean_d_eff_mm = d_eff_sum / n;
      f.mean_area_mm2 = area_sum / n;
    }
    f.flank_rows = any_flank;
    f.left_alone = left_alone;
    return f;
  }

  RecorderOptions opt;
  process::CuspStream cusp;
  // The sample waiting for the next (its direction of travel) and the one before it.
  process::CuspSample pending;
  std::uint32_t pending_motion = 0;
  bool have_pending = false, have_back = false;
  V3 back_tip = V3::Zero();
  std::deque<Source> sources;
  std::size_t sources_base = 0;
  bool sources_done = false;
  std::deque<Row> rows;
  // The pairing: the range of the current original motion, the cursor in it,
  // and the scan for the next one while its samples still come.
  bool have_range = false, scanning = false;
  std::size_t range_motion = 0, range_first = 0, range_end = 0, cursor = 0;
  std::size_t scan_motion = 0, scan_first = 0, scan_end = 0;
  // The path length so far.
  bool have_last = false;
  std::uint32_t last_motion = 0;
  V3 last_tip = V3::Zero();
  double path_mm = 0;
  // Figures.
  ErrorAccumulator err, err_as_written;
  ValueAccumulator cusp_stats;
  std::size_t cutting = 0;
  double peak_force_N = 0, force_sum = 0, peak_deflection_mm = 0, peak_mrr = 0, d_eff_sum = 0, area_sum = 0;
  double peak_power_kW = 0, peak_torque_Nm = 0, worst_ap_over_limit = 0;
  RunFigures::Share workpiece_share, tool_share;
  std::size_t above_limit = 0, stability_checked = 0;
  bool any_flank = false;
  std::map<interp::Fixed, RunFigures::LeftAlone> left_alone;
  std::unique_ptr<PageSink> page;
  // The tool of the last T number asked.
  bool have_tool = false;
  int tool_number = 0;
  const stiffness::Tool* tool_ptr = nullptr;
};

Recorder::Recorder(RecorderOptions o) : impl_(std::make_unique<Impl>(std::move(o))) {}
Recorder::~Recorder() = default;

void Recorder::as_written(const compensate::Point& p) {
  std::lock_guard<std::mutex> lock(mutex_);
  impl_->add_source(p);
  impl_->drain();
}

void Recorder::point(const compensate::Point& p, const V3& offset, std::size_t original) {
  std::lock_guard<std::mutex> lock(mutex_);
  impl_->add_row(p, offset, original);
  impl_->drain();
}

RunFigures Recorder::finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  impl_->end_sources();
  impl_->drain();
  if (!impl_->rows.empty()) throw Error(ErrorKind::internal, "report: rows left without their samples as written");
  return impl_->figures();
}

Page Recorder::page() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!impl_->page) throw Error(ErrorKind::internal, "report: no page was kept");
  return impl_->page->finish(impl_->cusp_stats.stats());
}

}  // namespace deflex::report
