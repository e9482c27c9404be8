// stability.html: the stability lobes of `deflex stability` as a page that
// opens offline (dygraphs compiled in): the limit against speed, the stable
// pockets marked, what the limit was computed from.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace deflex::report {

struct LobesPage {
  std::string title;
  std::vector<std::pair<std::string, std::string>> provenance;  // label, value
  std::vector<std::pair<double, double>> limit;    // rpm, ap_limit_mm: the lower envelope
  std::vector<std::pair<double, double>> pockets;  // rpm, ap_limit_mm: stable speeds, best first
  double ap_min_mm = 0;                            // the absolute limit
};

std::string lobes_html(const LobesPage& p);

}  // namespace deflex::report
