// Building the initial stock Z-map: a box from the command line or config, or
// the top surface of a solid (STL, STEP, IGES) read by OpenCASCADE.
#pragma once
#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "deflex/stock/zmap.hpp"

namespace deflex::stock {

// An axis-aligned box in the work frame, mm.
struct BoxSpec {
  double x0_mm = 0, y0_mm = 0, z0_mm = 0;
  double x1_mm = 0, y1_mm = 0, z1_mm = 0;
};

// "box:X0,Y0,Z0,X1,Y1,Z1" (mm; corners in any order). Throws Error(ErrorKind::settings)
// with the offending text on a malformed spec.
BoxSpec parse_box(std::string_view spec);

// The box as a Z-map of cell size cell_mm: cells whose centre lies in the box's XY
// rectangle are full from z0 to z1; the grid covers exactly the box (cells may
// overhang the far edges by less than one cell; those whose centre is outside are empty).
ZMap zmap_from_box(const BoxSpec& b, double cell_mm = default_cell_mm);

struct Triangle {
  std::array<std::array<double, 3>, 3> p{};  // vertices, mm
};

// Upper envelope of a triangle soup: each cell takes the highest triangle over
// its centre (no triangle: no material); material rests on the lowest vertex
// height. Exact for the top surface of a solid without overhangs; an undercut is
// filled (a vertical tool cannot reach it from above anyway).
ZMap zmap_from_triangles(std::span<const Triangle> tris, double cell_mm = default_cell_mm);

struct SolidOptions {
  double cell_mm = default_cell_mm;
  // Chordal deflection of the OpenCASCADE mesh of STEP/IGES surfaces, mm: the
  // Z-map's top surface lies within it of the exact one (STL is taken as is).
  double mesh_deflection_mm = 0.005;
};

// Reads an STL (read_stl), STEP (STEPControl_Reader) or IGES (IGESControl_Reader)
// file by extension (.stl, .step/.stp, .iges/.igs; any case) into triangles.
// Throws Error(ErrorKind::io) when the file cannot be read, ErrorKind::config when it holds no solid.
std::vector<Triangle> read_solid_triangles(const std::string& path, double mesh_deflection_mm);

// Sends OpenCASCADE's messages to stderr (failures only), never to stdout.
// Idempotent; every reader that goes through OCCT calls it first.
void route_occt_messages();

// An STL file, binary or ASCII, read by deflex itself (not OpenCASCADE: see
// src/stock/stl.cpp). Triangles without area are dropped. Throws Error(ErrorKind::io)
// on any malformed content.
std::vector<Triangle> read_stl(const std::string& path);

ZMap zmap_from_solid_file(const std::string& path, const SolidOptions& o = {});

// A stock spec as given on the command line or in the config: "box:..." or a
// path to a solid file.
ZMap make_stock(const std::string& spec, const SolidOptions& o = {});

}  // namespace deflex::stock
