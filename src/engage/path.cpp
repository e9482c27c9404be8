#include "deflex/engage/path.hpp"

#include <algorithm>
#include <cmath>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/interp/arc.hpp"

namespace deflex::engage {

namespace {

Point3 unit(const Point3& v) {
  const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (l == 0) return {0, 0, 0};
  return {v[0] / l, v[1] / l, v[2] / l};
}

}  // namespace

std::vector<Point3> motion_vertices(const interp::Motion& m, const PathOptions& o) {
  if (!(o.cl_spacing_mm > 0) || !(o.chord_tol_mm > 0))
    throw Error(ErrorKind::config, "engagement: CL spacing and chord tolerance must be > 0");
  if (interp::is_arc(m)) {
    const interp::Arc a = interp::arc_of(m);
    const int by_len = static_cast<int>(std::ceil(interp::arc_length_mm(a) / o.cl_spacing_mm - 1e-9));
    return interp::arc_polyline(a, std::max({1, by_len, interp::arc_chord_count(a, o.chord_tol_mm)}));
  }
  const Point3 &a = m.start_mm, &b = m.end_mm;
  const double len = std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
  const int n = std::max(1, static_cast<int>(std::ceil(len / o.cl_spacing_mm - 1e-9)));
  std::vector<Point3> v(static_cast<std::size_t>(n) + 1);
  for (int k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    for (int c = 0; c < 3; ++c) v[static_cast<std::size_t>(k)][c] = k == n ? b[c] : a[c] + t * (b[c] - a[c]);
  }
  return v;
}

Point3 motion_direction(const interp::Motion& m, std::span<const Point3> verts, std::size_t k) {
  if (interp::is_arc(m))
    return interp::arc_tangent(interp::arc_of(m), static_cast<double>(k) / static_cast<double>(verts.size() - 1));
  return unit({m.end_mm[0] - m.start_mm[0], m.end_mm[1] - m.start_mm[1], m.end_mm[2] - m.start_mm[2]});
}

CLSample cl_sample(const interp::Motion& m, std::span<const Point3> v, std::size_t k, std::array<double, 2>& feed) {
  CLSample s;
  s.point.tip_mm = v[k];
  s.point.dir = motion_direction(m, v, k);
  const double h = std::hypot(s.point.dir[0], s.point.dir[1]);
  if (h > 1e-6) feed = {s.point.dir[0] / h, s.point.dir[1] / h};
  s.point.feed_x = feed[0];
  s.point.feed_y = feed[1];
  s.line = m.line;
  s.index = static_cast<int>(k);
  s.count = static_cast<int>(v.size()) - 1;
  s.rapid = m.kind == interp::MotionKind::rapid;
  return s;
}

std::vector<CLSample> cl_samples(std::span<const interp::Motion> motions, const PathOptions& o,
                                 std::array<double, 2>* last_feed) {
  std::array<double, 2> feed = last_feed ? *last_feed : std::array<double, 2>{1, 0};
  std::vector<CLSample> out;
  for (std::size_t mi = 0; mi < motions.size(); ++mi) {
    const interp::Motion& m = motions[mi];
    const std::vector<Point3> v = motion_vertices(m, o);
    const int n = static_cast<int>(v.size()) - 1;
    for (int k = 1; k <= n; ++k) {
      out.push_back(cl_sample(m, v, static_cast<std::size_t>(k), feed));
      out.back().motion = mi;
    }
  }
  if (last_feed) *last_feed = feed;
  return out;
}

}  // namespace deflex::engage
