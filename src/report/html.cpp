// report.html (include/deflex/report/html.hpp).
#include "deflex/report/html.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "deflex/report/stats.hpp"
#include "deflex/stiffness/tool.hpp"
#include "html_text.hpp"


namespace deflex::report {
namespace {

using detail::escape_html;
using detail::fill;

Json num_or_null(double v, int decimals) { return std::isnan(v) ? Json() : Json(fixed(v, decimals)); }

Json plots_json(const std::vector<std::pair<std::string, std::string>>& maps) {
  Json errs = Json::array(), labels = Json::array();
  for (std::size_t m = 0; m < maps.size(); ++m) {
    errs.push_back("e" + std::to_string(m));
    labels.push_back("e " + maps[m].second + ", µm");
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
      plot("spindle power (mean over a revolution) and the S1 rating at the point's speed", "kW", {"P", "S1"},
           {"P", "P_S1"}),
      plot("spindle torque (mean over a revolution) and the S1 rating at the point's speed", "N m", {"M", "S1"},
           {"M", "M_S1"}),
      plot("axial depth of cut and the stability limit at the point's immersion and speed (chatter above it)", "mm",
           {"a_p", "limit"}, {"ap", "ap_lim"}),
  });
}

Json grid_json(const Grid& g, const std::vector<std::pair<std::string, std::string>>& maps, Json& map_list) {
  Json z = Json::array();
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (double v : g.z_mm) {
    z.push_back(num_or_null(v, 4));
    if (!std::isnan(v)) { lo = std::min(lo, v); hi = std::max(hi, v); }
  }
  for (std::size_t m = 0; m < maps.size(); ++m) {
    Json vals = Json::array();
    for (double v : g.values[m]) vals.push_back(num_or_null(v, 6));
    map_list.push_back({{"key", maps[m].first}, {"title", maps[m].second}, {"values", std::move(vals)}});
  }
  return {{"x0", g.x0_mm}, {"y0", g.y0_mm}, {"cell_mm", g.cell_mm}, {"nx", g.nx}, {"ny", g.ny},
          {"zmid", lo <= hi ? (lo + hi) / 2 : 0.0}, {"z", std::move(z)}};
}

// At most this many measured points on the page: a probe's few thousand all
// show; a scanned cloud of 10^5 would make the page heavy and its point views slow.
constexpr std::size_t kMeasuredShown = 5000;

// The measured points by columns (x, y, z in mm to the micrometre; m and p the
// measured and predicted error in mm, null where unknown). Past
// kMeasuredShown, each run of `per_bucket` consecutive points (a probe's path
// or a scan line: neighbours on the part) keeps its point of largest
// |predicted - measured|, or of largest |measured| where none has a
// prediction: the disagreements this section is for are never dropped.
Json measured_json(const std::vector<MeasuredMark>& marks) {
  const std::size_t per = std::max<std::size_t>(1, (marks.size() + kMeasuredShown - 1) / kMeasuredShown);
  auto weight = [](const MeasuredMark& k) {
    if (std::isnan(k.measured_error_mm)) return std::pair(-1, 0.0);
    if (k.predicted) return std::pair(1, std::fabs(k.predicted_error_mm - k.measured_error_mm));
    return std::pair(0, std::fabs(k.measured_error_mm));
  };
  Json x = Json::array(), y = Json::array(), z = Json::array(), m = Json::array(), p = Json::array();
  for (std::size_t b = 0; b < marks.size(); b += per) {
    const auto end = marks.begin() + static_cast<std::ptrdiff_t>(std::min(marks.size(), b + per));
    const MeasuredMark& k = *std::max_element(marks.begin() + static_cast<std::ptrdiff_t>(b), end,
                                              [&](const MeasuredMark& u, const MeasuredMark& v) { return weight(u) < weight(v); });
    x.push_back(fixed(k.x_mm, 3));
    y.push_back(fixed(k.y_mm, 3));
    z.push_back(fixed(k.z_mm, 3));
    m.push_back(num_or_null(k.measured_error_mm, 6));
    p.push_back(k.predicted ? num_or_null(k.predicted_error_mm, 6) : Json());
  }
  return {{"points", marks.size()}, {"per_bucket", per}, {"x", std::move(x)}, {"y", std::move(y)},
          {"z", std::move(z)},      {"m", std::move(m)},  {"p", std::move(p)}};
}

// The template's measured section (between its two marks) kept, marks
// dropped, or cut out: a run without measurements shows no empty section.
std::string measured_section(std::string page, bool keep) {
  static const std::string begin = "<!--@@MEASURED{-->", end = "<!--}@@MEASURED-->";
  const std::size_t a = page.find(begin), b = page.find(end);
  if (a == std::string::npos || b == std::string::npos || b < a)
    throw Error(ErrorKind::internal, "report template: no measured section");
  if (keep) return page.erase(b, end.size()).erase(a, begin.size());
  return page.erase(a, b + end.size() - a);
}

// Fills the template's marks in the order they stand in it, each searched
// after the text put in before it: no inserted text (a program line with
// "@@DATA@@" in a comment) is ever taken for a mark.
}  // namespace

Sha256::Sha256() : ctx_(EVP_MD_CTX_new()) {
  if (!ctx_ || !EVP_DigestInit_ex(static_cast<EVP_MD_CTX*>(ctx_), EVP_sha256(), nullptr))
    throw Error(ErrorKind::internal, "SHA-256: OpenSSL refused to start a digest");
}

Sha256::~Sha256() { EVP_MD_CTX_free(static_cast<EVP_MD_CTX*>(ctx_)); }

void Sha256::add(std::string_view bytes) { EVP_DigestUpdate(static_cast<EVP_MD_CTX*>(ctx_), bytes.data(), bytes.size()); }

std::string Sha256::hex() {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  if (!EVP_DigestFinal_ex(static_cast<EVP_MD_CTX*>(ctx_), md, &n)) return "";
  std::string hex;
  char b[3];
  for (unsigned int i = 0; i < n; ++i) {
    std::snprintf(b, sizeof b, "%02x", md[i]);
    hex += b;
  }
  return hex;
}

std::string sha256_hex(std::string_view bytes) {
  Sha256 s;
  s.add(bytes);
  return s.hex();
}

std::string report_html(const HtmlInput& in) {
  const Page& pg = *in.page;
  Json map_list = Json::array();
  Json prov = Json::array();
  for (const auto& [k, v] : in.provenance) prov.push_back({k, v});
  Json facts = Json::array();
  for (const auto& f : in.facts) facts.push_back(f);
  const ValueStats& cs = pg.cusp;
  if (cs.points) {
    char b[96];
    std::snprintf(b, sizeof b, "%.1f / %.1f µm", 1000 * cs.max, 1000 * cs.mean);
    facts.push_back({"cusp height, max / mean (Mikó Eq. 7)", b, "cusp_height_mm"});
  }
  Json data{{"provenance", std::move(prov)}, {"summary", in.summary}, {"tolerance_mm", in.tolerance_mm},
            {"scale_mm", pg.scale_mm}, {"facts", std::move(facts)}};
  data["grid"] = grid_json(pg.grid, pg.maps, map_list);
  Json cv = Json::array();
  for (double v : pg.grid.values.back()) cv.push_back(num_or_null(v, 6));
  data["cusp"] = {{"max_mm", pg.cusp_max_mm}, {"values", std::move(cv)}};
  data["maps"] = std::move(map_list);
  data["series"] = pg.series;
  data["plots"] = plots_json(pg.maps);
  data["histogram"] = pg.histogram;
  data["worst"] = pg.worst;
  if (!in.measured.empty()) data["measured"] = measured_json(in.measured);
  for (auto& row : data["worst"]["rows"]) {
    const auto it = in.line_text.find(row["line"].get<std::uint32_t>());
    if (it != in.line_text.end()) row["text"] = it->second;
  }
  const std::string json = detail::script_json(data);
  const std::string title = escape_html(in.title);
  return fill(measured_section(embedded::report_page(), !in.measured.empty()), {{"@@TITLE@@", title},
                                        {"/*@@DYGRAPHS_CSS@@*/", embedded::dygraphs_css()},
                                        {"@@TITLE@@", title},
                                        {"@@DATA@@", json},
                                        {"/*@@THREE@@*/", embedded::three_js()},
                                        {"/*@@ORBIT@@*/", embedded::orbit_controls_js()},
                                        {"/*@@DYGRAPHS@@*/", embedded::dygraphs_js()}});
}

}  // namespace deflex::report
