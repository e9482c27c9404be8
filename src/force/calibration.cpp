#include "deflex/force/calibration.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/profile/yaml.hpp"

namespace deflex::force {

namespace {

constexpr double pi = std::numbers::pi;

[[noreturn]] void bad(const std::string& file, int line, int col, const std::string& msg) {
  throw Error(ErrorKind::input, file + ":" + std::to_string(line) + ":" + std::to_string(col) +
                               ": error: " + msg);
}

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

struct Field {
  std::string text;
  int col = 1;  // 1-based column of the field's first byte
};

std::vector<Field> split(const std::string& line) {
  std::vector<Field> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    const std::string raw = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    std::size_t lead = 0;
    while (lead < raw.size() && std::isspace(static_cast<unsigned char>(raw[lead]))) ++lead;
    out.push_back({trim(raw), static_cast<int>(start + lead + 1)});
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::optional<double> to_number(const std::string& s) {
  if (s.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  LineFit f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  double sse = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = y[i] - (f.slope * x[i] + f.intercept);
    sse += r * r;
  }
  f.r2 = syy > 0 ? 1 - sse / syy : 1.0;
  return f;
}

// parse_slot_tests between lines: the header's values, the columns, the frame
// the forces are given in.
class SlotParser {
 public:
  SlotParser(const std::string& file, SlotTestData& d) : file_(file), d_(d) {}
  void line(const std::string& line, int line_no);
  // After the last line.
  void finish(int line_no);

 private:
  void header_line(const std::string& t, int line_no);
  void columns(const std::vector<Field>& f, int line_no);
  SlotTest test(const std::vector<Field>& f, int line_no) const;

  const std::string& file_;
  SlotTestData& d_;
  std::map<std::string, std::pair<std::string, int>> header_;  // key -> value, line
  std::map<std::string, std::size_t> col_;                     // column name -> index
  bool on_workpiece_ = false;
  bool have_columns_ = false;
};

// A `# key: value` line before the header row.
void SlotParser::header_line(const std::string& t, int line_no) {
  const std::size_t colon = t.find(':');
  if (colon == std::string::npos || have_columns_) return;
  const std::string key = trim(t.substr(1, colon - 1));
  const std::string val = trim(t.substr(colon + 1));
  if (key == "diameter_mm" || key == "flutes" || key == "ap_mm" || key == "helix_deg") {
    if (!to_number(val)) bad(file_, line_no, 1, key + " must be a number, not '" + val + "'");
    header_[key] = {val, line_no};
  } else if (key == "material") {
    d_.material = val;
  } else if (key == "tool") {
    d_.tool = val;
  } else if (key == "forces_on") {
    if (val != "tool" && val != "workpiece") bad(file_, line_no, 1, "forces_on must be 'tool' or 'workpiece'");
    on_workpiece_ = val == "workpiece";
  }
}

// The header row: the column names.
void SlotParser::columns(const std::vector<Field>& f, int line_no) {
  for (std::size_t i = 0; i < f.size(); ++i) {
    static const char* known[] = {"fz_mm", "Fx_N", "Fy_N", "Fz_N", "ap_mm", "flutes", "diameter_mm"};
    bool ok = false;
    for (const char* k : known) ok = ok || f[i].text == k;
    if (!ok)
      bad(file_, line_no, f[i].col,
          "unknown column '" + f[i].text + "' (expected fz_mm, Fx_N, Fy_N, Fz_N, ap_mm, flutes, diameter_mm)");
    if (col_.count(f[i].text)) bad(file_, line_no, f[i].col, "column '" + f[i].text + "' given twice");
    col_[f[i].text] = i;
  }
  for (const char* k : {"fz_mm", "Fx_N", "Fy_N", "Fz_N"})
    if (!col_.count(k)) bad(file_, line_no, 1, std::string("missing column '") + k + "'");
  for (const char* k : {"ap_mm", "flutes"})
    if (!col_.count(k) && !header_.count(k))
      bad(file_, line_no, 1, std::string("'") + k + "' must be a column or a '# " + k + ": value' line");
  have_columns_ = true;
}

// A data row: one slot test (forces given on the workpiece turned onto the tool).
SlotTest SlotParser::test(const std::vector<Field>& f, int line_no) const {
  if (f.size() != col_.size())
    bad(file_, line_no, 1, "expected " + std::to_string(col_.size()) + " fields, found " + std::to_string(f.size()));
  auto value = [&](const std::string& key) -> double {
    auto it = col_.find(key);
    if (it == col_.end()) return *to_number(header_.at(key).first);
    const Field& fld = f[it->second];
    const auto v = to_number(fld.text);
    if (!v) bad(file_, line_no, fld.col, key + " must be a number, not '" + fld.text + "'");
    return *v;
  };
  SlotTest s;
  s.line = line_no;
  s.fz_mm = value("fz_mm");
  s.ap_mm = value("ap_mm");
  const double nf = value("flutes");
  s.diameter_mm = (col_.count("diameter_mm") || header_.count("diameter_mm")) ? value("diameter_mm") : 0;
  s.mean_N = {value("Fx_N"), value("Fy_N"), value("Fz_N")};
  if (on_workpiece_) s.mean_N = -s.mean_N;
  if (!(s.fz_mm > 0)) bad(file_, line_no, 1, "fz_mm must be > 0");
  if (!(s.ap_mm > 0)) bad(file_, line_no, 1, "ap_mm must be > 0");
  if (nf < 1 || nf != std::floor(nf)) bad(file_, line_no, 1, "flutes must be a whole number >= 1");
  s.flutes = static_cast<int>(nf);
  return s;
}

void SlotParser::line(const std::string& line, int line_no) {
  const std::string t = trim(line);
  if (t.empty()) return;
  if (t[0] == '#') return header_line(t, line_no);
  const std::vector<Field> f = split(line);
  if (!have_columns_) return columns(f, line_no);
  d_.tests.push_back(test(f, line_no));
}

void SlotParser::finish(int line_no) {
  if (!have_columns_) bad(file_, line_no > 0 ? line_no : 1, 1, "no header row (fz_mm,Fx_N,Fy_N,Fz_N,...)");
  if (header_.count("helix_deg")) d_.helix_deg = *to_number(header_["helix_deg"].first);
}

}  // namespace

SlotTestData parse_slot_tests(const std::string& text, const std::string& file) {
  SlotTestData d;
  d.file = file;
  SlotParser parser(file, d);
  int line_no = 0;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    parser.line(line, line_no);
  }
  parser.finish(line_no);
  return d;
}

SlotTestData load_slot_tests(const std::string& path) {
  return parse_slot_tests(yaml::read_file(path), path);
}

Eigen::Vector3d slot_mean_force(const Coefficients& k, int flutes, double ap_mm, double fz_mm) {
  const double na = flutes * ap_mm;
  // Altintas 2012 ch. 2, mean forces between phi_st = 0 and phi_ex = pi.
  return {na * (-k.Krc_N_per_mm2 * fz_mm / 4 - k.Kre_N_per_mm / pi),
          na * (k.Ktc_N_per_mm2 * fz_mm / 4 + k.Kte_N_per_mm / pi),
          na * (-k.Kac_N_per_mm2 * fz_mm / pi - k.Kae_N_per_mm / 2)};
}

SlotCalibration calibrate_slot_tests(const SlotTestData& data) {
  const auto& t = data.tests;
  bool distinct = false;
  for (const auto& s : t) distinct = distinct || std::abs(s.fz_mm - t.front().fz_mm) > 1e-12;
  if (t.size() < 2 || !distinct)
    throw Error(ErrorKind::input, data.file + ": error: calibration needs tests at two or more different feeds per tooth");
  std::vector<double> x;
  std::array<std::vector<double>, 3> y;
  for (const auto& s : t) {
    x.push_back(s.fz_mm);
    for (int a = 0; a < 3; ++a) y[a].push_back(s.mean_N[a] / (s.flutes * s.ap_mm));
  }
  SlotCalibration c;
  for (int a = 0; a < 3; ++a) c.fit[a] = fit_line(x, y[a]);
  c.k.Krc_N_per_mm2 = -4 * c.fit[0].slope;
  c.k.Kre_N_per_mm = -pi * c.fit[0].intercept;
  c.k.Ktc_N_per_mm2 = 4 * c.fit[1].slope;
  c.k.Kte_N_per_mm = pi * c.fit[1].intercept;
  c.k.Kac_N_per_mm2 = -pi * c.fit[2].slope;
  c.k.Kae_N_per_mm = -2 * c.fit[2].intercept;
  Eigen::Vector3d ss = Eigen::Vector3d::Zero();
  for (const auto& s : t) {
    const Eigen::Vector3d p = slot_mean_force(c.k, s.flutes, s.ap_mm, s.fz_mm);
    c.predicted_N.push_back(p);
    c.residual_N.push_back(s.mean_N - p);
    ss += (s.mean_N - p).cwiseAbs2();
  }
  c.rms_residual_N = (ss / static_cast<double>(t.size())).cwiseSqrt();
  return c;
}

}  // namespace deflex::force
