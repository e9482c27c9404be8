// deflex compare's table in every format (include/deflex/report/compare.hpp).
// One list of columns serves the text, CSV, JSON and HTML forms.
#include "deflex/report/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "deflex/diag/plural.hpp"
#include "deflex/report/summary.hpp"
#include "html_text.hpp"

namespace deflex::report {
namespace {

struct Column {
  const char* key;      // JSON and CSV name (units in it)
  const char* header;   // text and HTML heading
  const char* unit;     // as shown in text and HTML
  double shown_per_unit;  // text/HTML value = stored value * this
  int decimals;         // text/HTML decimals
  double (*get)(const CompareRow&);
};

const std::vector<Column>& columns() {
  static const std::vector<Column> c = {
      {"error_max_mm", "error max", "um", 1000, 1, [](const CompareRow& r) { return r.error.max_abs; }},
      {"error_rms_mm", "error rms", "um", 1000, 1, [](const CompareRow& r) { return r.error.rms; }},
      {"error_p95_mm", "error p95", "um", 1000, 1, [](const CompareRow& r) { return r.error.p95_abs; }},
      {"out_of_tolerance_share", "outside", "%", 100, 1, [](const CompareRow& r) { return r.error.share_out; }},
      {"peak_force_N", "peak |F|", "N", 1, 0, [](const CompareRow& r) { return r.peak_force_N; }},
      {"mean_force_N", "mean |F|", "N", 1, 1, [](const CompareRow& r) { return r.mean_force_N; }},
      {"peak_deflection_mm", "peak defl.", "um", 1000, 1, [](const CompareRow& r) { return r.peak_deflection_mm; }},
      {"peak_mrr_mm3_per_s", "peak MRR", "mm3/s", 1, 1, [](const CompareRow& r) { return r.peak_mrr_mm3_per_s; }},
      {"mean_d_eff_mm", "mean D_eff", "mm", 1, 2, [](const CompareRow& r) { return r.mean_d_eff_mm; }},
      {"mean_area_mm2", "mean area", "mm2", 1, 2, [](const CompareRow& r) { return r.mean_area_mm2; }},
      {"cusp_max_mm", "cusp max", "um", 1000, 1, [](const CompareRow& r) { return r.cusp_max_mm; }},
      {"cusp_mean_mm", "cusp mean", "um", 1000, 1, [](const CompareRow& r) { return r.cusp_mean_mm; }},
      {"path_mm", "path", "mm", 1, 0, [](const CompareRow& r) { return r.path_mm; }},
      {"time_s", "time", "s", 1, 0, [](const CompareRow& r) { return r.time_s; }},
  };
  return c;
}

std::string shown(const Column& c, const CompareRow& r) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*f", c.decimals, c.get(r) * c.shown_per_unit);
  return b;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// The text table's ASCII units as a page shows them.
std::string html_unit(const std::string& u) {
  if (u == "um") return "µm";
  if (u == "mm3/s") return "mm³/s";
  if (u == "mm2") return "mm²";
  return u;
}

}  // namespace

CompareRow compare_row(const std::string& program, const RunFigures& f, const process::MachiningTime& time) {
  CompareRow r;
  r.program = program;
  r.error = f.error;
  r.peak_force_N = f.peak_force_N;
  r.mean_force_N = f.mean_force_N;
  r.peak_deflection_mm = f.peak_deflection_mm;
  r.peak_mrr_mm3_per_s = f.peak_mrr_mm3_per_s;
  r.mean_d_eff_mm = f.mean_d_eff_mm;
  r.mean_area_mm2 = f.mean_area_mm2;
  r.cusp_max_mm = f.cusp.max;
  r.cusp_mean_mm = f.cusp.mean;
  r.cusp_points = f.cusp.points;
  r.path_mm = time.program.cutting_mm;
  r.time_s = time.program.total_s;
  return r;
}

std::string compare_text(const std::vector<CompareRow>& rows, double tol) {
  std::size_t w = 7;
  for (const CompareRow& r : rows) w = std::max(w, r.program.size());
  std::string head = std::string("program") + std::string(w - 7, ' '), units(w, ' ');
  for (const Column& c : columns()) {
    char b[64];
    std::snprintf(b, sizeof b, " %11s", c.header);
    head += b;
    std::snprintf(b, sizeof b, " %11s", c.unit);
    units += b;
  }
  std::string out = head + "\n" + units + "\n";
  for (const CompareRow& r : rows) {
    out += r.program + std::string(w - r.program.size(), ' ');
    for (const Column& c : columns()) {
      char b[64];
      std::snprintf(b, sizeof b, " %11s", shown(c, r).c_str());
      out += b;
    }
    out += "\n";
  }
  char b[160];
  std::snprintf(b, sizeof b, "(surface error of each program against itself; outside: share of points beyond +-%.4f mm)\n", tol);
  return out + b;
}

std::string compare_csv(const std::vector<CompareRow>& rows) {
  std::string out = "program";
  for (const Column& c : columns()) out += std::string(",") + c.key;
  out += "\n";
  for (const CompareRow& r : rows) {
    out += csv_field(r.program);
    for (const Column& c : columns()) {
      char b[48];
      std::snprintf(b, sizeof b, ",%.6g", c.get(r));
      out += b;
    }
    out += "\n";
  }
  return out;
}

Json compare_json(const std::vector<CompareRow>& rows, double tol) {
  Json a = Json::array();
  for (const CompareRow& r : rows) {
    Json o{{"file", r.program}};
    for (const Column& c : columns()) o[c.key] = significant(c.get(r), 6);
    o["cusp_points"] = r.cusp_points;
    a.push_back(std::move(o));
  }
  return {{"tolerance_mm", fixed(tol, 6)}, {"programs", std::move(a)}};
}

std::string compare_html(const std::vector<CompareRow>& rows, double tol,
                         const std::vector<std::pair<std::string, std::string>>& provenance) {
  std::string h =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>deflex compare</title><style>\n"
      "body{font:14px/1.4 system-ui,sans-serif;margin:0 24px 40px;color:#222}h1{font-size:22px}"
      "table{border-collapse:collapse}td,th{border:1px solid #ddd;padding:3px 8px;text-align:right;vertical-align:bottom}"
      "th{background:#f0f0f0}td.p{text-align:left;font-family:ui-monospace,monospace}"
      ".bar{height:5px;background:#7a8fc2;margin-top:2px}.best{font-weight:bold;color:#185c18}"
      ".prov td{border:none;text-align:left;font-family:ui-monospace,monospace;font-size:13px}"
      ".prov td:first-child{white-space:nowrap}\n"
      "</style></head><body>\n<h1>deflex compare: " + plural(rows.size(), "program") + " on the same stock</h1>\n"
      "<table class=\"prov\">";
  for (const auto& [k, v] : provenance) h += "<tr><td>" + detail::escape_html(k) + "</td><td>" + detail::escape_html(v) + "</td></tr>";
  h += "</table>\n<p>Each program simulated from the same stock with the same tool data and machine; "
       "the surface error is against each program's own path (e &gt; 0 material left). Bars are scaled to the "
       "largest of their column; bold: the smallest of each column.</p>\n"
       "<table id=\"compare\"><tr><th>program</th>";
  for (const Column& c : columns()) h += std::string("<th>") + c.header + "<br>" + html_unit(c.unit) + "</th>";
  h += "</tr>\n";
  for (const CompareRow& r : rows) {
    h += "<tr><td class=\"p\">" + detail::escape_html(r.program) + "</td>";
    for (const Column& c : columns()) {
      double top = 0, low = HUGE_VAL;
      for (const CompareRow& o : rows) {
        top = std::max(top, c.get(o));
        low = std::min(low, c.get(o));
      }
      const double v = c.get(r);
      char bar[96];
      std::snprintf(bar, sizeof bar, "<div class=\"bar\" style=\"width:%.0fpx\"></div>", top > 0 ? 70 * v / top : 0.0);
      h += std::string("<td data-key=\"") + c.key + "\"" + (rows.size() > 1 && v == low ? " class=\"best\"" : "") + ">" +
           shown(c, r) + bar + "</td>";
    }
    h += "</tr>\n";
  }
  char b[120];
  std::snprintf(b, sizeof b, "</table>\n<p>Tolerance for the share outside: &plusmn;%.4f mm.</p>\n</body></html>\n", tol);
  return h + b;
}

}  // namespace deflex::report
