// Pieces of summary.json and of the text summary shared by the commands that
// simulate: machining time, cusp height, the date of a run.
#pragma once
#include <string>

#include "deflex/process/machining_time.hpp"
#include "deflex/report/json.hpp"
#include "deflex/report/recorder.hpp"

namespace deflex::report {

// {total_s, cutting_s, rapid_s, cutting_mm, rapid_mm, per_tool: {"T5": {...}}}
Json to_json(const process::MachiningTime& t);
// 754.2 s -> "12:34" (m:ss), an hour and more "3:02:05" (h:mm:ss); with
// `hours`, h:mm:ss under an hour too ("0:12:34"), for times printed beside
// one that reaches an hour.
std::string clock(double seconds, bool hours = false);
// Whether clock(seconds) has hours: the unit a label names ("h:mm:ss", "m:ss").
bool clock_has_hours(double seconds);
// {max, mean, points}: the cusp heights of the points in material (ball ends
// with a neighbouring pass).
Json cusp_json(const ValueStats& s);
// Now as ISO 8601 UTC, or SOURCE_DATE_EPOCH's time where that is set (the
// reproducible-builds convention: a report that must not change between runs).
std::string utc_now();

}  // namespace deflex::report
