// Test solids for the workpiece model, built by OpenCASCADE and written as
// STEP (or STL) in a temporary folder, as tests/part does.
#pragma once
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#pragma GCC diagnostic ignored "-Wdeprecated-enum-enum-conversion"
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <STEPControl_Writer.hxx>
#include <StlAPI_Writer.hxx>
#include <gp_Pln.hxx>
#pragma GCC diagnostic pop
#include <doctest/doctest.h>

#include <string>

#include "../support.hpp"
#include "deflex/stock/build.hpp"

namespace deflex::stiffness::testing {

inline void write_step(const TopoDS_Shape& s, const std::string& path) {
  stock::route_occt_messages();  // OCCT's writer reports on stdout otherwise
  STEPControl_Writer w;
  w.Transfer(s, STEPControl_AsIs);
  REQUIRE(w.Write(path.c_str()) == IFSelect_RetDone);
}

// A box from the origin to (x, y, z), mm, as STEP.
inline std::string box_step(const test::TempDir& dir, const std::string& name, double x, double y, double z) {
  const std::string path = dir / (name + ".step");
  write_step(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(x, y, z)).Shape(), path);
  return path;
}

// The same box as binary STL (OCCT's mesh of its faces).
inline std::string box_stl(const test::TempDir& dir, const std::string& name, double x, double y, double z) {
  const std::string path = dir / (name + ".stl");
  const TopoDS_Shape s = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(x, y, z)).Shape();
  BRepMesh_IncrementalMesh mesh(s, 0.01);
  StlAPI_Writer w;
  w.ASCIIMode() = false;
  REQUIRE(w.Write(s, path.c_str()));
  return path;
}

// A lone rectangular face in z = 0: a surface that bounds no volume.
inline std::string face_step(const test::TempDir& dir) {
  const std::string path = dir / "face.step";
  write_step(BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 0, 10, 0, 10).Face(), path);
  return path;
}

// Aluminium, as samples/materials.yaml gives Al6082-T4.
inline Material aluminium() { return Material{"Al6082-T4", 70000.0, 0.33}; }

}  // namespace deflex::stiffness::testing
