// A probe log joined with its probe program's targets (probe.hpp).
#include <algorithm>
#include <cmath>
#include <map>

#include "deflex/diag/plural.hpp"
#include "deflex/measure/probe.hpp"
#include "deflex/measure/text.hpp"

namespace deflex::measure {
namespace {

using detail::fail;

// The error along the normal of a stylus centre `centre` at target `t`: the
// contact point is the centre moved back by the radius along the normal.
double error_of(const ProbeTarget& t, const Eigen::Vector3d& centre) {
  return (centre - t.ball_radius_mm * t.normal - t.point_mm).dot(t.normal);
}

using Pair = std::pair<const ProbeTarget*, const Sample*>;

// Whether every point reads within the limit once its log is scaled by `scale`.
bool all_within(const std::vector<Pair>& pairs, double scale, double limit_mm) {
  return std::all_of(pairs.begin(), pairs.end(), [&](const Pair& p) {
    return std::abs(error_of(*p.first, p.second->p_mm * scale)) <= limit_mm;
  });
}

// The likeliest reason for an error no machine makes: a log in the other unit
// reads right once converted (judged on every point: one point near the
// origin fits any scale); else an offset or a program that does not match.
std::string likely_cause(const std::vector<Pair>& pairs, double limit_mm) {
  constexpr double inch_mm = 25.4;
  if (all_within(pairs, inch_mm, limit_mm))
    return "the log reads right in inches: the probe program ran in G20, or the control reports inches";
  if (all_within(pairs, 1 / inch_mm, limit_mm))
    return "the log reads right as inches: the probe program's targets are in inches, the log in mm";
  return "likely the wrong work offset (G54...) when probing, a log of another probe program, or a probe that did not "
         "trip (G38.3 then logs its programmed end point)";
}

std::vector<MeasuredPoint> measured(const std::vector<Pair>& pairs, const SourceText& log, double limit_mm) {
  std::vector<MeasuredPoint> out;
  for (const auto& [t, s] : pairs) {
    MeasuredPoint m;
    m.surface_mm = s->p_mm - t->ball_radius_mm * t->normal;
    m.intended_mm = t->point_mm;
    m.normal = t->normal;
    m.error_mm = error_of(*t, s->p_mm);
    m.id = t->id;
    m.feature = t->feature;
    m.line = s->line;
    if (!(std::abs(m.error_mm) <= limit_mm))
      fail(log, std::max<std::uint32_t>(1, s->line), 1,
           "probe point " + std::to_string(t->id) + " (" + t->feature + ") is " + fixed_decimals(m.error_mm, 3) +
               " mm off the intended surface along its normal, more than the " + fixed_decimals(limit_mm, 3) +
               " mm no machine deflects: " + likely_cause(pairs, limit_mm));
    out.push_back(std::move(m));
  }
  return out;
}

std::uint32_t last_line(const SourceText& log) {
  for (std::uint32_t l = log.last_line(); l >= 1; --l)
    if (!detail::trim(log.line_text(l)).empty()) return l;
  return 1;
}

std::vector<MeasuredPoint> in_order(const std::vector<ProbeTarget>& targets, const std::vector<Sample>& samples,
                                    const SourceText& log, double limit_mm) {
  const std::string counts =
      "the log has " + plural(samples.size(), "probe position") + ", the probe program " + plural(targets.size(), "point");
  if (samples.size() > targets.size())
    fail(log, std::max<std::uint32_t>(1, samples[targets.size()].line), 1,
         counts + ": this line is the first without a point (a log of another program, or two runs in one log?)");
  if (samples.size() < targets.size())
    fail(log, last_line(log), 1,
         counts + ": " + std::to_string(targets.size() - samples.size()) +
             " missing (a probe that did not trip, or one that tripped where the last did: LinuxCNC then "
             "writes no line)");
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < targets.size(); ++i) pairs.emplace_back(&targets[i], &samples[i]);
  return measured(pairs, log, limit_mm);
}

std::vector<MeasuredPoint> by_ids(const std::vector<ProbeTarget>& targets, const std::vector<Sample>& samples,
                                  const SourceText& log, double limit_mm) {
  std::map<int, const Sample*> got;
  for (const Sample& s : samples) {
    const std::uint32_t l = std::max<std::uint32_t>(1, s.line);
    if (s.id < 1 || s.id > static_cast<int>(targets.size()))
      fail(log, l, 1, "point " + std::to_string(s.id) + " is not in the probe program (its points are 1 to " +
                          std::to_string(targets.size()) + ")");
    if (!got.emplace(s.id, &s).second) fail(log, l, 1, "point " + std::to_string(s.id) + " given twice");
  }
  std::string missing;
  int n_missing = 0;
  for (const ProbeTarget& t : targets)
    if (!got.count(t.id) && ++n_missing <= 20) missing += (missing.empty() ? "" : ", ") + std::to_string(t.id);
  if (n_missing)
    throw Error(ErrorKind::input, log.name() + ": error: " + std::to_string(n_missing) + " of the probe program's " +
                                      plural(targets.size(), "point") + " never printed: " + missing +
                                      (n_missing > 20 ? ", ..." : ""));
  std::vector<Pair> pairs;
  for (const ProbeTarget& t : targets) pairs.emplace_back(&t, got.at(t.id));
  return measured(pairs, log, limit_mm);
}

}  // namespace

std::vector<MeasuredPoint> join_probe_log(const std::vector<ProbeTarget>& targets, const std::vector<Sample>& samples,
                                          bool by_id, const std::string& log_file, const std::string& log_text,
                                          double limit_mm) {
  if (!(limit_mm > 0) || !std::isfinite(limit_mm))
    throw Error(ErrorKind::settings, "the limit of a measured error must be a number > 0 mm, not " + std::to_string(limit_mm));
  // Ids 1..n in order, as read_probe_targets guarantees: target i has id i + 1.
  for (std::size_t i = 0; i < targets.size(); ++i)
    if (targets[i].id != static_cast<int>(i + 1))
      throw Error(ErrorKind::internal, "join_probe_log: the targets' ids are not 1..n in order");
  const SourceText log(log_file, log_text);
  return by_id ? by_ids(targets, samples, log, limit_mm) : in_order(targets, samples, log, limit_mm);
}

}  // namespace deflex::measure
