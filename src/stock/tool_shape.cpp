#include "deflex/stock/tool_shape.hpp"

namespace deflex::stock {

const char* to_string(ToolShape s) {
  switch (s) {
    case ToolShape::flat: return "flat";
    case ToolShape::ball: return "ball";
    case ToolShape::bull: return "bull";
  }
  return "?";
}

std::optional<ToolShape> parse_tool_shape(std::string_view s) {
  for (const ToolShape t : {ToolShape::flat, ToolShape::ball, ToolShape::bull})
    if (s == to_string(t)) return t;
  return std::nullopt;
}

}  // namespace deflex::stock
