// stability.html (include/deflex/report/lobes.hpp).
#include "deflex/report/lobes.hpp"

#include <algorithm>
#include <cstdio>

#include "deflex/report/json.hpp"
#include "html_text.hpp"

namespace deflex::report {
namespace {

// The page: its data in a script, drawn by dygraphs: the limit, the
// absolute limit under it, the pockets as points.
const char* kPage = R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>@@TITLE@@</title>
<style>/*@@DYGRAPHS_CSS@@*/</style><style>
body{font:14px/1.4 system-ui,sans-serif;margin:0 24px 40px;color:#222}h1{font-size:22px}
table{border-collapse:collapse}td,th{border:1px solid #ddd;padding:3px 8px;text-align:right}
th{background:#f0f0f0}.prov td{border:none;text-align:left;font-family:ui-monospace,monospace;font-size:13px}
#lobes{width:900px;height:420px}
</style></head><body>
<h1>@@TITLE@@</h1>
<table class="prov" id="provenance"></table>
<p>Below the curve the cut is stable; above it, it chatters (zero-order limit, Altintas &amp; Budak 1995).
The dashed line is the absolute limit, stable at every speed. Dots: the stable pockets.</p>
<div id="lobes"></div>
<h2>Stable pockets</h2>
<table id="pockets"><tr><th>spindle speed, rpm</th><th>a<sub>p</sub> limit, mm</th></tr></table>
<script>/*@@DYGRAPHS@@*/</script>
<script>
const data = @@DATA@@;
const esc = s => String(s).replace(/[&<>"]/g, c => ({'&':'&amp;','<':'&lt;','>':'&gt;','"':'&quot;'}[c]));
document.getElementById('provenance').innerHTML =
  data.provenance.map(r => '<tr><td>' + esc(r[0]) + '</td><td>' + esc(r[1]) + '</td></tr>').join('');
const pocket = new Map(data.pockets.map(p => [p[0], p[1]]));
const rows = data.limit.map(r => [r[0], r[1], data.ap_min_mm, pocket.has(r[0]) ? r[1] : null]);
new Dygraph(document.getElementById('lobes'), rows, {
  labels: ['rpm', 'a_p limit', 'absolute limit', 'pocket'], xlabel: 'spindle speed, rpm', ylabel: 'a_p limit, mm',
  series: {'absolute limit': {strokePattern: Dygraph.DASHED_LINE}, 'pocket': {drawPoints: true, pointSize: 4, strokeWidth: 0}},
  connectSeparatedPoints: false, legend: 'always'});
document.getElementById('pockets').innerHTML += data.pockets.slice(0, 12)
  .map(p => '<tr><td>' + p[0].toFixed(0) + '</td><td>' + p[1].toFixed(3) + '</td></tr>').join('');
</script>
</body></html>
)";

Json pairs(const std::vector<std::pair<double, double>>& v, int decimals) {
  Json a = Json::array();
  for (const auto& [x, y] : v) a.push_back({fixed(x, 1), fixed(y, decimals)});
  return a;
}

}  // namespace

std::string lobes_html(const LobesPage& p) {
  Json prov = Json::array();
  for (const auto& [k, v] : p.provenance) prov.push_back({k, v});
  // The pockets at the speeds of the limit's rows, so the page can mark them.
  const Json data{{"provenance", std::move(prov)}, {"limit", pairs(p.limit, 4)}, {"pockets", pairs(p.pockets, 4)},
                  {"ap_min_mm", fixed(p.ap_min_mm, 4)}};
  const std::string title = detail::escape_html(p.title);
  return detail::fill(kPage, {{"@@TITLE@@", title},
                              {"/*@@DYGRAPHS_CSS@@*/", embedded::dygraphs_css()},
                              {"@@TITLE@@", title},
                              {"/*@@DYGRAPHS@@*/", embedded::dygraphs_js()},
                              {"@@DATA@@", detail::script_json(data)}});
}

}  // namespace deflex::report
