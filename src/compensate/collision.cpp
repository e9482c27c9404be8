#include "deflex/compensate/collision.hpp"

#include <algorithm>
#include <cmath>

#include "deflex/diag/plural.hpp"

namespace deflex::compensate {

const char* to_string(AssemblyPart p) {
  switch (p) {
    case AssemblyPart::neck: return "neck";
    case AssemblyPart::shank: return "shank";
    case AssemblyPart::holder: return "holder";
  }
  return "?";
}

Assembly assembly_of(const stiffness::Tool& t, const std::optional<stiffness::Holder>& holder) {
  Assembly a;
  double z = a.flute_top_mm = t.flute_length_mm;
  if (t.neck && t.neck->length_mm > 0) {
    const double r = t.neck->diameter_mm / 2;
    a.frusta.push_back({AssemblyPart::neck, z, z + t.neck->length_mm, r, r});
    z += t.neck->length_mm;
  }
  const double rs = (t.shank_diameter_mm > 0 ? t.shank_diameter_mm : t.diameter_mm) / 2;
  if (t.stickout_mm > z) a.frusta.push_back({AssemblyPart::shank, z, t.stickout_mm, rs, rs});
  if (holder && holder->length_mm > 0)
    a.frusta.push_back({AssemblyPart::holder, t.stickout_mm, t.stickout_mm + holder->length_mm,
                        holder->nose_diameter_mm / 2, holder->base_diameter_mm / 2});
  return a;
}

namespace {

// The lowest height of frustum f at distance d from the axis (where its radius
// reaches d), or NaN where it never does.
double lowest_at(const Frustum& f, double d) {
  if (d <= f.r0_mm) return f.z0_mm;
  if (f.r1_mm <= f.r0_mm || d > f.r1_mm) return std::nan("");
  return f.z0_mm + (d - f.r0_mm) / (f.r1_mm - f.r0_mm) * (f.z1_mm - f.z0_mm);
}

// The material height h at (x, y) after sweep l of a tool whose flutes reach
// flute_top_mm above its tip. A sweep lowers the Z-map to the tool's lower
// surface as if the tool went up forever; the flutes do not: where the
// material stood higher than the flutes reached as they passed (the tip's
// height where the axis passes nearest the point, the highest over a
// plunge), the material above them is still there for the shank to meet.
double cut_by(const stock::LineSweep& l, double x, double y, double h, double flute_top_mm) {
  double tip_z = std::max(l.a()[2], l.b()[2]);
  if (l.xy_length() > 0) {
    const double u = ((x - l.a()[0]) * l.dir_x() + (y - l.a()[1]) * l.dir_y()) / l.xy_length();
    tip_z = l.a()[2] + std::clamp(u, 0.0, 1.0) * (l.b()[2] - l.a()[2]);
  }
  return h <= tip_z + flute_top_mm ? std::min(h, l.lower_height(x, y)) : h;
}

// The deepest cell of frustum f: the rows of its disc the tile and row maxima
// do not clear, cell by cell. A cell's material is the Z-map's height, lowered
// by the sweeps not yet committed to it (`near`: the tool's own last moves,
// which in a plunge or a ramp deeper than the flutes have cut the bore the
// shank follows into) where their flutes reached the top of it (cut_by).
double deepest(const stock::ZMap& z, const std::vector<const stock::LineSweep*>& near, double flute_top_mm,
               const V3& tip, const Frustum& f) {
  const double rmax = std::max(f.r0_mm, f.r1_mm);
  const float low = static_cast<float>(tip.z() + f.z0_mm);
  // Most points: no material anywhere over the part's square stands above its
  // lowest point (the tiles' maxima say so without reading a cell).
  if (z.none_above(tip.x() - rmax, tip.y() - rmax, tip.x() + rmax, tip.y() + rmax, low)) return 0;
  const stock::GridSpec& g = z.grid();
  double worst = 0;
  const int j0 = std::max(0, z.iy(tip.y() - rmax)), j1 = std::min(g.ny - 1, z.iy(tip.y() + rmax));
  for (int j = j0; j <= j1; ++j) {
    const double dy = z.cy(j) - tip.y();
    if (std::fabs(dy) > rmax) continue;
    const double half = std::sqrt(rmax * rmax - dy * dy);
    const int i0 = std::max(0, z.ix(tip.x() - half)), i1 = std::min(g.nx - 1, z.ix(tip.x() + half));
    if (i1 < i0 || !z.row_above(j, i0, i1, low)) continue;
    for (int i = i0; i <= i1; ++i) {
      double h = z.at(i, j);
      if (h <= low) continue;
      const double zl = lowest_at(f, std::hypot(z.cx(i) - tip.x(), dy));
      if (std::isnan(zl)) continue;
      for (const stock::LineSweep* l : near) h = cut_by(*l, z.cx(i), z.cy(j), h, flute_top_mm);
      worst = std::max(worst, h - (tip.z() + zl));
    }
  }
  return worst;
}

}  // namespace

Interference interference(const engage::StockView& stock, const V3& tip_mm, const Assembly& a) {
  Interference r;
  double rmax = 0;
  for (const Frustum& f : a.frusta) rmax = std::max({rmax, f.r0_mm, f.r1_mm});
  // The uncommitted sweeps whose footprint reaches the assembly's, in the
  // order they were cut (the pending oldest first, then the sample's own
  // move): whether one cuts a cell depends on the height the ones before it
  // left there (cut_by).
  thread_local std::vector<const stock::LineSweep*> near;
  near.clear();
  auto reaches = [&](const stock::LineSweep& l) {
    return l.x_min() <= tip_mm.x() + rmax && l.x_max() >= tip_mm.x() - rmax && l.y_min() <= tip_mm.y() + rmax &&
           l.y_max() >= tip_mm.y() - rmax;
  };
  for (const stock::LineSweep& l : stock.pending)
    if (reaches(l)) near.push_back(&l);
  if (stock.current && reaches(*stock.current)) near.push_back(stock.current);
  for (const Frustum& f : a.frusta) {
    const double d = deepest(*stock.zmap, near, a.flute_top_mm, tip_mm, f);
    if (d > r.depth_mm) r = {d, f.part};
  }
  return r;
}

std::string Collision::kind() const {
  return part == AssemblyPart::holder ? "holder_collision" : "shank_collision";
}

std::string Collision::message() const {
  const std::string where = "; " + plural(points, "point") + " on " + plural(line_count, "line") +
                            (worst_line != first_line ? ", the deepest " + fixed_decimals(worst_mm, 2) + " mm at line " +
                                                  std::to_string(worst_line)
                                            : "");
  if (part == AssemblyPart::holder)
    return "the holder of " + tool + " runs " + fixed_decimals(first_mm, 2) + " mm into the material at its stick-out of " +
           fixed_decimals(from_mm, 1) + " mm: the machine crashes here" + where +
           "; a stick-out of at least " + fixed_decimals(clears_mm, 1) + " mm keeps the holder clear";
  return std::string("the ") + to_string(part) + " of " + tool + " (diameter " + fixed_decimals(diameter_mm, 2) +
         " mm from " + fixed_decimals(from_mm, 1) + " mm above the tip) runs " + fixed_decimals(first_mm, 2) +
         " mm into the material: it rubs or breaks" + where + "; the cut needs a tool whose flutes or neck reach " +
         fixed_decimals(clears_mm, 1) + " mm above the tip at that diameter";
}

void CollisionScan::add(const Point& p, const std::string& tool_id) {
  if (!(p.collision_mm > collision_tolerance_mm)) return;
  const bool holder = p.collision_part == AssemblyPart::holder;
  Acc& a = acc_[{tool_id, holder}];
  Collision& c = a.c;
  if (!c.points++) {
    c.tool = tool_id;
    c.part = p.collision_part;
    c.first_line = p.line;
  }
  if (p.line == c.first_line) c.first_mm = std::max(c.first_mm, p.collision_mm);
  if (p.collision_mm > c.worst_mm) {
    c.worst_mm = p.collision_mm;
    c.worst_line = p.line;
    c.part = p.collision_part;
  }
  a.lines.insert(p.line);
}

std::vector<Collision> CollisionScan::collisions() const {
  std::vector<Collision> out;
  for (const auto& [key, a] : acc_) {
    Collision c = a.c;
    c.line_count = a.lines.size();
    const stiffness::Tool& t = stiffness::find_tool(tools_, c.tool);
    if (c.part == AssemblyPart::holder) {
      c.from_mm = t.stickout_mm;
      c.clears_mm = t.stickout_mm + c.worst_mm;
    } else {
      c.from_mm = t.flute_length_mm;
      c.diameter_mm = t.diameter_mm;
      for (const Frustum& f : assembly_of(t, std::nullopt).frusta)
        if (f.part == c.part) c.from_mm = f.z0_mm, c.diameter_mm = 2 * f.r0_mm;
      c.clears_mm = c.from_mm + c.worst_mm;
    }
    out.push_back(std::move(c));
  }
  std::sort(out.begin(), out.end(), [](const Collision& a, const Collision& b) { return a.first_line < b.first_line; });
  return out;
}

}  // namespace deflex::compensate
