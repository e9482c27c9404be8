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
// 754.2 s -> "12:34" (m:ss), 3 h and more "3:02:05".
std::string clock(double seconds);
// {max, mean, points}: the cusp heights of the points in material (ball ends
// with a neighbouring pass).
Json cusp_json(const ValueStats& s);
// Now as ISO 8601 UTC, or SOURCE_DATE_EPOCH's time where that is set (the
// reproducible-builds convention: a report that must not change between runs).
std::string utc_now();

}  // namespace deflex::report
