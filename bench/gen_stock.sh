#!/bin/sh
# gen_stock.sh N OUT [ALLOWANCE_MM]: the semi-finished stock of gen_program.sh's
# raster of about N blocks: its wavy surface z = -1 - 2 sin(x/15) cos(y/20)
# raised by the finishing allowance (default 0.2 mm), as an ASCII STL height
# field on a 2 mm grid, 10 mm beyond the path on every side (deflex takes the
# upper envelope of the triangles: no sides or bottom needed). The 2 mm grid
# is within 5 um of the surface (curvature <= 2/15^2 per mm). Needs only awk.
set -eu
n=${1:-1000000}; out=${2:-bench/data/stock_${n}.stl}; allow=${3:-0.2}
mkdir -p "$(dirname "$out")"
awk -v n="$n" -v a="$allow" 'function f(x, y) { return -1.0 - 2.0 * sin(x / 15.0) * cos(y / 20.0) + a }
function v(x, y) { printf "vertex %.3f %.3f %.4f\n", x, y, f(x, y) }
function tri(x0, y0, x1, y1, x2, y2) {
  print "facet normal 0 0 1"; print "outer loop"; v(x0, y0); v(x1, y1); v(x2, y2); print "endloop"; print "endfacet"
}
BEGIN {
  rows = int((n - 10) / 501); ymax = (rows - 1) * 0.125  # the rows are centred on Y0 (gen_program.sh)
  print "solid finish_stock"
  for (x = -10; x < 210; x += 2)
    for (y = -ymax - 10; y < ymax + 10; y += 2) { tri(x, y, x + 2, y, x + 2, y + 2); tri(x, y, x + 2, y + 2, x, y + 2) }
  print "endsolid finish_stock"
}' > "$out"
echo "$out"
