#include "deflex/compensate/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace deflex::compensate {
namespace {

// Diverging scale: blue (-1) .. white (0) .. red (+1).
std::string colour(double t) {
  t = std::clamp(t, -1.0, 1.0);
  int r, g, b;
  if (t >= 0) { r = 255; g = b = static_cast<int>(255 * (1 - t)); }
  else { b = 255; r = g = static_cast<int>(255 * (1 + t)); }
  char buf[16];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", r, g, b);
  return buf;
}

}  // namespace

std::string error_map_svg(const std::vector<PlotPoint>& pts, double tol, double scale, const std::string& title) {
  const double W = 700, margin = 60, bar = 110;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& p : pts) {
    x0 = std::min(x0, p.x_mm); x1 = std::max(x1, p.x_mm);
    y0 = std::min(y0, p.y_mm); y1 = std::max(y1, p.y_mm);
  }
  if (pts.empty()) { x0 = y0 = 0; x1 = y1 = 1; }
  const double span_x = std::max(x1 - x0, 1e-6), span_y = std::max(y1 - y0, 1e-6);
  const double px_per_mm = (W - 2 * margin - bar) / span_x;
  const double H = std::clamp(span_y * px_per_mm, 60.0, 900.0) + 2 * margin;
  const double sy = (H - 2 * margin) / span_y;
  // Raster of ~3 px cells: keep the error of largest magnitude per cell.
  const int nx = static_cast<int>((W - 2 * margin - bar) / 3), ny = std::max(1, static_cast<int>((H - 2 * margin) / 3));
  std::vector<double> cell(static_cast<std::size_t>(nx) * ny, NAN);
  for (const auto& p : pts) {
    const int i = std::min(nx - 1, static_cast<int>((p.x_mm - x0) / span_x * nx));
    const int j = std::min(ny - 1, static_cast<int>((p.y_mm - y0) / span_y * ny));
    double& c = cell[static_cast<std::size_t>(j) * nx + i];
    if (std::isnan(c) || std::fabs(p.error_mm) > std::fabs(c)) c = p.error_mm;
  }
  std::string s;
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" font-family=\"sans-serif\" font-size=\"12\">\n"
                "<rect width=\"100%%\" height=\"100%%\" fill=\"#f4f4f4\"/>\n<text x=\"%.0f\" y=\"22\" font-size=\"14\">%s</text>\n",
                W, H, margin, title.c_str());
  s += buf;
  const double cw = (W - 2 * margin - bar) / nx, ch = (H - 2 * margin) / ny;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double e = cell[static_cast<std::size_t>(j) * nx + i];
      if (std::isnan(e)) continue;
      const std::string c = std::fabs(e) <= tol ? "#ffffff" : colour(e / scale);
      // SVG y grows downwards: flip so +Y is up.
      std::snprintf(buf, sizeof buf, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.2f\" height=\"%.2f\" fill=\"%s\"/>\n",
                    margin + i * cw, H - margin - (j + 1) * ch, cw + 0.05, ch + 0.05, c.c_str());
      s += buf;
    }
  // Axes (mm).
  std::snprintf(buf, sizeof buf,
                "<rect x=\"%.0f\" y=\"%.0f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"#333\"/>\n"
                "<text x=\"%.0f\" y=\"%.0f\">X %.1f</text><text x=\"%.1f\" y=\"%.0f\" text-anchor=\"end\">%.1f mm</text>\n"
                "<text x=\"4\" y=\"%.0f\">Y %.1f</text><text x=\"4\" y=\"%.0f\">%.1f</text>\n",
                margin, margin, span_x * px_per_mm, span_y * sy, margin, H - margin + 16, x0, margin + span_x * px_per_mm,
                H - margin + 16, x1, H - margin, y0, margin + 10, y1);
  s += buf;
  // Colour bar.
  const double bx = W - bar + 10, bh = H - 2 * margin;
  for (int k = 0; k < 50; ++k) {
    const double t = 1 - 2.0 * k / 49;
    std::snprintf(buf, sizeof buf, "<rect x=\"%.0f\" y=\"%.1f\" width=\"14\" height=\"%.2f\" fill=\"%s\"/>\n", bx,
                  margin + k * bh / 50, bh / 50 + 0.5, std::fabs(t * scale) <= tol ? "#ffffff" : colour(t).c_str());
    s += buf;
  }
  std::snprintf(buf, sizeof buf,
                "<text x=\"%.0f\" y=\"%.0f\">+%.1f um</text><text x=\"%.0f\" y=\"%.0f\">0</text>"
                "<text x=\"%.0f\" y=\"%.0f\">-%.1f um</text>\n"
                "<text x=\"%.0f\" y=\"%.0f\" font-size=\"11\">surface error; white: within +-%.1f um (red: material left)</text>\n</svg>\n",
                bx + 18, margin + 10, scale * 1000, bx + 18, margin + bh / 2 + 4, bx + 18, margin + bh, scale * 1000, margin,
                H - 10, tol * 1000);
  s += buf;
  return s;
}

}  // namespace deflex::compensate
