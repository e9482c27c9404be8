// The workpiece model: the part's solid meshed by gmsh (solid_mesh.cpp), held
// by its fixtures, its stiffness factorised once by the solid model's FEM
// (solid_fem.cpp, ElasticSolver), and asked at any number of surface points.
#include "deflex/stiffness/workpiece.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <unistd.h>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stock/mesh_out.hpp"
#include "deflex/writer/temp_files.hpp"
#include "occt_api.hpp"
#include "solid_internal.hpp"

namespace deflex::stiffness {

namespace {

using V3 = Eigen::Vector3d;
namespace fs = std::filesystem;

std::string fmt3(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The part for gmsh in a temporary file, removed when it goes out of scope:
// STEP and IGES as the .brep of their solid(s) (OpenCASCADE, in its plugin),
// an STL as the triangles deflex read (binary STL).
struct PartFile {
  std::string path;
  int slot = -1;
  explicit PartFile(const PartSurface& s) {
    if (!s.boxes.empty()) return;  // meshed from the boxes themselves
    static int counter = 0;
    path = (fs::temp_directory_path() / ("deflex-part-" + std::to_string(::getpid()) + "-" +
                                         std::to_string(counter++) + (s.stl ? ".stl" : ".brep")))
               .string();
    slot = writer::temp_files::add(path);
    std::string ext = fs::path(s.file).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (s.stl) {
      std::ofstream out(path, std::ios::binary);
      stock::write_binary_stl(out, s.triangles, "deflex workpiece");
      if (!out) throw Error(ErrorKind::io, path + ": error: cannot write the temporary STL file");
    } else {
      occt::api().write_part_brep(s.file, ext == ".step" || ext == ".stp", path);
    }
  }
  ~PartFile() {
    if (path.empty()) return;
    std::error_code ec;
    fs::remove(path, ec);
    writer::temp_files::forget(slot);
  }
  solid::TetMesh mesh(const PartSurface& s, double h_mm) const {
    if (!s.boxes.empty()) return solid::mesh_boxes(s.boxes, h_mm);
    return s.stl ? solid::mesh_stl(path, h_mm) : solid::mesh_brep(path, h_mm, false);
  }
};

// The mesh's boundary: the faces that belong to one tet only (the corner
// triple sorted as the key), their nodes (a face's mid-edge nodes come with
// it) and their corner triangles.
struct Boundary {
  std::vector<char> on;  // per node
  PartSurface faces;
};

Boundary boundary_of(const solid::TetMesh& m) {
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  std::map<std::array<int, 3>, std::pair<int, std::size_t>> faces;  // key -> (count, tet*4 + face)
  for (std::size_t e = 0; e < m.tet.size(); ++e)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> k{m.tet[e][kFace[f][0]], m.tet[e][kFace[f][1]], m.tet[e][kFace[f][2]]};
      std::sort(k.begin(), k.end());
      auto& v = faces[k];
      v = {v.first + 1, 4 * e + f};
    }
  Boundary b;
  std::vector<char>& on = b.on;
  on.assign(m.node_mm.size(), 0);
  for (const auto& [k, v] : faces) {
    if (v.first != 1) continue;
    stock::Triangle tri;
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 3; ++i) tri.p[c][i] = m.node_mm[k[c]](i);
    b.faces.triangles.push_back(tri);
    const auto& t = m.tet[v.second / 4];
    const int skip = static_cast<int>(v.second % 4);  // the corner opposite the face
    for (int a = 0; a < 10; ++a) {
      const bool corner = a < 4 && a != skip;
      const bool edge = a >= 4 && solid::kEdges[a - 4][0] != skip && solid::kEdges[a - 4][1] != skip;
      if (corner || edge) on[t[a]] = 1;
    }
  }
  return b;
}

bool inside(const stock::BoxSpec& b, const V3& p, double tol) {
  return p(0) >= std::min(b.x0_mm, b.x1_mm) - tol && p(0) <= std::max(b.x0_mm, b.x1_mm) + tol &&
         p(1) >= std::min(b.y0_mm, b.y1_mm) - tol && p(1) <= std::max(b.y0_mm, b.y1_mm) + tol &&
         p(2) >= std::min(b.z0_mm, b.z1_mm) - tol && p(2) <= std::max(b.z0_mm, b.z1_mm) + tol;
}

// Surface nodes inside any box are fixed. A box without a node, or fixed
// nodes all in a line (the part could turn about it), is an error.
std::vector<char> clamp(const solid::TetMesh& m, const std::vector<char>& on, const std::vector<Fixture>& fixtures,
                        double mesh_mm, std::size_t& fixed_count) {
  std::vector<char> fixed(m.node_mm.size(), 0);
  const double tol = 1e-6 * std::max(1.0, mesh_mm);
  std::vector<V3> held;
  for (const auto& f : fixtures) {
    std::size_t n = 0;
    for (std::size_t a = 0; a < m.node_mm.size(); ++a)
      if (on[a] && inside(f.box, m.node_mm[a], tol)) {
        ++n;
        if (!fixed[a]) held.push_back(m.node_mm[a]);
        fixed[a] = 1;
      }
    if (n == 0) {
      char b[64];
      std::snprintf(b, sizeof b, "%.3g mm", mesh_mm);
      throw Error(ErrorKind::settings, "the fixture box " + f.spec + " touches the part's surface but holds no node of its mesh (elements of " + b + "): make the box larger or the mesh finer");
    }
  }
  fixed_count = held.size();
  double spread = 0;  // the largest distance of a held node from the line through two of them
  if (held.size() >= 3) {
    const auto far = std::max_element(held.begin(), held.end(), [&](const V3& a, const V3& b) {
      return (a - held[0]).squaredNorm() < (b - held[0]).squaredNorm();
    });
    const V3 axis = (*far - held[0]).normalized();
    for (const V3& p : held) spread = std::max(spread, ((p - held[0]) - (p - held[0]).dot(axis) * axis).norm());
  }
  if (!(spread > 1e-3 * mesh_mm))
    throw Error(ErrorKind::settings, "the fixtures hold the part only along a line (" + std::to_string(held.size()) +
                                         " mesh nodes): it could turn about it; give boxes that hold a face");
  return fixed;
}

// A sparse Cholesky of a 3D mesh grows faster than its dofs (fill-in): past
// a million dofs it outgrows the memory of a workstation. Quadratic tets of
// size h give some 32 V / h^3 dofs (a 10 x 2 x 40 mm strip at 1 mm: 25,000),
// so a size that would make too many is refused before meshing, and a mesh
// that came out larger (small features) after it.
constexpr double kMaxDofs = 1e6;

void check_size_before(const PartSurface& part, double mesh_mm, double wall_mm, bool given) {
  const double volume = enclosed_volume_mm3(part), dofs = 32 * volume / (mesh_mm * mesh_mm * mesh_mm);
  if (dofs <= kMaxDofs) return;
  const std::string why = given ? "" : " (the default: half its thinnest wall, " + fmt3(wall_mm) +
                                            " mm, at least a 150th of its size)";
  char b[320];
  std::snprintf(b, sizeof b,
                "elements of %.3g mm%s would give %s some %.2g dofs, more than deflex factorises (%.0e): give "
                "an element size of %.2g mm or more",
                mesh_mm, why.c_str(), part.file.c_str(), dofs, kMaxDofs, std::cbrt(32 * volume / kMaxDofs));
  throw Error(ErrorKind::settings, b);
}

void check_size_after(const solid::TetMesh& m, const PartSurface& part, double mesh_mm) {
  if (3.0 * static_cast<double>(m.node_mm.size()) <= kMaxDofs) return;
  char b[200];
  std::snprintf(b, sizeof b, "the mesh of %s has %zu dofs (elements of %.3g mm), more than deflex factorises (%.0e): ",
                part.file.c_str(), 3 * m.node_mm.size(), mesh_mm, kMaxDofs);
  throw Error(ErrorKind::settings, std::string(b) + "give larger elements");
}

}  // namespace

struct WorkpieceModel::Impl {
  PartSurface part;
  WorkpieceOptions opt;
  WorkpieceInfo info;
  solid::TetMesh mesh;
  PartSurface mesh_surface;  // the mesh's boundary faces
  std::unique_ptr<solid::ElasticSolver> fem;

  // The patch around the surface point nearest p (returned in surface),
  // centred on the mesh's own boundary: a remeshed curved surface lies off
  // the part's facets by its chords, which may exceed a small patch.
  solid::Patch patch(const V3& p, V3& surface) const {
    surface = check_on_part(part, p, opt.on_part_mm).point_mm;
    return solid::patch_weights(mesh, nearest_surface_point(mesh_surface, surface).point_mm, info.patch_radius_mm);
  }
};

WorkpieceModel::WorkpieceModel(const PartSurface& part, const std::vector<Fixture>& fixtures, const Material& m,
                               const WorkpieceOptions& o)
    : impl_(std::make_unique<Impl>()) {
  check_fixtures(part, fixtures);
  if (!(o.mesh_mm >= 0) || !(o.patch_radius_mm >= 0))
    throw Error(ErrorKind::settings, "the workpiece's mesh size and patch radius must be >= 0 mm (0: the default)");
  Impl& d = *impl_;
  d.part = part;
  d.opt = o;
  WorkpieceInfo& inf = d.info;
  inf.thinnest_wall_mm = thinnest_wall_mm(part);
  inf.mesh_mm = o.mesh_mm > 0 ? o.mesh_mm : default_workpiece_mesh_mm(part, inf.thinnest_wall_mm);
  // A quarter of the wall, and of an element: a patch smaller than the
  // elements' chords off a curved surface could miss the mesh.
  inf.patch_radius_mm = o.patch_radius_mm > 0 ? o.patch_radius_mm
                        : std::isfinite(inf.thinnest_wall_mm) ? std::max(inf.thinnest_wall_mm, inf.mesh_mm) / 4
                                                             : inf.mesh_mm / 2;
  check_size_before(part, inf.mesh_mm, inf.thinnest_wall_mm, o.mesh_mm > 0);
  auto t0 = std::chrono::steady_clock::now();
  {
    const PartFile file(part);
    d.mesh = file.mesh(part, inf.mesh_mm);
  }
  inf.straightened = solid::straighten_inverted(d.mesh);
  check_size_after(d.mesh, part, inf.mesh_mm);
  inf.mesh_seconds = seconds_since(t0);
  inf.nodes = d.mesh.node_mm.size();
  inf.elements = d.mesh.tet.size();
  Boundary boundary = boundary_of(d.mesh);
  const std::vector<char> fixed = clamp(d.mesh, boundary.on, fixtures, inf.mesh_mm, inf.fixed_nodes);
  d.mesh_surface = std::move(boundary.faces);
  t0 = std::chrono::steady_clock::now();
  d.fem = std::make_unique<solid::ElasticSolver>(d.mesh, m, fixed);
  inf.solve_seconds = seconds_since(t0);
  inf.dofs = d.fem->dofs();
}

WorkpieceModel::WorkpieceModel(WorkpieceModel&&) noexcept = default;
WorkpieceModel& WorkpieceModel::operator=(WorkpieceModel&&) noexcept = default;
WorkpieceModel::~WorkpieceModel() = default;

PointCompliance WorkpieceModel::compliance_at(const V3& p) const {
  PointCompliance r;
  const solid::Patch w = impl_->patch(p, r.surface_mm);
  r.point_mm = p;
  r.load_centroid_mm = w.centroid_mm;
  r.matrix_mm_per_N = impl_->fem->compliance(w);
  return r;
}

std::vector<PointCompliance> WorkpieceModel::compliance_at(const std::vector<V3>& points_mm) const {
  std::vector<PointCompliance> r(points_mm.size());
  for (std::size_t b = 0; b < points_mm.size(); b += kBatchPoints) {
    const std::size_t e = std::min(points_mm.size(), b + kBatchPoints);
    std::vector<solid::Patch> w;
    for (std::size_t i = b; i < e; ++i) {
      w.push_back(impl_->patch(points_mm[i], r[i].surface_mm));
      r[i].point_mm = points_mm[i];
      r[i].load_centroid_mm = w.back().centroid_mm;
    }
    const Eigen::MatrixXd u = impl_->fem->solve(w);
    for (std::size_t i = b; i < e; ++i)
      r[i].matrix_mm_per_N = impl_->fem->read(w[i - b], u.middleCols(3 * static_cast<Eigen::Index>(i - b), 3));
  }
  return r;
}

Compliance WorkpieceModel::transfer(const V3& load_mm, const V3& read_mm) const {
  V3 at;
  return impl_->fem->read(impl_->patch(read_mm, at), impl_->fem->solve(impl_->patch(load_mm, at)));
}

const WorkpieceInfo& WorkpieceModel::info() const { return impl_->info; }

}  // namespace deflex::stiffness
