#include "deflex/profile/spindle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "deflex/diag/plural.hpp"
#include "sections.hpp"

namespace deflex::profile {

double angular_speed_rad_per_s(double rpm) { return 2 * std::numbers::pi * rpm / 60.0; }
double power_from_torque_kW(double torque_Nm, double rpm) { return torque_Nm * angular_speed_rad_per_s(rpm) / 1000.0; }

namespace {

// The curve's value at n: linear between its points, the last one past the end.
double at(const std::vector<double>& rpm, const std::vector<double>& v, double n) {
  if (n >= rpm.back()) return v.back();
  const auto hi = std::upper_bound(rpm.begin(), rpm.end(), n);
  const std::size_t k = static_cast<std::size_t>(hi - rpm.begin());
  const double t = (n - rpm[k - 1]) / (rpm[k] - rpm[k - 1]);
  return v[k - 1] + t * (v[k] - v[k - 1]);
}

}  // namespace

double SpindleCurve::allowed_torque_Nm(double rpm_now) const {
  double m = std::numeric_limits<double>::infinity();
  if (!torque_Nm.empty()) m = at(rpm, torque_Nm, rpm_now);
  const double w = angular_speed_rad_per_s(rpm_now);
  if (!power_kW.empty() && w > 0) m = std::min(m, 1000.0 * at(rpm, power_kW, rpm_now) / w);
  return m;
}

double SpindleCurve::allowed_power_kW(double rpm_now) const {
  return power_from_torque_kW(allowed_torque_Nm(rpm_now), rpm_now);
}

namespace {

using yaml::Map;
using yaml::Range;

std::vector<double> column(const Map& s, const char* key, Range r) {
  const YAML::Node n = s.get(key);
  const std::string what = s.name() + "." + key;
  if (!n.IsSequence() || n.size() < 2) s.fail(n, what + " must be a list of at least 2 numbers");
  std::vector<double> v;
  for (const YAML::Node& e : n) v.push_back(yaml::number(e, what, s.file(), r));
  return v;
}

SpindleCurve parse_curve(const Map& s) {
  SpindleCurve c;
  const std::string name = s.name();
  c.rpm = column(s, "rpm", Range::non_negative());
  if (c.rpm.front() != 0) s.fail("rpm", name + ".rpm must start at 0 (the curve covers every speed the program may ask)");
  for (std::size_t k = 1; k < c.rpm.size(); ++k)
    if (!(c.rpm[k] > c.rpm[k - 1])) s.fail("rpm", name + ".rpm must be strictly increasing");
  if (!s.has("power_kW") && !s.has("torque_Nm")) s.fail(s.node(), name + " needs power_kW, torque_Nm or both");
  auto same_length = [&](const char* key, std::vector<double>& v) {
    v = column(s, key, Range::non_negative());
    if (v.size() != c.rpm.size())
      s.fail(key, name + "." + key + " has " + plural(v.size(), "value") + ", rpm " + plural(c.rpm.size(), "value"));
  };
  if (s.has("power_kW")) same_length("power_kW", c.power_kW);
  if (s.has("torque_Nm")) same_length("torque_Nm", c.torque_Nm);
  if (!c.power_kW.empty() && !c.torque_Nm.empty())
    for (std::size_t k = 0; k < c.rpm.size(); ++k) {
      const double from_torque = power_from_torque_kW(c.torque_Nm[k], c.rpm[k]);
      if (std::fabs(from_torque - c.power_kW[k]) > 0.1 * std::max(from_torque, c.power_kW[k]))
        s.fail("power_kW", name + " at " + fixed_decimals(c.rpm[k], 0) + " rpm: " + fixed_decimals(c.torque_Nm[k], 1) +
                               " N m is " + fixed_decimals(from_torque, 2) + " kW (P = M 2 pi n / 60), not " +
                               fixed_decimals(c.power_kW[k], 2) + " kW: the two curves disagree by more than 10 %");
    }
  if (c.allowed_torque_Nm(c.rpm.back()) <= 0) s.fail(s.node(), name + " allows no torque at " + fixed_decimals(c.rpm.back(), 0) + " rpm");
  return c;
}

}  // namespace

SpindleRating parse_spindle(const YAML::Node& section, const std::string& file) {
  const Map s(section, "spindle", file, {"max_rpm", "source", "S1", "S6"});
  SpindleRating r;
  r.set = true;
  r.max_rpm = s.number("max_rpm", Range::positive());
  r.source = s.text("source", "");
  r.s1 = parse_curve(s.map("S1", {"rpm", "power_kW", "torque_Nm"}));
  if (s.has("S6")) r.s6 = parse_curve(s.map("S6", {"rpm", "power_kW", "torque_Nm"}));
  return r;
}

}  // namespace deflex::profile
