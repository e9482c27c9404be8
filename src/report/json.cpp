#include "deflex/report/json.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace deflex::report {

double fixed(double v, int decimals) {
  if (!std::isfinite(v)) return v;
  const double scale = std::pow(10.0, decimals);
  const double r = std::round(v * scale) / scale;
  // Beyond 2^53 / scale the product is already an integer: rounding would only lose bits.
  const double out = std::fabs(v * scale) < 9.0e15 ? r : v;
  return out == 0 ? 0.0 : out;
}

double significant(double v, int digits) {
  if (!std::isfinite(v) || v == 0) return v == 0 ? 0.0 : v;
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return std::strtod(b, nullptr);
}

Json xyz(double x, double y, double z, int decimals) {
  return Json::array({fixed(x, decimals), fixed(y, decimals), fixed(z, decimals)});
}

Json to_json(const Diagnostic& d) {
  const char* sev = d.severity == Severity::error ? "error" : d.severity == Severity::warning ? "warning" : "note";
  return Json{{"file", d.file}, {"line", d.line}, {"col", d.col}, {"severity", sev}, {"message", d.message}};
}

Json to_json(const std::vector<Diagnostic>& all) {
  Json a = Json::array();
  for (const Diagnostic& d : all) a.push_back(to_json(d));
  return a;
}

std::string line(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n"; }

std::string document(const Json& j) { return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n"; }

}  // namespace deflex::report
