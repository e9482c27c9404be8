// The tool solid of the solid model, in deflex's OpenCASCADE plugin
// (src/stiffness/occt_api.hpp): the revolved equivalent profile, or a
// vendor's STEP model, written as .brep for gmsh or as STEP.
#include <cmath>
#include <numbers>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <BRepTools.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Vertex.hxx>
#include <gp_Ax1.hxx>
#include <gp_Ax2.hxx>
#include <gp_Circ.hxx>
#include <gp_Elips.hxx>
#include <gp_Pnt.hxx>

#include "../occt_api.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "stock_occt_api.hpp"

namespace deflex::stiffness::occt {

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
  stock::occt::route_messages();
  STEPControl_Reader reader;
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
    throw Error(ErrorKind::io, path + ": error: cannot read the STEP file");
  if (reader.TransferRoots() == 0)
    throw Error(ErrorKind::io, path + ": error: no shape in the STEP file");
  return reader.OneShape();
}

void write_brep(const TopoDS_Shape& shape, const std::string& brep_path) {
  if (!BRepTools::Write(shape, brep_path.c_str()))
    throw Error(ErrorKind::io, brep_path + ": error: cannot write the temporary BREP file");
}

void write_shape_brep(const ToolShape& s, const std::string& brep_path) { write_brep(tool_solid(s), brep_path); }

void write_step_brep(const std::string& step_path, const std::string& brep_path) {
  write_brep(read_step(step_path), brep_path);
}

void write_shape_step(const ToolShape& s, const std::string& step_path) {
  stock::occt::route_messages();
  STEPControl_Writer writer;
  if (writer.Transfer(tool_solid(s), STEPControl_AsIs) != IFSelect_RetDone ||
      writer.Write(step_path.c_str()) != IFSelect_RetDone)
    throw Error(ErrorKind::io, step_path + ": error: cannot write the STEP file");
}

}  // namespace

}  // namespace deflex::stiffness::occt

extern "C" __attribute__((visibility("default"))) const void* deflex_occt_stiffness() {
  using namespace deflex::stiffness::occt;
  static const Api api{&write_shape_brep, &write_step_brep, &write_shape_step, &write_part_brep};
  return &api;
}
