// job::fitted_profile_text() (fit.hpp): the starting profile's text with its
// numbers replaced where they stand, so that its comments, order and every
// section the fit does not touch stay as the shop wrote them.
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "deflex/job/fit.hpp"
#include "deflex/profile/yaml.hpp"

namespace deflex::job {

namespace {

struct Edit {
  std::size_t pos = 0, length = 0;
  std::string text;
};

// The extent of the plain or quoted scalar starting at `pos` of `text`:
// yaml-cpp marks where a node starts, not where it ends, and its emitter
// would rewrite the whole file without its comments.
std::size_t scalar_length(const std::string& text, std::size_t pos) {
  if (pos < text.size() && (text[pos] == '"' || text[pos] == '\'')) {
    const std::size_t close = text.find(text[pos], pos + 1);
    return close == std::string::npos ? text.size() - pos : close + 1 - pos;
  }
  std::size_t end = pos;
  while (end < text.size() && text[end] != '\n' && text[end] != ',' && text[end] != '}' && text[end] != ']' &&
         !(text[end] == '#' && end > pos && text[end - 1] == ' '))
    ++end;
  while (end > pos && (text[end - 1] == ' ' || text[end - 1] == '\t' || text[end - 1] == '\r')) --end;
  return end - pos;
}

std::string number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.5g", v);
  return b;
}

void scale_scalar(const YAML::Node& n, double factor, const std::string& text, std::vector<Edit>& edits) {
  if (!n || !n.IsScalar()) return;
  const std::size_t pos = static_cast<std::size_t>(n.Mark().pos);
  edits.push_back({pos, scalar_length(text, pos), number(n.as<double>() * factor)});
}

void scale_springs(const YAML::Node& springs, double factor, const std::string& text, std::vector<Edit>& edits) {
  if (!springs || !springs.IsMap()) return;
  for (const char* k : {"radial_N_per_um", "rotational_Nm_per_rad", "axial_N_per_um"}) scale_scalar(springs[k], factor, text, edits);
}

void scale_structure(const YAML::Node& st, const fit::Scales& s, const std::string& text, std::vector<Edit>& edits) {
  if (!st || !st.IsMap()) return;
  const int x = int(fit::Param::structure_x);
  if (const YAML::Node k = st["stiffness_N_per_um"]) {
    const char* axes[] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) scale_scalar(k.IsMap() ? k[axes[a]] : k[a], s[x + a], text, edits);
  }
  if (const YAML::Node c = st["compliance_mm_per_N"])
    for (int a = 0; a < 3; ++a) scale_scalar(c[a][a], 1 / s[x + a], text, edits);  // stiffer: less compliant
}

}  // namespace

std::string fitted_profile_text(const std::string& file, const fit::Scales& s, const std::vector<std::string>& provenance) {
  const std::string text = yaml::read_file(file);
  const YAML::Node root = yaml::load_text(text, file);
  std::vector<Edit> edits;
  if (const YAML::Node st = root["stiffness"]) {
    scale_springs(st["tool_clamp"], s[int(fit::Param::clamp)], text, edits);
    scale_springs(st["spindle"], s[int(fit::Param::spindle)], text, edits);
    scale_structure(st["structure"], s, text, edits);
  }
  const double force = s[int(fit::Param::coefficients)];
  if (const YAML::Node f = root["force_scale"]) {
    const std::size_t pos = static_cast<std::size_t>(f.Mark().pos);
    edits.push_back({pos, scalar_length(text, pos), number(force)});
  }
  if (const YAML::Node n = root["name"]; n && n.IsScalar()) {
    const std::size_t pos = static_cast<std::size_t>(n.Mark().pos);
    const std::string name = n.as<std::string>();  // a profile fitted again keeps one suffix
    edits.push_back({pos, scalar_length(text, pos), name.ends_with("-fitted") ? name : name + "-fitted"});
  }
  std::sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.pos > b.pos; });
  std::string body = text;
  for (const Edit& e : edits) body.replace(e.pos, e.length, e.text);
  if (!body.empty() && body.back() != '\n') body += '\n';
  if (!root["force_scale"])
    body += "force_scale: " + number(force) + "         # the material's force coefficients on this machine (fitted)\n";
  std::ostringstream out;
  for (const std::string& line : provenance) out << "# " << line << "\n";
  out << "#\n" << body;
  return out.str();
}

}  // namespace deflex::job
