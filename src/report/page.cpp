// What report.html draws, from the rows kept on disk (src/report/page.hpp).
#include "page.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace deflex::report {
namespace {


Json num_or_null(double v, int decimals) { return std::isnan(v) ? Json() : Json(fixed(v, decimals)); }

// The plots' series along the program, in the order of PageSink::Rec::series.
// P and M: the spindle's power and torque; P_S1 and M_S1 what its S1 curve
// allows at the point's speed (NaN without a rating). ap_lim: the stability
// limit (NaN where not checked).
const char* const kSeries[kSeriesCount] = {"F",    "Fx",   "Fy", "Fz", "delta", "ap",  "ae",
                                           "mrr",  "deff", "area", "cusp", "P", "P_S1", "M", "M_S1", "ap_lim"};

// One pass of gap filling: an empty cell enclosed by filled ones - two on
// opposite sides (across a row, a column or a diagonal), or five of its eight
// neighbours - takes the value of largest magnitude among them per map and
// their mean height. Steep walls move the contact points of a pass sideways and
// leave such holes inside a part; the outside of a part is not enclosed and
// stays "no data".
void fill_gaps(Grid& g) {
  const std::vector<double> z0 = g.z_mm;
  const std::vector<std::vector<double>> v0 = g.values;
  auto filled = [&](int i, int j) {
    return i >= 0 && j >= 0 && i < g.nx && j < g.ny && !std::isnan(z0[static_cast<std::size_t>(j) * g.nx + i]);
  };
  static const int kDir[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * g.nx + i;
      if (!std::isnan(z0[c])) continue;
      bool enclosed = false;
      for (const auto& d : kDir) enclosed = enclosed || (filled(i + d[0], j + d[1]) && filled(i - d[0], j - d[1]));
      int n = 0;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) n += (di || dj) && filled(i + di, j + dj);
      if (!enclosed && n < 5) continue;
      double zs = 0;
      int zn = 0;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          if (!(di || dj) || !filled(i + di, j + dj)) continue;
          const std::size_t k = static_cast<std::size_t>(j + dj) * g.nx + (i + di);
          zs += z0[k];
          ++zn;
          for (std::size_t m = 0; m < g.values.size(); ++m) {
            const double v = v0[m][k];
            double& cell = g.values[m][c];
            if (!std::isnan(v) && (std::isnan(cell) || std::fabs(v) > std::fabs(cell))) cell = v;
          }
        }
      g.z_mm[c] = zs / zn;
    }
}

}  // namespace

GridBuilder::GridBuilder(double x0, double y0, double x1, double y1, std::size_t maps, double min_cell_mm,
                         int max_cells)
    : empty_(!(x0 <= x1 && y0 <= y1)) {
  g_.values.assign(maps, {});
  if (empty_) return;
  const double span = std::max({x1 - x0, y1 - y0, 1e-3});
  g_.cell_mm = std::max(span / max_cells, std::isfinite(min_cell_mm) ? min_cell_mm : 0.0);
  g_.nx = std::clamp(static_cast<int>(std::ceil((x1 - x0) / g_.cell_mm + 1e-9)), 1, max_cells);
  g_.ny = std::clamp(static_cast<int>(std::ceil((y1 - y0) / g_.cell_mm + 1e-9)), 1, max_cells);
  g_.cell_mm = std::max(g_.cell_mm, std::max((x1 - x0) / g_.nx, (y1 - y0) / g_.ny));
  // Centre the grid on the points' extent.
  g_.x0_mm = (x0 + x1) / 2 - g_.nx * g_.cell_mm / 2;
  g_.y0_mm = (y0 + y1) / 2 - g_.ny * g_.cell_mm / 2;
  const std::size_t cells = static_cast<std::size_t>(g_.nx) * static_cast<std::size_t>(g_.ny);
  zsum_.assign(cells, 0.0);
  zn_.assign(cells, 0.0);
  for (auto& v : g_.values) v.assign(cells, kNone);
}

void GridBuilder::add(const Eigen::Vector3d& xyz, const double* values) {
  if (empty_) return;
  const int cx = std::clamp(static_cast<int>((xyz.x() - g_.x0_mm) / g_.cell_mm), 0, g_.nx - 1);
  const int cy = std::clamp(static_cast<int>((xyz.y() - g_.y0_mm) / g_.cell_mm), 0, g_.ny - 1);
  const std::size_t c = static_cast<std::size_t>(cy) * g_.nx + cx;
  zsum_[c] += xyz.z();
  zn_[c] += 1;
  for (std::size_t m = 0; m < g_.values.size(); ++m) {
    const double v = values[m];
    double& cell = g_.values[m][c];
    if (!std::isnan(v) && (std::isnan(cell) || std::fabs(v) > std::fabs(cell))) cell = v;
  }
}

Grid GridBuilder::finish() {
  if (empty_) {
    g_.z_mm.assign(1, kNone);
    for (auto& v : g_.values) v.assign(1, kNone);
    return g_;
  }
  g_.z_mm.assign(zsum_.size(), kNone);
  for (std::size_t c = 0; c < zsum_.size(); ++c)
    if (zn_[c] > 0) g_.z_mm[c] = zsum_[c] / zn_[c];
  fill_gaps(g_);
  fill_gaps(g_);
  return g_;
}

Grid make_grid(const std::vector<Eigen::Vector3d>& xyz, const std::vector<const std::vector<double>*>& values,
               double min_cell_mm, int max_cells) {
  auto used = [&](std::size_t i) {
    bool any = false;
    for (const auto* v : values) any = any || !std::isnan((*v)[i]);
    return any;
  };
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    if (!used(i)) continue;
    x0 = std::min(x0, xyz[i].x()), x1 = std::max(x1, xyz[i].x());
    y0 = std::min(y0, xyz[i].y()), y1 = std::max(y1, xyz[i].y());
  }
  GridBuilder b(x0, y0, x1, y1, values.size(), min_cell_mm, max_cells);
  std::vector<double> v(values.size());
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    if (!used(i)) continue;
    for (std::size_t m = 0; m < values.size(); ++m) v[m] = (*values[m])[i];
    b.add(xyz[i], v.data());
  }
  return b.finish();
}

PageSink::PageSink(const std::string& spill_dir, int maps, double tolerance_mm, const profile::SpindleRating* spindle)
    : spill_(spill_dir), maps_(maps), tol_(tolerance_mm), spindle_(spindle) {}

void PageSink::add(const compensate::Point& p, const V3& contact, double path_mm, double error, double as_written,
                   const process::CuspResult& c) {
  Rec r{};
  r.e[0] = maps_ == 2 ? as_written : error;
  r.e[1] = maps_ == 2 ? error : kNone;
  r.path_mm = path_mm;
  for (int k = 0; k < 3; ++k) r.contact_mm[k] = static_cast<float>(contact[k]);
  const double allowed_Nm = spindle_ && p.spindle_rpm > 0 ? spindle_->s1.allowed_torque_Nm(p.spindle_rpm) : kNone;
  const double s[kSeriesCount] = {p.force_N.norm(), p.force_N.x(), p.force_N.y(), p.force_N.z(), 1000 * p.delta_mm.norm(),
                                  p.ap_mm, p.ae_mm, p.mrr_mm3_per_s, p.d_eff_mm, p.cwe_area_mm2, 1000 * c.height_mm,
                                  p.power_kW, profile::power_from_torque_kW(allowed_Nm, p.spindle_rpm),
                                  p.torque_Nm, allowed_Nm, p.ap_limit_mm > 0 ? p.ap_limit_mm : kNone};
  for (std::size_t k = 0; k < kSeriesCount; ++k) r.series[k] = static_cast<float>(s[k]);
  r.stepover_mm = static_cast<float>(c.stepover_mm);
  r.cusp_mm = static_cast<float>(c.height_mm);
  r.line = p.line;
  spill_.push_back(r);
  x0_ = std::min(x0_, contact.x()), x1_ = std::max(x1_, contact.x());
  y0_ = std::min(y0_, contact.y()), y1_ = std::max(y1_, contact.y());
  for (int m = 0; m < maps_; ++m)
    if (!std::isnan(r.e[m])) max_abs_ = std::max(max_abs_, std::fabs(r.e[m]));
  if (!std::isnan(c.height_mm)) cusp_max_ = std::max(cusp_max_, c.height_mm);
  if (!std::isnan(r.stepover_mm)) {
    ++steps_;
    step_lo_ = std::min(step_lo_, static_cast<double>(r.stepover_mm));
    step_hi_ = std::max(step_hi_, static_cast<double>(r.stepover_mm));
  }
  const double last = r.e[maps_ - 1];
  if (std::isnan(last)) return;
  std::array<double, 3> vals{kNone, kNone, kNone};
  for (int m = maps_, k = 0; m-- > 0;) vals[static_cast<std::size_t>(k++)] = r.e[m];
  vals[static_cast<std::size_t>(maps_)] = c.height_mm;
  worst_add(p.line, std::fabs(last), vals);
}

void PageSink::worst_add(std::uint32_t line, double key, const std::array<double, 3>& values) {
  auto same = std::find_if(worst_.begin(), worst_.end(), [&](const Worst& w) { return w.line == line; });
  if (same != worst_.end()) {
    if (key > same->key) *same = {line, key, values};
    return;
  }
  if (worst_.size() < 20) {
    worst_.push_back({line, key, values});
    return;
  }
  auto least = std::min_element(worst_.begin(), worst_.end(), [](const Worst& a, const Worst& b) { return a.key < b.key; });
  if (key > least->key) *least = {line, key, values};
}

namespace {

using MapNames = std::vector<std::pair<std::string, std::string>>;

// The plots: buckets of `per` rows, each the first row's path length, the
// line of the row of largest |e| of the last map, and per series the value
// of largest magnitude.
struct Plots {
  static constexpr std::size_t kBuckets = 4000;
  int maps;
  std::size_t per, cols;
  Json x = Json::array(), lines = Json::array();
  std::vector<Json> out;
  std::vector<double> best;
  std::uint32_t worst_line = 0;
  std::size_t in_bucket = 0;

  Plots(std::size_t rows, int map_count)
      : maps(map_count), per(std::max<std::size_t>(1, (rows + kBuckets - 1) / kBuckets)),
        cols(kSeriesCount + static_cast<std::size_t>(map_count)), out(cols, Json::array()), best(cols, kNone) {}
  // Keeps `val` in column c when of larger magnitude; true if kept.
  bool pick(std::size_t c, double val) {
    if (std::isnan(val) || !(std::isnan(best[c]) || std::fabs(val) > std::fabs(best[c]))) return false;
    best[c] = val;
    return true;
  }
  // A row: its path length, line, series (kSeries) and errors (maps).
  void add(double path_mm, std::uint32_t line, const float* series, const double* e) {
    if (in_bucket == 0) {
      x.push_back(fixed(path_mm, 3));
      worst_line = line;
    }
    for (std::size_t c = 0; c < kSeriesCount; ++c) pick(c, series[c]);
    for (int m = 0; m < maps; ++m) {
      const bool worse = pick(kSeriesCount + static_cast<std::size_t>(m), 1000 * e[m]);
      if (worse && m == maps - 1) worst_line = line;
    }
    if (++in_bucket == per) close();
  }
  void close() {
    for (std::size_t c = 0; c < cols; ++c) out[c].push_back(num_or_null(best[c], c < kSeriesCount ? 4 : 3));
    lines.push_back(worst_line);
    std::fill(best.begin(), best.end(), kNone);
    in_bucket = 0;
  }
  Json json(std::size_t rows) {
    Json j = {{"points", rows}, {"per_bucket", per}, {"x", std::move(x)}, {"line", std::move(lines)}};
    for (std::size_t c = 0; c < kSeriesCount; ++c) j[kSeries[c]] = std::move(out[c]);
    for (int m = 0; m < maps; ++m) j["e" + std::to_string(m)] = std::move(out[kSeriesCount + static_cast<std::size_t>(m)]);
    return j;
  }
};

// The histogram of each map over +-scale, in percent of the map's rows.
struct Histogram {
  static constexpr int bins = 60;
  double scale_mm, w;
  std::vector<std::vector<double>> hist;
  std::vector<double> hist_n;

  Histogram(int maps, double scale)
      : scale_mm(scale), w(2 * scale / bins),
        hist(static_cast<std::size_t>(maps), std::vector<double>(bins, 0.0)),
        hist_n(static_cast<std::size_t>(maps), 0.0) {}
  void add(int m, double e) {
    if (std::isnan(e)) return;
    const int b = std::clamp(static_cast<int>(std::floor((e + scale_mm) / w)), 0, bins - 1);
    hist[static_cast<std::size_t>(m)][static_cast<std::size_t>(b)] += 1;
    hist_n[static_cast<std::size_t>(m)] += 1;
  }
  Json json(const MapNames& maps) const {
    Json edges = Json::array(), counts = Json::object();
    for (int b = 0; b < bins; ++b) edges.push_back(fixed(1000 * (-scale_mm + b * w), 3));
    for (std::size_t m = 0; m < hist.size(); ++m) {
      Json a = Json::array();
      const double hn = hist_n[m];
      for (double c : hist[m]) a.push_back(fixed(hn > 0 ? 100 * c / hn : 0.0, 3));
      counts[maps[m].first] = std::move(a);
    }
    return {{"edges_um", std::move(edges)}, {"bin_um", 1000 * w}, {"counts", std::move(counts)}};
  }
};

}  // namespace

// The grid's cell: at least the median step-over, so passes leave no stripes.
double PageSink::grid_cell_mm() {
  if (!steps_) return 0;
  return 1.05 * kth_value(
                    [&](const std::function<void(double)>& f) {
                      spill_.each([&](const Rec& r) {
                        if (!std::isnan(r.stepover_mm)) f(r.stepover_mm);
                      });
                    },
                    steps_, steps_ / 2, step_lo_, step_hi_);
}

// The worst lines, worst first (equal ones by line).
Json PageSink::worst_table(const MapNames& maps) {
  std::sort(worst_.begin(), worst_.end(),
            [](const Worst& a, const Worst& b) { return a.key != b.key ? a.key > b.key : a.line < b.line; });
  Json wcols = Json::array(), rows = Json::array();
  for (int m = maps_; m-- > 0;) wcols.push_back("e " + maps[static_cast<std::size_t>(m)].second + ", µm");
  wcols.push_back("cusp, µm");
  for (const Worst& wr : worst_) {
    Json vals = Json::array();
    for (int k = 0; k <= maps_; ++k) vals.push_back(num_or_null(wr.values[static_cast<std::size_t>(k)], 6));
    rows.push_back({{"line", wr.line}, {"values", std::move(vals)}, {"text", ""}});
  }
  return {{"columns", std::move(wcols)}, {"rows", std::move(rows)}};
}

Page PageSink::finish(const ValueStats& cusp) {
  Page pg;
  if (maps_ == 2) pg.maps = {{"surface_error_as_written_mm", "as written"}, {"surface_error_mm", "compensated"}};
  else pg.maps = {{"surface_error_mm", "predicted"}};
  pg.scale_mm = std::max(2 * tol_, max_abs_);
  pg.cusp = cusp;
  pg.cusp_max_mm = cusp_max_;
  const std::size_t n = spill_.size();
  GridBuilder gb(x0_, y0_, x1_, y1_, static_cast<std::size_t>(maps_) + 1, grid_cell_mm());
  Plots plots(n, maps_);
  Histogram hist(maps_, pg.scale_mm);
  // One pass over the rows on disk feeds the grid, the plots and the histogram.
  spill_.each([&](const Rec& r) {
    double v[3];
    for (int m = 0; m < maps_; ++m) v[m] = r.e[m];
    v[maps_] = r.cusp_mm;
    gb.add(V3(r.contact_mm[0], r.contact_mm[1], r.contact_mm[2]), v);
    plots.add(r.path_mm, r.line, r.series, r.e);
    for (int m = 0; m < maps_; ++m) hist.add(m, r.e[m]);
  });
  if (plots.in_bucket) plots.close();
  pg.grid = gb.finish();
  pg.series = plots.json(n);
  pg.histogram = hist.json(pg.maps);
  pg.worst = worst_table(pg.maps);
  return pg;
}

}  // namespace deflex::report
