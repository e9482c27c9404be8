// Reading STEP and IGES stock solids in deflex's OpenCASCADE plugin
// (src/stock/internal/stock_occt_api.hpp): their readers, meshed by
// BRepMesh_IncrementalMesh.
// OCCT 7.6 headers use std::iterator (deprecated in C++17).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#pragma GCC diagnostic ignored "-Wdeprecated-enum-enum-conversion"
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <Message_PrinterOStream.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#pragma GCC diagnostic pop
#include <utility>

#include "deflex/diag/diagnostics.hpp"
#include "stock_occt_api.hpp"

namespace deflex::stock::occt {

namespace {

// A face's triangulation is wound by its surface's parametrisation (the
// normal du x dv), which is the solid's outward side only where the face is
// FORWARD in the shell: a REVERSED face (the pocket's floor and walls after
// BRepAlgoAPI_Cut, half the faces of a box) is flipped here, as OCCT's own
// StlAPI_Writer::Write does (StlAPI_Writer.cxx, OCCT 7.6). The upper envelope
// of the stock does not see the winding; the part model's inside and outside
// do (src/part/part.cpp).
void append(const Handle(Poly_Triangulation) & tri, const gp_Trsf* trsf, bool reversed, std::vector<Triangle>& out) {
  if (tri.IsNull()) return;
  out.reserve(out.size() + static_cast<std::size_t>(tri->NbTriangles()));
  for (Standard_Integer k = 1; k <= tri->NbTriangles(); ++k) {
    Standard_Integer n[3];
    tri->Triangle(k).Get(n[0], n[1], n[2]);
    if (reversed) std::swap(n[1], n[2]);
    Triangle t;
    for (int v = 0; v < 3; ++v) {
      gp_Pnt p = tri->Node(n[v]);
      if (trsf) p.Transform(*trsf);
      t.p[v] = {p.X(), p.Y(), p.Z()};
    }
    out.push_back(t);
  }
}

std::vector<Triangle> read_brep_triangles(const std::string& path, bool step, double mesh_deflection_mm) {
  route_messages();
  std::vector<Triangle> out;
  try {
    const TopoDS_Shape shape = read_shape(path, step);
    if (shape.IsNull()) throw Error(ErrorKind::config, path + ": the file holds no shape");
    // Relative deflection off; angular deflection 0.2 rad keeps small fillets round.
    BRepMesh_IncrementalMesh mesh(shape, mesh_deflection_mm, false, 0.2, false);
    for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) {
      TopLoc_Location loc;
      const TopoDS_Face& face = TopoDS::Face(ex.Current());
      const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
      const gp_Trsf trsf = loc.Transformation();
      append(tri, loc.IsIdentity() ? nullptr : &trsf, face.Orientation() == TopAbs_REVERSED, out);
    }
  } catch (const Standard_Failure& e) {
    throw Error(ErrorKind::io, path + ": OpenCASCADE: " + e.GetMessageString());
  }
  if (out.empty()) throw Error(ErrorKind::config, path + ": the solid has no faces to mesh");
  return out;
}

}  // namespace

TopoDS_Shape read_shape(const std::string& path, bool step) {
  if (step) {
    STEPControl_Reader r;
    if (r.ReadFile(path.c_str()) != IFSelect_RetDone) throw Error(ErrorKind::io, path + ": cannot read as STEP");
    r.TransferRoots();
    return r.OneShape();
  }
  IGESControl_Reader r;
  if (r.ReadFile(path.c_str()) != IFSelect_RetDone) throw Error(ErrorKind::io, path + ": cannot read as IGES");
  r.TransferRoots();
  return r.OneShape();
}

// OCCT's readers print progress and errors on stdout, which is deflex's
// output (a compensated program): its messages go to stderr instead, failures
// only and without terminal colours; deflex reports its own error beside them.
void route_messages() {
  static const bool done = [] {
    const Handle(Message_Messenger)& m = Message::DefaultMessenger();
    m->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
    Handle(Message_PrinterOStream) err = new Message_PrinterOStream("cerr", false, Message_Fail);
    err->SetToColorize(false);
    m->AddPrinter(err);
    return true;
  }();
  (void)done;
}

}  // namespace deflex::stock::occt

extern "C" __attribute__((visibility("default"))) const void* deflex_occt_stock() {
  static const deflex::stock::occt::Api api{&deflex::stock::occt::read_brep_triangles,
                                            &deflex::stock::occt::route_messages};
  return &api;
}
