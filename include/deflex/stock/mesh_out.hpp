// The Z-map as a closed triangle mesh (the in-process stock
// for the next operation, a CAM system or a viewer).
//
// The top surface runs through the cell centres at their heights, extended by
// half a cell at the border so that its outline is the grid's: read back at the
// same cell size the mesh gives the same grid and, at tolerance 0, the same
// heights. Vertical walls close it down to a flat bottom 0.01 mm under the
// stock's base (cells without material lie on the base, over that thin plate),
// so it is one solid: every edge is shared by exactly two triangles, with
// opposite orientations, all normals outward.
//
// Reduction: a quadtree over the grid merges a square into one leaf where its
// vertex heights lie within `tolerance_mm` of each other (max - min), or where
// its triangles - two along a diagonal, or a fan from its centre - pass within
// the tolerance of all of them (the fan within half of it: the proof is at
// one_leaf() in mesh_out.cpp). A leaf is two triangles where no neighbour puts
// a vertex on its sides, else a fan from its centre vertex through every leaf
// corner on its sides (so no T-junction: neighbouring leaves share the same
// vertices along a side). The surface is within `tolerance_mm` of every cell
// height it covers. Flat floors, untouched stock and smooth slopes become a
// few large triangles; a scallop field stays fine.
#pragma once
#include <iosfwd>
#include <vector>

#include "deflex/stock/build.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::stock {

std::vector<Triangle> zmap_mesh(const ZMap& z, double tolerance_mm);

// The Z-map as a union of boxes from its base up to the cells' heights, each
// height rounded to the nearest multiple of height_step_mm above the base
// (cells at or below the base, or empty, have none): rectangles of cells of
// one rounded height, each grown along its row, then down the rows while the
// whole run matches (greedy; the cells' own edges, so a wall a cell thick
// stays one). For a solid modeller that meshes exact faces (OpenCASCADE).
std::vector<BoxSpec> zmap_boxes(const ZMap& z, double height_step_mm);

// Binary STL (little-endian float32, normals from the vertex order); throws
// Error(ErrorKind::io) when the stream fails.
void write_binary_stl(std::ostream& out, const std::vector<Triangle>& tris, const std::string& header);

}  // namespace deflex::stock
