// report.html (include/deflex/report/html.hpp).
#include "deflex/report/html.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "deflex/report/stats.hpp"
#include "deflex/stiffness/tool.hpp"

namespace deflex::embedded {
const std::string& report_page();
const std::string& three_js();
const std::string& orbit_controls_js();
const std::string& dygraphs_js();
const std::string& dygraphs_css();
}  // namespace deflex::embedded

namespace deflex::report {
namespace {

Json num_or_null(double v, int decimals) { return std::isnan(v) ? Json() : Json(fixed(v, decimals)); }

struct MapSpec {
  std::string key, title;
  std::vector<double> values;  // per point; NaN where not drawn
};

std::vector<MapSpec> maps_of(const PointTable& t) {
  auto masked = [&](const std::vector<double>& v) {
    std::vector<double> m(v.size(), kNone);
    for (std::size_t i = 0; i < v.size(); ++i)
      if (t.cutting(i)) m[i] = v[i];
    return m;
  };
  if (t.has_as_written)
    return {{"surface_error_as_written_mm", "as written", masked(t.error_as_written_mm)},
            {"surface_error_mm", "compensated", masked(t.error_mm)}};
  return {{"surface_error_mm", "predicted", masked(t.error_mm)}};
}

// Series along the program, decimated to at most `buckets` rows: each row the
// first point's path length, the line of the point of largest |e| of the last
// map, and per series the value of largest magnitude in the bucket.
Json series_json(const PointTable& t, const std::vector<MapSpec>& maps, std::size_t buckets) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < t.points.size(); ++i)
    if (t.cutting(i)) idx.push_back(i);
  using Get = double (*)(const PointTable&, std::size_t);
  const std::vector<std::pair<std::string, Get>> cols = {
      {"F", [](const PointTable& t, std::size_t i) { return t.points[i].force_N.norm(); }},
      {"Fx", [](const PointTable& t, std::size_t i) { return t.points[i].force_N.x(); }},
      {"Fy", [](const PointTable& t, std::size_t i) { return t.points[i].force_N.y(); }},
      {"Fz", [](const PointTable& t, std::size_t i) { return t.points[i].force_N.z(); }},
      {"delta", [](const PointTable& t, std::size_t i) { return 1000 * t.points[i].delta_mm.norm(); }},
      {"ap", [](const PointTable& t, std::size_t i) { return t.points[i].ap_mm; }},
      {"ae", [](const PointTable& t, std::size_t i) { return t.points[i].ae_mm; }},
      {"mrr", [](const PointTable& t, std::size_t i) { return t.points[i].mrr_mm3_per_s; }},
      {"deff", [](const PointTable& t, std::size_t i) { return t.points[i].d_eff_mm; }},
      {"area", [](const PointTable& t, std::size_t i) { return t.points[i].cwe_area_mm2; }},
      {"cusp", [](const PointTable& t, std::size_t i) { return 1000 * t.cusp[i].height_mm; }},
  };
  const std::size_t per = std::max<std::size_t>(1, (idx.size() + buckets - 1) / std::max<std::size_t>(1, buckets));
  Json x = Json::array(), line = Json::array();
  std::vector<Json> out(cols.size() + maps.size(), Json::array());
  for (std::size_t b = 0; b < idx.size(); b += per) {
    const std::size_t e = std::min(idx.size(), b + per);
    x.push_back(fixed(t.path_mm[idx[b]], 3));
    auto pick = [&](auto get) {
      double best = kNone;
      std::size_t at = idx[b];
      for (std::size_t k = b; k < e; ++k) {
        const double v = get(idx[k]);
        if (!std::isnan(v) && (std::isnan(best) || std::fabs(v) > std::fabs(best))) { best = v; at = idx[k]; }
      }
      return std::pair(best, at);
    };
    for (std::size_t c = 0; c < cols.size(); ++c)
      out[c].push_back(num_or_null(pick([&](std::size_t i) { return cols[c].second(t, i); }).first, 4));
    std::size_t worst_at = idx[b];
    for (std::size_t m = 0; m < maps.size(); ++m) {
      const auto [v, at] = pick([&](std::size_t i) { return 1000 * maps[m].values[i]; });
      out[cols.size() + m].push_back(num_or_null(v, 3));
      worst_at = at;
    }
    line.push_back(t.points[worst_at].line);
  }
  Json s{{"points", idx.size()}, {"per_bucket", per}, {"x", std::move(x)}, {"line", std::move(line)}};
  for (std::size_t c = 0; c < cols.size(); ++c) s[cols[c].first] = std::move(out[c]);
  for (std::size_t m = 0; m < maps.size(); ++m) s["e" + std::to_string(m)] = std::move(out[cols.size() + m]);
  return s;
}

Json plots_json(const std::vector<MapSpec>& maps) {
  Json errs = Json::array(), labels = Json::array();
  for (std::size_t m = 0; m < maps.size(); ++m) {
    errs.push_back("e" + std::to_string(m));
    labels.push_back("e " + maps[m].title + ", µm");
  }
  auto plot = [](const char* title, const char* unit, Json labels, Json series) {
    return Json{{"title", title}, {"unit", unit}, {"labels", std::move(labels)}, {"series", std::move(series)}};
  };
  return Json::array({
      plot("surface error along the normal", "e, µm", labels, errs),
      plot("cutting force on the tool (mean over a revolution, machine axes)", "N", {"|F|", "Fx", "Fy", "Fz"},
           {"F", "Fx", "Fy", "Fz"}),
      plot("deflection of tool + holder + spindle + machine", "|δ|, µm", {"|δ|"}, {"delta"}),
      plot("depth and width of cut", "mm", {"a_p", "a_e"}, {"ap", "ae"}),
      plot("material removal rate (Bagci Eq. 1)", "mm³/s", {"MRR"}, {"mrr"}),
      plot("effective diameter (Bagci Eq. 2) and engaged area", "mm, mm²", {"D_eff, mm", "area, mm²"},
           {"deff", "area"}),
      plot("cusp height (Mikó Eq. 7)", "µm", {"cusp"}, {"cusp"}),
  });
}

Json histogram_json(const std::vector<MapSpec>& maps, double scale_mm) {
  const int bins = 60;
  const double w = 2 * scale_mm / bins;
  Json edges = Json::array(), counts = Json::object();
  for (int b = 0; b < bins; ++b) edges.push_back(fixed(1000 * (-scale_mm + b * w), 3));
  for (const MapSpec& m : maps) {
    std::vector<double> c(bins, 0.0);
    double n = 0;
    for (double v : m.values) {
      if (std::isnan(v)) continue;
      c[static_cast<std::size_t>(std::clamp(static_cast<int>(std::floor((v + scale_mm) / w)), 0, bins - 1))] += 1;
      n += 1;
    }
    Json a = Json::array();
    for (double x : c) a.push_back(fixed(n > 0 ? 100 * x / n : 0.0, 3));
    counts[m.key] = std::move(a);
  }
  return {{"edges_um", std::move(edges)}, {"bin_um", 1000 * w}, {"counts", std::move(counts)}};
}

// The 20 lines whose worst point (last map) is worst, with the other maps and
// the cusp at that point, and the line's text.
Json worst_json(const PointTable& t, const std::vector<MapSpec>& maps, const SourceText* src) {
  std::map<std::uint32_t, std::size_t> worst;  // line -> point
  const std::vector<double>& last = maps.back().values;
  for (std::size_t i = 0; i < last.size(); ++i) {
    if (std::isnan(last[i])) continue;
    auto [it, fresh] = worst.try_emplace(t.points[i].line, i);
    if (!fresh && std::fabs(last[i]) > std::fabs(last[it->second])) it->second = i;
  }
  std::vector<std::pair<std::uint32_t, std::size_t>> v(worst.begin(), worst.end());
  const std::size_t n = std::min<std::size_t>(20, v.size());
  std::partial_sort(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n), v.end(),
                    [&](const auto& a, const auto& b) { return std::fabs(last[a.second]) > std::fabs(last[b.second]); });
  Json cols = Json::array(), rows = Json::array();
  for (auto it = maps.rbegin(); it != maps.rend(); ++it) cols.push_back("e " + it->title + ", µm");
  cols.push_back("cusp, µm");
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = v[k].second;
    Json vals = Json::array();
    for (auto it = maps.rbegin(); it != maps.rend(); ++it) vals.push_back(num_or_null(it->values[i], 6));
    vals.push_back(num_or_null(t.cusp[i].height_mm, 6));
    std::string text;
    if (src && v[k].first >= 1 && v[k].first <= src->line_count()) text = std::string(src->line_text(v[k].first));
    rows.push_back({{"line", v[k].first}, {"values", std::move(vals)}, {"text", text}});
  }
  return {{"columns", std::move(cols)}, {"rows", std::move(rows)}};
}

Json grid_json(const Grid& g, const std::vector<MapSpec>& maps, Json& map_list) {
  Json z = Json::array();
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (double v : g.z_mm) {
    z.push_back(num_or_null(v, 4));
    if (!std::isnan(v)) { lo = std::min(lo, v); hi = std::max(hi, v); }
  }
  for (std::size_t m = 0; m < maps.size(); ++m) {
    Json vals = Json::array();
    for (double v : g.values[m]) vals.push_back(num_or_null(v, 6));
    map_list.push_back({{"key", maps[m].key}, {"title", maps[m].title}, {"values", std::move(vals)}});
  }
  return {{"x0", g.x0_mm}, {"y0", g.y0_mm}, {"cell_mm", g.cell_mm}, {"nx", g.nx}, {"ny", g.ny},
          {"zmid", lo <= hi ? (lo + hi) / 2 : 0.0}, {"z", std::move(z)}};
}

// Fills the template's marks in the order they stand in it, each searched
// after the text put in before it: no inserted text (a program line with
// "@@DATA@@" in a comment) is ever taken for a mark.
std::string fill(const std::string& page, const std::vector<std::pair<std::string, std::string>>& marks) {
  std::string out;
  std::size_t pos = 0;
  for (const auto& [mark, text] : marks) {
    const std::size_t at = page.find(mark, pos);
    if (at == std::string::npos) throw Error(Exit::internal, "report template: no mark " + mark);
    out.append(page, pos, at - pos);
    out += text;
    pos = at + mark.size();
  }
  out.append(page, pos, std::string::npos);
  return out;
}

std::string escape_html(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

// One pass of gap filling: an empty cell enclosed by filled ones - two on
// opposite sides (across a row, a column or a diagonal), or five of its eight
// neighbours - takes the value of largest magnitude among them per map and
// their mean height. Steep walls move the contact points of a pass sideways and
// leave such holes inside a part; the outside of a part is not enclosed and
// stays "no data".
void fill_gaps(Grid& g) {
  const std::vector<double> z0 = g.z_mm;
  const std::vector<std::vector<double>> v0 = g.values;
  auto filled = [&](int i, int j) { return i >= 0 && j >= 0 && i < g.nx && j < g.ny && !std::isnan(z0[static_cast<std::size_t>(j) * g.nx + i]); };
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

Grid make_grid(const std::vector<Eigen::Vector3d>& xyz, const std::vector<const std::vector<double>*>& values,
               double min_cell_mm, int max_cells) {
  Grid g;
  double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
  std::vector<std::size_t> used;
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    bool any = false;
    for (const auto* v : values) any = any || !std::isnan((*v)[i]);
    if (!any) continue;
    used.push_back(i);
    x0 = std::min(x0, xyz[i].x()); x1 = std::max(x1, xyz[i].x());
    y0 = std::min(y0, xyz[i].y()); y1 = std::max(y1, xyz[i].y());
  }
  g.values.assign(values.size(), {});
  if (used.empty()) {
    g.z_mm.assign(1, kNone);
    for (auto& v : g.values) v.assign(1, kNone);
    return g;
  }
  const double span = std::max({x1 - x0, y1 - y0, 1e-3});
  g.cell_mm = std::max(span / max_cells, std::isfinite(min_cell_mm) ? min_cell_mm : 0.0);
  g.nx = std::clamp(static_cast<int>(std::ceil((x1 - x0) / g.cell_mm + 1e-9)), 1, max_cells);
  g.ny = std::clamp(static_cast<int>(std::ceil((y1 - y0) / g.cell_mm + 1e-9)), 1, max_cells);
  g.cell_mm = std::max(g.cell_mm, std::max((x1 - x0) / g.nx, (y1 - y0) / g.ny));
  // Centre the grid on the points' extent.
  g.x0_mm = (x0 + x1) / 2 - g.nx * g.cell_mm / 2;
  g.y0_mm = (y0 + y1) / 2 - g.ny * g.cell_mm / 2;
  const std::size_t cells = static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny);
  std::vector<double> zsum(cells, 0.0), zn(cells, 0.0);
  for (auto& v : g.values) v.assign(cells, kNone);
  for (std::size_t i : used) {
    const int cx = std::clamp(static_cast<int>((xyz[i].x() - g.x0_mm) / g.cell_mm), 0, g.nx - 1);
    const int cy = std::clamp(static_cast<int>((xyz[i].y() - g.y0_mm) / g.cell_mm), 0, g.ny - 1);
    const std::size_t c = static_cast<std::size_t>(cy) * g.nx + cx;
    zsum[c] += xyz[i].z();
    zn[c] += 1;
    for (std::size_t m = 0; m < values.size(); ++m) {
      const double v = (*values[m])[i];
      double& cell = g.values[m][c];
      if (!std::isnan(v) && (std::isnan(cell) || std::fabs(v) > std::fabs(cell))) cell = v;
    }
  }
  g.z_mm.assign(cells, kNone);
  for (std::size_t c = 0; c < cells; ++c)
    if (zn[c] > 0) g.z_mm[c] = zsum[c] / zn[c];
  fill_gaps(g);
  fill_gaps(g);
  return g;
}

std::vector<Eigen::Vector3d> contact_points(const PointTable& t, const std::vector<interp::Motion>& motions,
                                            const compensate::Physics& ph, const compensate::Settings& s) {
  std::vector<Eigen::Vector3d> out(t.points.size());
  for (std::size_t i = 0; i < t.points.size(); ++i) {
    const compensate::Point& p = t.points[i];
    out[i] = p.tip_mm;
    const auto it = ph.tools.tools.find(compensate::tool_id(motions[p.motion], s));
    if (it == ph.tools.tools.end()) continue;
    const stiffness::Tool& tool = it->second;
    const double R = tool.diameter_mm / 2;
    const double r = tool.type == stiffness::ToolType::ball ? R : tool.type == stiffness::ToolType::bull ? tool.corner_radius_mm : 0.0;
    // The corner circle's centre on the side n faces, then r back along n.
    Eigen::Vector3d h(p.normal.x(), p.normal.y(), 0);
    h = h.norm() > 1e-9 ? Eigen::Vector3d(h.normalized()) : Eigen::Vector3d::Zero();
    out[i] = p.tip_mm + Eigen::Vector3d(0, 0, r) + (R - r) * h - r * p.normal;
  }
  return out;
}

std::string sha256_hex(const std::string& bytes) {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  if (!EVP_Digest(bytes.data(), bytes.size(), md, &n, EVP_sha256(), nullptr)) return "";
  std::string hex;
  char b[3];
  for (unsigned int i = 0; i < n; ++i) {
    std::snprintf(b, sizeof b, "%02x", md[i]);
    hex += b;
  }
  return hex;
}

std::string report_html(const HtmlInput& in) {
  const PointTable& t = *in.table;
  const std::vector<MapSpec> maps = maps_of(t);
  double scale = 2 * in.tolerance_mm;
  for (const MapSpec& m : maps)
    for (double v : m.values)
      if (!std::isnan(v)) scale = std::max(scale, std::fabs(v));
  // The grid's cell: at least the median step-over, so passes leave no stripes.
  std::vector<double> steps;
  for (const auto& c : t.cusp)
    if (!std::isnan(c.stepover_mm)) steps.push_back(c.stepover_mm);
  double step = 0;
  if (!steps.empty()) {
    std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
    step = steps[steps.size() / 2] * 1.05;
  }
  std::vector<const std::vector<double>*> vals;
  for (const MapSpec& m : maps) vals.push_back(&m.values);
  std::vector<double> cusp(t.points.size(), kNone);
  double cusp_max = 0;
  for (std::size_t i = 0; i < t.points.size(); ++i)
    if (t.cutting(i) && !std::isnan(t.cusp[i].height_mm)) {
      cusp[i] = t.cusp[i].height_mm;
      cusp_max = std::max(cusp_max, cusp[i]);
    }
  vals.push_back(&cusp);
  const Grid g = make_grid(in.contact_mm, vals, step);
  Json map_list = Json::array();
  Json prov = Json::array();
  for (const auto& [k, v] : in.provenance) prov.push_back({k, v});
  Json facts = Json::array();
  for (const auto& f : in.facts) facts.push_back(f);
  const ValueStats cs = value_stats(cusp);
  if (cs.points) {
    char b[96];
    std::snprintf(b, sizeof b, "%.1f / %.1f µm", 1000 * cs.max, 1000 * cs.mean);
    facts.push_back({"cusp height, max / mean (Mikó Eq. 7)", b, "cusp_height_mm"});
  }
  Json data{{"provenance", std::move(prov)}, {"summary", in.summary}, {"tolerance_mm", in.tolerance_mm},
            {"scale_mm", scale}, {"facts", std::move(facts)}};
  data["grid"] = grid_json(g, maps, map_list);
  Json cv = Json::array();
  for (double v : g.values.back()) cv.push_back(num_or_null(v, 6));
  data["cusp"] = {{"max_mm", cusp_max}, {"values", std::move(cv)}};
  data["maps"] = std::move(map_list);
  data["series"] = series_json(t, maps, 4000);
  data["plots"] = plots_json(maps);
  data["histogram"] = histogram_json(maps, scale);
  data["worst"] = worst_json(t, maps, in.source);
  std::string json = data.dump(-1, ' ', false, Json::error_handler_t::replace);
  // Inside <script>: "</" never appears outside a JSON string, and "<\/" reads the same in one.
  for (std::size_t at = json.find("</"); at != std::string::npos; at = json.find("</", at + 3)) json.insert(at + 1, "\\");
  const std::string title = escape_html(in.title);
  return fill(embedded::report_page(), {{"@@TITLE@@", title},
                                        {"/*@@DYGRAPHS_CSS@@*/", embedded::dygraphs_css()},
                                        {"@@TITLE@@", title},
                                        {"@@DATA@@", json},
                                        {"/*@@THREE@@*/", embedded::three_js()},
                                        {"/*@@ORBIT@@*/", embedded::orbit_controls_js()},
                                        {"/*@@DYGRAPHS@@*/", embedded::dygraphs_js()}});
}

}  // namespace deflex::report
