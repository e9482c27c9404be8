// Solid model driver: stations, cache, and the machine in series.
//
// Load patch: a point load is singular in 3D elasticity (the displacement under
// it is infinite), so each station's unit force is spread over a ball of radius
// r (default a quarter of the fluted radius) centred on the tool axis, with the
// smooth weight (1 - d^2/r^2)^2, and the displacement is read back as the
// average under the same weights: C = W^T K^-1 W, symmetric by construction.
// The row's height is the weighted centroid of the patch. Stations start one
// patch radius above the tip so the patch lies inside the body; C(0) is
// extrapolated by the parabola through the first three stations (the bending
// compliance is a smooth cubic in h there; beam theory error < 0.1%).
#include "deflex/stiffness/solid.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stiffness/beam.hpp"
#include "deflex/stiffness/shape.hpp"
#include "deflex/writer/temp_files.hpp"
#include "solid_internal.hpp"

namespace deflex::stiffness {

namespace fs = std::filesystem;

double default_mesh_size_mm(const Tool& t) { return t.flute_diameter_ratio * t.diameter_mm / 5; }

double default_patch_radius_mm(const Tool& t) {
  return 0.25 * 0.5 * t.flute_diameter_ratio * t.diameter_mm;
}

std::string default_cache_dir() {
  if (const char* d = std::getenv("DEFLEX_CACHE_DIR"); d && *d) return d;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/deflex";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/deflex";
  return "";
}

namespace {

// FNV-1a, 64 bit: a stable hash for cache file names (not for security).
std::uint64_t fnv1a(const std::string& s, std::uint64_t h = 1469598103934665603ull) {
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::io, path + ": error: cannot read the STEP file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Everything the result depends on, as text.
std::string cache_key(const Tool& t, double h_mm, double r_mm, const std::vector<double>& centres) {
  std::string k = "deflex-solid-v1|E=" + num(t.material.E_MPa) + "|nu=" + num(t.material.poisson) +
                  "|mesh=" + num(h_mm) + "|patch=" + num(r_mm) + "|clamp=" + num(t.stickout_mm);
  if (!t.step_file.empty()) {
    k += "|step=" + std::to_string(fnv1a(read_file(t.step_file)));
  } else {
    const ToolShape s = tool_shape(t);
    k += "|cap=" + num(s.cap_height_mm) + "," + num(s.cap_offset_mm) + "," + num(s.cap_semi_axis_mm);
    for (const auto& c : s.cylinders) k += "|cyl=" + num(c.z0_mm) + "," + num(c.z1_mm) + "," + num(c.radius_mm);
  }
  k += "|stations=";
  for (double c : centres) k += num(c) + ",";
  return k;
}

std::optional<ComplianceTable> read_cache(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line) || line != key) return std::nullopt;
  std::vector<ComplianceRow> rows;
  ComplianceRow r;
  while (in >> r.height_mm) {
    for (int i = 0; i < 9; ++i) in >> r.matrix_mm_per_N(i / 3, i % 3);
    if (!in) return std::nullopt;
    rows.push_back(r);
  }
  if (rows.empty()) return std::nullopt;
  return ComplianceTable(std::move(rows));
}

// Best effort: a cache that cannot be written only costs time.
void write_cache(const std::string& path, const std::string& key, const ComplianceTable& t) {
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  const int slot = writer::temp_files::add(tmp);
  bool ok = false;
  {
    std::ofstream out(tmp);
    out << key << "\n";
    for (const auto& r : t.rows()) {
      out << num(r.height_mm);
      for (int i = 0; i < 9; ++i) out << " " << num(r.matrix_mm_per_N(i / 3, i % 3));
      out << "\n";
    }
    ok = static_cast<bool>(out);
  }
  if (ok) fs::rename(tmp, path, ec);
  if (!ok || ec) fs::remove(tmp, ec);
  writer::temp_files::forget(slot);
}

// Temporary file removed when it goes out of scope (or by the signal handler:
// writer/temp_files.hpp).
struct TempFile {
  std::string path;
  int slot = -1;
  explicit TempFile(const std::string& ext) {
    static int counter = 0;
    path = (fs::temp_directory_path() /
            ("deflex-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ext))
               .string();
    slot = writer::temp_files::add(path);
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove(path, ec);
    writer::temp_files::forget(slot);
  }
};

// Rows at the patch centroids plus C(0) from the parabola through the first three.
ComplianceTable table_of(const std::vector<solid::Station>& st) {
  std::vector<ComplianceRow> rows;
  for (const auto& s : st) rows.push_back({s.height_mm, s.c});
  if (rows.size() >= 3 && rows[0].height_mm > 1e-9) {
    const double x0 = rows[0].height_mm, x1 = rows[1].height_mm, x2 = rows[2].height_mm;
    // Lagrange basis at h = 0.
    const double l0 = x1 * x2 / ((x0 - x1) * (x0 - x2));
    const double l1 = x0 * x2 / ((x1 - x0) * (x1 - x2));
    const double l2 = x0 * x1 / ((x2 - x0) * (x2 - x1));
    rows.push_back({0.0, l0 * rows[0].matrix_mm_per_N + l1 * rows[1].matrix_mm_per_N +
                             l2 * rows[2].matrix_mm_per_N});
  }
  return ComplianceTable(std::move(rows));
}

}  // namespace

ComplianceTable solid_tool_compliance(const Tool& t, const SolidOptions& opt, SolidInfo* info) {
  const auto t0 = std::chrono::steady_clock::now();
  SolidInfo local;
  SolidInfo& inf = info ? *info : local;
  inf = {};
  const double h = opt.mesh_size_mm > 0 ? opt.mesh_size_mm : default_mesh_size_mm(t);
  const double r = opt.patch_radius_mm > 0 ? opt.patch_radius_mm : default_patch_radius_mm(t);
  // Patch centres from one radius above the tip to the top of the flutes, kept
  // a radius and a half clear of the clamp.
  const double top = std::min(t.flute_length_mm, t.stickout_mm - 1.5 * r);
  const int steps = std::max(2, opt.station_steps);
  std::vector<double> centres;
  for (int i = 0; i <= steps; ++i) centres.push_back(r + (top - r) * i / steps);

  const std::string key = cache_key(t, h, r, centres);
  const std::string dir = opt.cache_dir ? *opt.cache_dir : default_cache_dir();
  if (!dir.empty()) {
    char name[40];
    std::snprintf(name, sizeof name, "solid-%016llx.txt", static_cast<unsigned long long>(fnv1a(key)));
    inf.cache_file = (fs::path(dir) / name).string();
    if (auto cached = read_cache(inf.cache_file, key)) {
      inf.from_cache = true;
      inf.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return *cached;
    }
  }

  const TempFile brep(".brep");
  solid::write_tool_brep(t, brep.path);
  const solid::TetMesh mesh = solid::mesh_brep(brep.path, h, !t.step_file.empty());
  std::vector<solid::Station> st;
  for (double c : centres) st.push_back({c, c, Compliance::Zero()});
  const solid::FemStats fem = solid::solve_stations(mesh, t.material, t.stickout_mm, r, st);
  const ComplianceTable table = table_of(st);

  inf.nodes = mesh.node_mm.size();
  inf.elements = mesh.tet.size();
  inf.dofs = fem.dofs;
  if (!inf.cache_file.empty()) write_cache(inf.cache_file, key, table);
  inf.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return table;
}

ComplianceTable solid_compliance(const Tool& t, const MachineStiffness& m, bool tool_only,
                                 const SolidOptions& opt, SolidInfo* info) {
  const ComplianceTable tool = solid_tool_compliance(t, opt, info);
  return tool_only ? tool : add_machine(tool, t, m);
}

}  // namespace deflex::stiffness
