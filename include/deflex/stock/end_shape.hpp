// The shape of an end mill's cutting end, the one name the tool library
// (stiffness::Tool), the force model (force::Cutter) and the material removal
// (stock::ToolProfile) share. It lives in stock, the lowest of those modules:
// stiffness and force already depend on stock (stiffness meshes the stock's
// solids; force reads stiffness's tools) and stock depends on neither, so no
// module gains a cycle; interp, lower still, knows tool numbers but no shapes.
// (stiffness::ToolShape is another thing: the tool body's radius profile.)
#pragma once
#include <optional>
#include <string_view>

namespace deflex::stock {

enum class EndShape {
  flat,  // square end: corner radius 0
  ball,  // ball end: corner radius D/2
  bull,  // bull nose (torus): corner radius r_c in (0, D/2]
};

const char* to_string(EndShape s);  // "flat", "ball", "bull": the tool library's `type:`
std::optional<EndShape> parse_end_shape(std::string_view s);  // inverse of to_string

// The corner radius the geometry uses: R0 for a ball, 0 for a flat end, a bull
// nose's own r_c (bull_corner_mm; the others ignore it). mm.
constexpr double corner_radius_mm(EndShape s, double radius_mm, double bull_corner_mm) {
  return s == EndShape::ball ? radius_mm : s == EndShape::flat ? 0.0 : bull_corner_mm;
}

}  // namespace deflex::stock
