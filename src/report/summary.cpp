#include "deflex/report/summary.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "deflex/report/stats.hpp"

namespace deflex::report {
namespace {

Json totals_json(const process::TimeTotals& t) {
  return {{"total_s", fixed(t.total_s, 2)}, {"cutting_s", fixed(t.cutting_s, 2)}, {"rapid_s", fixed(t.rapid_s, 2)},
          {"cutting_mm", fixed(t.cutting_mm, 2)}, {"rapid_mm", fixed(t.rapid_mm, 2)}};
}

}  // namespace

Json to_json(const process::MachiningTime& t) {
  Json j = totals_json(t.program);
  Json per = Json::object();
  for (const auto& [tool, tt] : t.per_tool) per["T" + std::to_string(tool)] = totals_json(tt);
  j["per_tool"] = std::move(per);
  return j;
}

bool clock_has_hours(double seconds) { return std::lround(std::max(0.0, seconds)) >= 3600; }

std::string clock(double seconds, bool hours) {
  const long s = std::lround(std::max(0.0, seconds));
  char b[40];
  if (hours || s >= 3600) std::snprintf(b, sizeof b, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else std::snprintf(b, sizeof b, "%ld:%02ld", s / 60, s % 60);
  return b;
}

Json cusp_json(const ValueStats& s) {
  return {{"max", fixed(s.max, 6)}, {"mean", fixed(s.mean, 6)}, {"points", s.points}};
}

std::string utc_now() {
  std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  if (const char* e = std::getenv("SOURCE_DATE_EPOCH")) {
    char* end = nullptr;
    const long long v = std::strtoll(e, &end, 10);
    if (end != e && *end == '\0' && v >= 0) now = static_cast<std::time_t>(v);
  }
  std::tm tm{};
  gmtime_r(&now, &tm);
  char b[32];
  std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return b;
}

}  // namespace deflex::report
