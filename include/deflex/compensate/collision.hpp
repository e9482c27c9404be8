// The parts of the tool assembly that do not cut - the neck, the shank and the
// holder - against the stock: where one of them would run into material the
// flutes have not removed (a deep cavity under a short stick-out).
//
// The assembly is axisymmetric about the spindle axis, in heights above the
// tool tip: the neck from the top of the flutes, then the shank up to the
// stick-out (the holder face), then the holder's taper from its nose diameter
// to its base diameter over its length (the machine profile's `holder:`).
// Whatever lies higher (the spindle nose) is not modelled.
//
// A part of the assembly in the material is an error, not a warning: the
// machine crashes there whatever the compensation does. Depths up to
// collision_tolerance_mm are not counted.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "deflex/compensate/compensate.hpp"
#include "deflex/engage/engagement.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/tool.hpp"
#include "deflex/stock/zmap.hpp"

namespace deflex::compensate {

const char* to_string(AssemblyPart p);  // AssemblyPart: compensate.hpp

// A frustum of the assembly: radius r0 at height z0 above the tip, r1 at z1.
struct Frustum {
  AssemblyPart part;
  double z0_mm, z1_mm, r0_mm, r1_mm;
};

struct Assembly {
  std::vector<Frustum> frusta;  // bottom up
  double flute_top_mm = 0;      // the flutes' top above the tip: what cuts lies below it
};
// The tool's non-cutting parts and the holder (none: the tool's alone).
Assembly assembly_of(const stiffness::Tool& t, const std::optional<stiffness::Holder>& holder);

// The deepest interference of the assembly with the stock (the Z-map and the
// sweeps not yet committed to it, engage::StockView) when the tip is at
// tip_mm: how far material stands above the lowest point of a part at its
// distance from the axis (mm, > 0), and which part. depth 0: clear.
struct Interference {
  double depth_mm = 0;
  AssemblyPart part = AssemblyPart::shank;
};
Interference interference(const engage::StockView& stock, const V3& tip_mm, const Assembly& a);

// Below a hundredth of a millimetre the Z-map's cells on a wall decide, not
// the part (a wall a tool has just cut stands within a cell of its flank):
// a depth up to this is no collision.
inline constexpr double collision_tolerance_mm = 0.01;

// One tool's part (the holder, or the neck or shank) in the material.
struct Collision {
  std::string tool;
  AssemblyPart part = AssemblyPart::holder;  // the neck or shank: the one of the deepest point
  std::uint32_t first_line = 0;              // the first line where it is in the material
  double first_mm = 0;                       // how deep there (its deepest point on that line)
  std::uint32_t worst_line = 0;              // the deepest point's line
  double worst_mm = 0;
  std::size_t points = 0, line_count = 0;
  // The holder: the least stick-out that clears it (the stick-out plus the
  // deepest depth: the holder rises with it, and the longer shank below it
  // is narrower than the holder and already checked to any height). The neck
  // or shank: the height above the tip its bottom must reach at that diameter.
  double clears_mm = 0;
  double from_mm = 0;      // the part's bottom above the tip (the holder's: the stick-out)
  double diameter_mm = 0;  // the neck's or shank's diameter
  std::string kind() const;             // holder_collision | shank_collision
  std::string message() const;          // one sentence, without the location
};

// The collisions of a simulation's points (Point::collision_mm), in program
// order as they come: one per tool and part (holder; neck or shank).
class CollisionScan {
 public:
  explicit CollisionScan(const stiffness::ToolLibrary& tools) : tools_(tools) {}
  void add(const Point& p, const std::string& tool_id);
  bool any() const { return !acc_.empty(); }
  // By first line.
  std::vector<Collision> collisions() const;

 private:
  struct Acc {
    Collision c;
    std::set<std::uint32_t> lines;
  };
  const stiffness::ToolLibrary& tools_;
  std::map<std::pair<std::string, bool>, Acc> acc_;  // (tool, holder?)
};

}  // namespace deflex::compensate
