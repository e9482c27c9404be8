// The workpiece solid of its compliance model (src/stiffness/workpiece.cpp),
// in deflex's OpenCASCADE plugin (src/stiffness/occt_api.hpp): a part's STEP
// or IGES file as its closed solid(s) in a .brep file for gmsh.
// OCCT 7.6 headers use std::iterator (deprecated in C++17).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#pragma GCC diagnostic ignored "-Wdeprecated-enum-enum-conversion"
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Shape.hxx>
#pragma GCC diagnostic pop

#include "../occt_api.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "stock_occt_api.hpp"

namespace deflex::stiffness::occt {

namespace {

// The solids of `shape`; where it has none, its closed shells made solids.
// A face or an open shell bounds no volume: nothing to mesh.
TopoDS_Shape solids_of(const TopoDS_Shape& shape, const std::string& path) {
  TopoDS_Compound out;
  BRep_Builder b;
  b.MakeCompound(out);
  int solids = 0, open_shells = 0;
  for (TopExp_Explorer ex(shape, TopAbs_SOLID); ex.More(); ex.Next(), ++solids) b.Add(out, ex.Current());
  if (solids == 0)
    for (TopExp_Explorer ex(shape, TopAbs_SHELL); ex.More(); ex.Next()) {
      const TopoDS_Shell& sh = TopoDS::Shell(ex.Current());
      if (!BRep_Tool::IsClosed(sh)) {
        ++open_shells;
        continue;
      }
      b.Add(out, BRepBuilderAPI_MakeSolid(sh).Solid());
      ++solids;
    }
  if (solids == 0)
    throw Error(ErrorKind::config, path + ": error: the part is not a closed solid (" +
                                       (open_shells ? "its surface is open" : "the file holds no solid") +
                                       "): the workpiece model needs the volume it bounds");
  return out;
}

void write_brep(const TopoDS_Shape& shape, const std::string& brep_path) {
  if (!BRepTools::Write(shape, brep_path.c_str()))
    throw Error(ErrorKind::io, brep_path + ": error: cannot write the temporary BREP file");
}

}  // namespace

void write_part_brep(const std::string& path, bool step, const std::string& brep_path) {
  stock::occt::route_messages();
  try {
    const TopoDS_Shape shape = stock::occt::read_shape(path, step);
    if (shape.IsNull()) throw Error(ErrorKind::config, path + ": error: the file holds no shape");
    write_brep(solids_of(shape, path), brep_path);
  } catch (const Standard_Failure& e) {
    throw Error(ErrorKind::io, path + ": error: OpenCASCADE: " + e.GetMessageString());
  }
}

}  // namespace deflex::stiffness::occt
