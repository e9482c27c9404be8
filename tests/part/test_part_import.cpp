// The part model of one solid read from STEP (written by OpenCASCADE here, and
// by gmsh: tests/part/data/pocket_fillet.geo) and from STL (OCCT's mesh of the
// same B-rep): the same signed distances and normals within the tessellation
// tolerance, and the same gouge check of a pocket program.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#pragma GCC diagnostic ignored "-Wdeprecated-enum-enum-conversion"
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRep_Tool.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <StlAPI_Writer.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#pragma GCC diagnostic pop
#include <doctest/doctest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>

#include "../support.hpp"
#include "deflex/compensate/gouge.hpp"
#include "deflex/part/part.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;
using V3 = Eigen::Vector3d;
namespace fs = std::filesystem;

namespace {

const std::string data_dir = std::string(DEFLEX_SOURCE_DIR) + "/tests/part/data/";

// The solid of pocket_fillet.geo built by OCCT: a 100 x 100 x 30 block (z from
// -30 to 0) less a 60 x 60 x 12 pocket in its middle, the pocket's vertical
// edges rounded R5 and its rim R2.
TopoDS_Shape pocketed_block() {
  const TopoDS_Shape block = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, -30), gp_Pnt(100, 100, 0)).Shape();
  const TopoDS_Shape pocket = BRepPrimAPI_MakeBox(gp_Pnt(20, 20, -12), gp_Pnt(80, 80, 1)).Shape();
  const TopoDS_Shape cut = BRepAlgoAPI_Cut(block, pocket).Shape();
  BRepFilletAPI_MakeFillet fillet(cut);
  for (TopExp_Explorer ex(cut, TopAbs_EDGE); ex.More(); ex.Next()) {
    const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
    const gp_Pnt a = BRep_Tool::Pnt(TopExp::FirstVertex(e)), b = BRep_Tool::Pnt(TopExp::LastVertex(e));
    const bool in_pocket = a.X() > 10 && a.X() < 90 && a.Y() > 10 && a.Y() < 90;
    const bool vertical = std::fabs(a.X() - b.X()) < 1e-9 && std::fabs(a.Y() - b.Y()) < 1e-9;
    const bool rim = std::fabs(a.Z()) < 1e-9 && std::fabs(b.Z()) < 1e-9;
    if (in_pocket && vertical) fillet.Add(5.0, e);
    else if (in_pocket && rim) fillet.Add(2.0, e);
  }
  return fillet.Shape();
}

TopoDS_Shape read_step(const std::string& path) {
  STEPControl_Reader r;
  REQUIRE(r.ReadFile(path.c_str()) == IFSelect_RetDone);
  r.TransferRoots();
  return r.OneShape();
}

// OCCT's writer reports on stdout unless routed as deflex routes it.
void write_step(const TopoDS_Shape& s, const std::string& path) {
  stock::route_occt_messages();
  STEPControl_Writer w;
  w.Transfer(s, STEPControl_AsIs);
  REQUIRE(w.Write(path.c_str()) == IFSelect_RetDone);
}

// The STL a CAD system exports: the B-rep meshed to `deflection_mm`, binary.
void write_stl(const TopoDS_Shape& s, const std::string& path, double deflection_mm) {
  BRepMesh_IncrementalMesh mesh(s, deflection_mm);
  StlAPI_Writer w;
  w.ASCIIMode() = false;
  REQUIRE(w.Write(s, path.c_str()));
}

using test::TempDir;

// occt.step and occt.stl of pocketed_block() in tmp.
void write_occt_solid(const TempDir& tmp, double stl_deflection_mm) {
  const TopoDS_Shape s = pocketed_block();
  write_step(s, tmp / "occt.step");
  write_stl(s, tmp / "occt.stl", stl_deflection_mm);
}

double angle_deg(const V3& a, const V3& b) {
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

// Signed distances and normals of two models of one solid at n random points
// in `lo`..`hi`: the distances within tol_mm; the normals within tol_deg where
// both find the same closest point (off the medial surface, where the nearest
// face flips from one side to the other).
void check_same_surface(const part::PartModel& a, const part::PartModel& b, const V3& lo, const V3& hi, int n,
                        double tol_mm, double tol_deg) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst_mm = 0, worst_deg = 0;
  int inside = 0, compared = 0;
  for (int i = 0; i < n; ++i) {
    const V3 p = lo + V3(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo);
    const part::Contact ca = a.closest(p), cb = b.closest(p);
    worst_mm = std::max(worst_mm, std::fabs(ca.gap_mm - cb.gap_mm));
    inside += ca.gap_mm < 0;
    if ((ca.point_mm - cb.point_mm).norm() > 0.05) continue;
    ++compared;
    worst_deg = std::max(worst_deg, angle_deg(ca.normal, cb.normal));
  }
  INFO(a.name() << " vs " << b.name() << ": worst distance " << worst_mm << " mm, worst normal " << worst_deg
                << " deg over " << compared << " points, " << inside << " inside");
  CHECK(worst_mm <= tol_mm);
  CHECK(worst_deg <= tol_deg);
  CHECK(inside > n / 10);
  CHECK(compared > n * 9 / 10);
}

// T1 (flat D10) plunges to the pocket's floor and goes round it 5 mm off its
// walls: on the pocketed part every point touches it, none cuts into it.
const char* pocket_program =
    "%\nO0100\nN10 G21 G90 G17 G40 G49 G80 G54\nN20 T1 M06\nN30 S8000 M03\nN40 G00 X50. Y50. Z5.\n"
    "N50 G01 Z-12. F300.\nN60 X25. F1200.\nN70 Y25.\nN80 X75.\nN90 Y75.\nN100 X25.\nN110 Y50.\nN120 X50.\n"
    "N130 G00 Z5.\nN140 M30\n%\n";

}  // namespace

TEST_SUITE("part") {

TEST_CASE("part model: a pocketed block from STEP (OCCT's and gmsh's) and from STL gives the same distances and normals") {
  const TempDir tmp;
  // The STL meshed coarser than deflex meshes a STEP (0.002 mm), as a CAD export is.
  const double stl_deflection_mm = 0.005;
  write_occt_solid(tmp, stl_deflection_mm);
  const std::string gmsh_step = data_dir + "pocket_fillet_gmsh.step";
  write_stl(read_step(gmsh_step), tmp / "gmsh.stl", stl_deflection_mm);
  // Each mesh lies within its deflection of the B-rep. A facet's normal is
  // within half the angle between neighbouring facets of the smooth surface's
  // (part.hpp), on the R2 rim acos(1 - deflection / R) = 4.05 deg.
  const double tol_mm = stl_deflection_mm + part::PartOptions{}.mesh_deflection_mm;
  const double tol_deg = std::acos(1 - stl_deflection_mm / 2.0) * 180.0 / std::numbers::pi;
  for (auto [step, stl] : {std::pair{tmp / "occt.step", tmp / "occt.stl"}, std::pair{gmsh_step, tmp / "gmsh.stl"}}) {
    const part::PartModel from_step = part::PartModel::load(step), from_stl = part::PartModel::load(stl);
    // The whole solid, and the pocket with its fillets close up.
    check_same_surface(from_step, from_stl, V3(-5, -5, -35), V3(105, 105, 5), 3000, tol_mm, tol_deg);
    check_same_surface(from_step, from_stl, V3(15, 15, -14), V3(85, 85, 2), 3000, tol_mm, tol_deg);
  }
}

TEST_CASE("gouge check: a pocket program against the pocketed part from STEP and from STL reads the same: clean") {
  const TempDir tmp;
  write_occt_solid(tmp, 0.005);
  test::write_file(tmp / "pocket.nc", pocket_program);
  for (const std::string& part : {tmp / "occt.step", tmp / "occt.stl", data_dir + "pocket_fillet_gmsh.step"}) {
    const test::CliResult r = test::run_cli({"check", tmp / "pocket.nc", "--part", part});
    INFO(part << ":\n" << r.err);
    CHECK(r.rc == 0);
    CHECK(r.err.find("into the part") == std::string::npos);
  }
}

TEST_CASE("gouge check: the pocket program against the block without the pocket cuts 12 mm into it, from STEP and from STL") {
  const TempDir tmp;
  const TopoDS_Shape block = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, -30), gp_Pnt(100, 100, 0)).Shape();
  write_step(block, tmp / "block.step");
  write_stl(block, tmp / "block.stl", 0.005);
  const test::Interpreted in = test::interpret_text(pocket_program);
  REQUIRE(in.errors == 0);
  const stiffness::ToolLibrary lib = stiffness::load_tool_library("samples/tools.yaml");
  test::write_file(tmp / "pocket.nc", pocket_program);
  for (const std::string& file : {tmp / "block.step", tmp / "block.stl"}) {
    const part::PartModel pm = part::PartModel::load(file);
    const compensate::PartGaps g =
        compensate::part_gaps(in.motions, pm, lib, [](const interp::Motion&) { return "T1"; }, {}, 0.02, 1.0);
    INFO(file << ": deepest " << g.overcut.worst_mm << " mm at line " << g.overcut.worst_line);
    // The tip 12 mm under the top all round the loop (lines 8 to 14 of the text).
    CHECK(g.overcut.worst_mm == deflex::test::within(12, 1e-6));
    CHECK(g.overcut.lines == std::vector<std::uint32_t>{7, 8, 9, 10, 11, 12, 13, 14});
    const test::CliResult r = test::run_cli({"check", tmp / "pocket.nc", "--part", file});
    INFO(r.err);
    CHECK(r.err.find("cuts 12.0000 mm into the part model") != std::string::npos);
  }
  // Down to Z-20 in the 30 mm block the depth below the nearest face is at most
  // 15 mm (+ the 0.2 mm corner): a bound, and the warning says so.
  std::string deeper = pocket_program;
  deeper.replace(deeper.find("Z-12."), 5, "Z-20.");
  test::write_file(tmp / "deeper.nc", deeper);
  const test::CliResult r = test::run_cli({"check", tmp / "deeper.nc", "--part", tmp / "block.stl"});
  INFO(r.err);
  CHECK(r.err.find("cuts at least 15.2000 mm into the part model here (through more than half the part's thickness "
                   "there)") != std::string::npos);
}

}  // TEST_SUITE
