// The tool solid's quadratic tetrahedral mesh (gmsh API); the solid itself
// is OpenCASCADE's, in deflex's plugin (solid_occt.cpp).
#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "deflex/diag/diagnostics.hpp"
#include "gmsh_runtime.hpp"
#include "solid_internal.hpp"

namespace deflex::stiffness::solid {

namespace {

// gmsh is one global state: initialise once, one mesh at a time.
std::mutex& gmsh_mutex() {
  static std::mutex m;
  return m;
}
const gmshrt::Api& ensure_gmsh() {
  const gmshrt::Api& g = gmshrt::api();
  static bool done = [&g] {
    int ierr = 0;
    g.initialize(0, nullptr, 0, &ierr);
    gmshrt::check(ierr, "gmsh could not start");
    g.option_set_number("General.Terminal", 0, &ierr);
    g.option_set_number("General.Verbosity", 1, &ierr);
    return true;
  }();
  (void)done;
  return g;
}

// My node slot (0-9) of each gmsh local node of a 10-node tet, from the
// reference coordinates gmsh reports (corner k at 0, e1, e2, e3).
std::array<int, 10> gmsh_to_local(const gmshrt::Api& g) {
  char* name = nullptr;
  int dim = 0, order = 0, n = 0, nprim = 0, ierr = 0;
  double* ref_c = nullptr;
  std::size_t ref_n = 0;
  g.mesh_get_element_properties(11, &name, &dim, &order, &n, &ref_c, &ref_n, &nprim, &ierr);
  gmshrt::check(ierr, "gmsh: no properties of the 10-node tetrahedron");
  const std::vector<double> ref(ref_c, ref_c + ref_n);
  g.free(name);
  g.free(ref_c);
  if (n != 10 || ref.size() < 30) throw Error(ErrorKind::internal, "gmsh: unexpected 10-node tet layout");
  std::array<int, 10> slot{};
  for (int k = 0; k < 10; ++k) {
    const double x = ref[3 * k], y = ref[3 * k + 1], z = ref[3 * k + 2];
    const std::array<double, 4> L{1 - x - y - z, x, y, z};
    std::vector<int> half, one;
    for (int c = 0; c < 4; ++c) {
      if (std::abs(L[c] - 1) < 1e-9) one.push_back(c);
      if (std::abs(L[c] - 0.5) < 1e-9) half.push_back(c);
    }
    if (one.size() == 1) {
      slot[k] = one[0];
    } else if (half.size() == 2) {
      const auto it = std::find(kEdges.begin(), kEdges.end(), std::array<int, 2>{half[0], half[1]});
      slot[k] = 4 + static_cast<int>(it - kEdges.begin());
    } else {
      throw Error(ErrorKind::internal, "gmsh: unexpected 10-node tet node");
    }
  }
  return slot;
}

TetMesh read_mesh(const gmshrt::Api& g) {
  std::size_t *tags_c = nullptr, tags_n = 0, xyz_n = 0, par_n = 0;
  double *xyz_c = nullptr, *par_c = nullptr;
  int ierr = 0;
  g.mesh_get_nodes(&tags_c, &tags_n, &xyz_c, &xyz_n, &par_c, &par_n, -1, -1, 0, 0, &ierr);
  gmshrt::check(ierr, "gmsh: cannot read the mesh nodes");
  const std::vector<std::size_t> tags(tags_c, tags_c + tags_n);
  const std::vector<double> xyz(xyz_c, xyz_c + xyz_n);
  g.free(tags_c);
  g.free(xyz_c);
  g.free(par_c);
  if (tags.empty() || xyz.size() != 3 * tags.size()) throw Error(ErrorKind::internal, "gmsh: no mesh nodes");
  TetMesh mesh;
  std::vector<int> index(*std::max_element(tags.begin(), tags.end()) + 1, -1);
  for (std::size_t i = 0; i < tags.size(); ++i) {
    index[tags[i]] = static_cast<int>(i);
    mesh.node_mm.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  }
  const std::array<int, 10> slot = gmsh_to_local(g);
  std::size_t *etags_c = nullptr, etags_n = 0, *enodes_c = nullptr, enodes_n = 0;
  g.mesh_get_elements_by_type(11, &etags_c, &etags_n, &enodes_c, &enodes_n, -1, 0, 1, &ierr);
  gmshrt::check(ierr, "gmsh: cannot read the tetrahedra");
  const std::vector<std::size_t> etags(etags_c, etags_c + etags_n), enodes(enodes_c, enodes_c + enodes_n);
  g.free(etags_c);
  g.free(enodes_c);
  if (enodes.size() != 10 * etags.size()) throw Error(ErrorKind::internal, "gmsh: unexpected tetrahedron connectivity");
  mesh.tet.resize(etags.size());
  for (std::size_t e = 0; e < etags.size(); ++e)
    for (int k = 0; k < 10; ++k) mesh.tet[e][slot[k]] = index[enodes[10 * e + k]];
  return mesh;
}

}  // namespace

namespace {

// Builds a model with `geometry`, meshes it with quadratic tets of at most
// h_mm and reads the mesh; gmsh's own messages join deflex's error.
template <class F>
TetMesh mesh_model(double h_mm, const F& geometry) {
  std::lock_guard<std::mutex> lock(gmsh_mutex());
  const gmshrt::Api& g = ensure_gmsh();
  int ierr = 0;
  g.model_add("deflex_solid", &ierr);
  TetMesh mesh;
  try {
    gmshrt::check(ierr, "gmsh: cannot add a model");
    geometry(g);
    g.option_set_number("Mesh.MeshSizeMax", h_mm, &ierr);
    g.option_set_number("Mesh.MeshSizeMin", 0.05 * h_mm, &ierr);
    g.option_set_number("Mesh.ElementOrder", 2, &ierr);
    g.option_set_number("Mesh.HighOrderOptimize", 0, &ierr);
    g.mesh_generate(3, &ierr);
    gmshrt::check(ierr, "gmsh failed to mesh the solid");
    mesh = read_mesh(g);
  } catch (const Error&) {
    g.model_remove(&ierr);
    throw;
  } catch (const std::exception& e) {
    char* why = nullptr;
    g.logger_get_last_error(&why, &ierr);
    std::string msg = e.what();
    if (why && *why) msg += std::string(": ") + why;
    g.free(why);
    g.model_remove(&ierr);
    throw Error(ErrorKind::internal, msg);
  }
  g.model_remove(&ierr);
  if (mesh.tet.empty()) throw Error(ErrorKind::internal, "gmsh produced no tetrahedra for the solid");
  return mesh;
}

}  // namespace

TetMesh mesh_brep(const std::string& brep_path, double h_mm, bool move_tip_to_origin) {
  return mesh_model(h_mm, [&](const gmshrt::Api& g) {
    int ierr = 0;
    int* dimtags = nullptr;
    std::size_t dimtags_n = 0;
    g.occ_import_shapes(brep_path.c_str(), &dimtags, &dimtags_n, 1, "brep", &ierr);
    gmshrt::check(ierr, "gmsh: cannot import the solid");
    std::vector<int> dt(dimtags, dimtags + dimtags_n);
    g.free(dimtags);
    g.occ_synchronize(&ierr);
    if (move_tip_to_origin) {
      double x0, y0, z0, x1, y1, z1;
      g.get_bounding_box(-1, -1, &x0, &y0, &z0, &x1, &y1, &z1, &ierr);
      gmshrt::check(ierr, "gmsh: no bounding box of the solid");
      g.occ_translate(dt.data(), dt.size(), 0, 0, -z0, &ierr);
      g.occ_synchronize(&ierr);
    }
  });
}

TetMesh mesh_stl(const std::string& stl_path, double h_mm) {
  return mesh_model(h_mm, [&](const gmshrt::Api& g) {
    int ierr = 0;
    g.merge(stl_path.c_str(), &ierr);
    gmshrt::check(ierr, "gmsh: cannot read the STL");
    // Facets meeting at more than 40 degrees bound separate patches, each
    // split until one map parametrises it, so gmsh remeshes the surface at
    // h_mm instead of keeping the STL's triangles (gmsh's tutorial t13).
    constexpr double kPi = 3.14159265358979323846;
    g.mesh_classify_surfaces(40 * kPi / 180, 1, 1, kPi, 1, &ierr);
    gmshrt::check(ierr, "gmsh: cannot split the STL into surfaces");
    g.mesh_create_geometry(nullptr, 0, &ierr);
    gmshrt::check(ierr, "gmsh: cannot parametrise the STL's surfaces");
    int* dimtags = nullptr;
    std::size_t n = 0;
    g.get_entities(&dimtags, &n, 2, &ierr);
    std::vector<int> surfaces;
    for (std::size_t i = 1; i < n; i += 2) surfaces.push_back(dimtags[i]);
    g.free(dimtags);
    int loop = g.geo_add_surface_loop(surfaces.data(), surfaces.size(), -1, &ierr);
    gmshrt::check(ierr, "gmsh: the STL's surfaces close no volume");
    g.geo_add_volume(&loop, 1, -1, &ierr);
    gmshrt::check(ierr, "gmsh: the STL's surfaces close no volume");
    g.geo_synchronize(&ierr);
  });
}

TetMesh mesh_boxes(const std::vector<stock::BoxSpec>& boxes, double h_mm) {
  return mesh_model(h_mm, [&](const gmshrt::Api& g) {
    int ierr = 0;
    std::vector<int> object, tools;
    for (const stock::BoxSpec& b : boxes) {
      const int tag = g.occ_add_box(b.x0_mm, b.y0_mm, b.z0_mm, b.x1_mm - b.x0_mm, b.y1_mm - b.y0_mm, b.z1_mm - b.z0_mm,
                                    -1, &ierr);
      gmshrt::check(ierr, "gmsh: cannot add a box of the solid");
      std::vector<int>& to = object.empty() ? object : tools;
      to.insert(to.end(), {3, tag});
    }
    if (!tools.empty()) {
      int* out = nullptr;
      std::size_t out_n = 0;
      int** map = nullptr;
      std::size_t* map_n = nullptr;
      std::size_t map_nn = 0;
      g.occ_fuse(object.data(), object.size(), tools.data(), tools.size(), &out, &out_n, &map, &map_n, &map_nn, -1, 1,
                 1, &ierr);
      gmshrt::check(ierr, "gmsh: cannot unite the boxes of the solid");
      for (std::size_t i = 0; i < map_nn; ++i) g.free(map[i]);
      g.free(map);
      g.free(map_n);
      g.free(out);
    }
    g.occ_synchronize(&ierr);
    gmshrt::check(ierr, "gmsh: cannot build the solid");
  });
}

}  // namespace deflex::stiffness::solid
