// Where the program's tools reach the part (compensate/reach.hpp): a face
// turned against the tool within its radius and flutes, not the back of a
// wall, nor a top beside the flutes, nor a face beyond the radius.
#include <doctest/doctest.h>

#include "../support.hpp"
#include "deflex/compensate/reach.hpp"

using namespace deflex;
using V3 = Eigen::Vector3d;

TEST_SUITE("compensate") {
  TEST_CASE("tool reach: the wall's face and the floor under the tip, not the wall's back or top; a ball's contact side") {
    const stiffness::ToolLibrary lib = stiffness::load_tool_library("samples/tools.yaml");
    // T6, flat D12, along a 2 mm wall (Y0 to Y2) with its centre at Y8, tip at Z-5.
    compensate::ToolReach flat(1.0);
    flat.add({test::linear_motion({18, 8, -5}, {82, 8, -5})}, lib, [](const interp::Motion&) { return std::string("T6"); }, {});
    CHECK(flat.reaches(V3(50, 2, -3), V3::UnitY()));        // the face, beside the flutes
    CHECK(!flat.reaches(V3(50, 0, -3), -V3::UnitY()));      // its back: as near, turned away
    CHECK(!flat.reaches(V3(50, 1, 0), V3::UnitZ()));        // the wall's top, beside the flutes
    CHECK(flat.reaches(V3(50, 8, -5), V3::UnitZ()));        // the floor under the tip
    CHECK(!flat.reaches(V3(50, 17.5, -3), -V3::UnitY()));   // a face 9.5 mm from the axis: beyond R + 1
    CHECK(flat.reaches(V3(50, 14.9, -3), -V3::UnitY()));    // within R + 1
    CHECK(!flat.reaches(V3(50, 2, 26.5), V3::UnitY()));     // above the flutes (30 mm) and the margin
    // T7, ball D10, tip at the origin: a surface below the ball's centre facing it.
    compensate::ToolReach ball(1.0);
    ball.add({test::linear_motion({0, 0, 0}, {0.1, 0, 0})}, lib, [](const interp::Motion&) { return std::string("T7"); }, {});
    CHECK(ball.reaches(V3(3, 0, 1), V3(-0.6, 0, 0.8)));
    CHECK(!ball.reaches(V3(3, 0, 1), V3(0.6, 0, -0.8)));
  }
}
