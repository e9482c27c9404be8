#include "deflex/stock/end_shape.hpp"

namespace deflex::stock {

const char* to_string(EndShape s) {
  switch (s) {
    case EndShape::flat: return "flat";
    case EndShape::ball: return "ball";
    case EndShape::bull: return "bull";
  }
  return "?";
}

std::optional<EndShape> parse_end_shape(std::string_view s) {
  for (const EndShape t : {EndShape::flat, EndShape::ball, EndShape::bull})
    if (s == to_string(t)) return t;
  return std::nullopt;
}

}  // namespace deflex::stock
