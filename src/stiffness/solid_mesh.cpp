// Tool solid (OpenCASCADE) and its quadratic tetrahedral mesh (gmsh API).
#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <stdexcept>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <BRepTools.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Vertex.hxx>
#include <gp_Ax1.hxx>
#include <gp_Ax2.hxx>
#include <gp_Circ.hxx>
#include <gp_Elips.hxx>
#include <gp_Pnt.hxx>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stiffness/shape.hpp"
#include "gmsh_runtime.hpp"
#include "deflex/stiffness/solid.hpp"
#include "deflex/stock/build.hpp"
#include "solid_internal.hpp"

namespace deflex::stiffness::solid {

namespace {

// Profile in the xz plane (x = radius), as shared vertices joined by edges.
class ProfileBuilder {
 public:
  explicit ProfileBuilder(double r, double z) : last_(vertex(r, z)), first_(last_) {}
  void line_to(double r, double z) {
    const TopoDS_Vertex v = vertex(r, z);
    wire_.Add(BRepBuilderAPI_MakeEdge(last_, v).Edge());
    last_ = v;
  }
  // Quarter ellipse about (rc, zc) from (rc, zc - c) to (rc + a, zc): a corner
  // of radial semi-axis a and axial semi-axis c (a circle when a == c).
  void corner_to(double rc, double zc, double a, double c) {
    const TopoDS_Vertex v = vertex(rc + a, zc);
    const gp_Pnt centre(rc, 0, zc);
    if (std::abs(a - c) < 1e-12 * c) {
      // Circle in the xz plane, parameter increasing from -z towards +x.
      const gp_Circ circ(gp_Ax2(centre, gp_Dir(0, -1, 0), gp_Dir(0, 0, -1)), c);
      wire_.Add(BRepBuilderAPI_MakeEdge(circ, last_, v).Edge());
    } else if (c > a) {
      const gp_Elips e(gp_Ax2(centre, gp_Dir(0, -1, 0), gp_Dir(0, 0, -1)), c, a);
      wire_.Add(BRepBuilderAPI_MakeEdge(e, last_, v).Edge());
    } else {
      // Major axis radial: the parameter runs from (rc + a, zc) down to the tip side.
      const gp_Elips e(gp_Ax2(centre, gp_Dir(0, 1, 0), gp_Dir(1, 0, 0)), a, c);
      wire_.Add(BRepBuilderAPI_MakeEdge(e, v, last_).Edge());
    }
    last_ = v;
  }
  TopoDS_Shape revolve() {
    wire_.Add(BRepBuilderAPI_MakeEdge(last_, first_).Edge());
    const BRepBuilderAPI_MakeFace face(wire_.Wire(), true);
    if (!face.IsDone()) throw Error(ErrorKind::internal, "tool profile face failed");
    BRepPrimAPI_MakeRevol revol(face.Face(), gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)),
                                2 * std::numbers::pi);
    if (!revol.IsDone()) throw Error(ErrorKind::internal, "tool revolution failed");
    return revol.Shape();
  }

 private:
  static TopoDS_Vertex vertex(double r, double z) {
    return BRepBuilderAPI_MakeVertex(gp_Pnt(r, 0, z)).Vertex();
  }
  BRepBuilderAPI_MakeWire wire_;
  TopoDS_Vertex last_, first_;
};

// The revolved equivalent profile: tip, cap, fluted cylinder, neck, shank, top
// face at the holder face and back down the axis.
TopoDS_Shape tool_solid(const ToolShape& s) {
  ProfileBuilder p(0, 0);
  if (s.cap_offset_mm > 0) p.line_to(s.cap_offset_mm, 0);  // flat end face
  if (s.cap_height_mm > 0)
    p.corner_to(s.cap_offset_mm, s.cap_height_mm, s.cap_semi_axis_mm, s.cap_height_mm);
  double r = s.cap_offset_mm + s.cap_semi_axis_mm;
  for (const auto& c : s.cylinders) {
    if (std::abs(c.radius_mm - r) > 1e-12) p.line_to(c.radius_mm, c.z0_mm);
    p.line_to(c.radius_mm, c.z1_mm);
    r = c.radius_mm;
  }
  p.line_to(0, s.length_mm);
  return p.revolve();
}

TopoDS_Shape read_step(const std::string& path) {
  stock::route_occt_messages();
  STEPControl_Reader reader;
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
    throw Error(ErrorKind::io, path + ": error: cannot read the STEP file");
  if (reader.TransferRoots() == 0)
    throw Error(ErrorKind::io, path + ": error: no shape in the STEP file");
  return reader.OneShape();
}

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

void write_tool_brep(const Tool& t, const std::string& brep_path) {
  const TopoDS_Shape shape = t.step_file.empty() ? tool_solid(tool_shape(t)) : read_step(t.step_file);
  if (!BRepTools::Write(shape, brep_path.c_str()))
    throw Error(ErrorKind::io, brep_path + ": error: cannot write the temporary BREP file");
}

}  // namespace deflex::stiffness::solid

namespace deflex::stiffness {

void write_tool_step(const Tool& t, const std::string& step_path) {
  stock::route_occt_messages();
  STEPControl_Writer writer;
  if (writer.Transfer(solid::tool_solid(tool_shape(t)), STEPControl_AsIs) != IFSelect_RetDone ||
      writer.Write(step_path.c_str()) != IFSelect_RetDone)
    throw Error(ErrorKind::io, step_path + ": error: cannot write the STEP file");
}

}  // namespace deflex::stiffness

namespace deflex::stiffness::solid {

TetMesh mesh_brep(const std::string& brep_path, double h_mm, bool move_tip_to_origin) {
  std::lock_guard<std::mutex> lock(gmsh_mutex());
  const gmshrt::Api& g = ensure_gmsh();
  int ierr = 0;
  g.model_add("deflex_tool", &ierr);
  TetMesh mesh;
  try {
    gmshrt::check(ierr, "gmsh: cannot add a model");
    int* dimtags = nullptr;
    std::size_t dimtags_n = 0;
    g.occ_import_shapes(brep_path.c_str(), &dimtags, &dimtags_n, 1, "brep", &ierr);
    gmshrt::check(ierr, "gmsh: cannot import the tool solid");
    std::vector<int> dt(dimtags, dimtags + dimtags_n);
    g.free(dimtags);
    g.occ_synchronize(&ierr);
    if (move_tip_to_origin) {
      double x0, y0, z0, x1, y1, z1;
      g.get_bounding_box(-1, -1, &x0, &y0, &z0, &x1, &y1, &z1, &ierr);
      gmshrt::check(ierr, "gmsh: no bounding box of the tool solid");
      g.occ_translate(dt.data(), dt.size(), 0, 0, -z0, &ierr);
      g.occ_synchronize(&ierr);
    }
    g.option_set_number("Mesh.MeshSizeMax", h_mm, &ierr);
    g.option_set_number("Mesh.MeshSizeMin", 0.05 * h_mm, &ierr);
    g.option_set_number("Mesh.ElementOrder", 2, &ierr);
    g.option_set_number("Mesh.HighOrderOptimize", 0, &ierr);
    g.mesh_generate(3, &ierr);
    gmshrt::check(ierr, "gmsh failed to mesh the tool solid");
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
  if (mesh.tet.empty()) throw Error(ErrorKind::internal, "gmsh produced no tetrahedra for the tool solid");
  return mesh;
}

}  // namespace deflex::stiffness::solid
