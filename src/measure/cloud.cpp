// Point clouds by extension, and the dispatcher over all four forms (measured.hpp).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>
#include <tuple>

#include "deflex/measure/measured.hpp"
#include "deflex/profile/yaml.hpp"
#include "deflex/stock/build.hpp"
#include "deflex/measure/text.hpp"

namespace deflex::measure {
namespace {

std::string extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// The distinct corners of an STL's triangles, in the order they first appear.
std::vector<Sample> stl_vertices(const std::string& path) {
  std::vector<Sample> out;
  std::set<std::tuple<double, double, double>> seen;
  for (const stock::Triangle& t : stock::read_stl(path))
    for (const auto& p : t.p)
      if (seen.emplace(p[0], p[1], p[2]).second) {
        Sample s;
        s.p_mm = {p[0], p[1], p[2]};
        out.push_back(s);
      }
  if (out.empty()) throw Error(ErrorKind::input, path + ": error: the STL has no triangle, so no point");
  return out;
}

// The first line that is neither blank nor '%' starts with PT: DPRNT output.
bool looks_like_dprnt(const std::string& text) {
  const SourceText src("", text);
  for (std::uint32_t l = 1; l <= src.line_count(); ++l) {
    const std::string_view t = detail::trim(src.line_text(l));
    if (t.empty() || t == "%") continue;
    return t.starts_with("PT");
  }
  return false;
}

}  // namespace

std::vector<Sample> read_point_cloud(const std::string& path) {
  const std::string e = extension(path);
  if (e == ".ply") return parse_ply(yaml::read_file(path), path);
  if (e == ".stl") return stl_vertices(path);
  throw Error(ErrorKind::input, path + ": error: not a point cloud deflex reads (expected .ply or .stl)");
}

Measured read_measured(const std::string& path, const std::string& probe_program, double limit_mm) {
  Measured m;
  const std::string e = extension(path);
  if (e == ".csv") {
    m.form = MeasuredForm::points_csv;
    m.samples = read_points_csv(yaml::read_file(path), path);
    return m;
  }
  if (e == ".ply" || e == ".stl") {
    m.form = MeasuredForm::point_cloud;
    m.samples = read_point_cloud(path);
    return m;
  }
  if (probe_program.empty())
    throw Error(ErrorKind::settings, path + ": a probe log is read with the probe program that wrote it; none given");
  const std::vector<ProbeTarget> targets = read_probe_targets(yaml::read_file(probe_program), probe_program);
  const std::string log = yaml::read_file(path);
  const bool dprnt = looks_like_dprnt(log);
  m.form = dprnt ? MeasuredForm::dprnt : MeasuredForm::linuxcnc_log;
  const std::vector<Sample> samples = dprnt ? read_dprnt(log, path) : read_linuxcnc_probe_log(log, path);
  m.points = join_probe_log(targets, samples, dprnt, path, log, limit_mm);
  return m;
}

}  // namespace deflex::measure
