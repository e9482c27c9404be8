#!/bin/sh
# Regenerates the compensation samples (POSIX sh + awk only):
#
#   programs/six_surfaces.nc      ball D16 finishing of the six-surface part of
#                                 Smaoui et al. 2011 (paper 001), C35 steel
#   stock/six_surfaces_stock.stl  its semi-finished stock (1.0 mm allowance)
#   programs/side_wall.nc         flat D12 side milling of a straight wall in
#                                 down-milling (Morelli et al. 2021, paper 003), Al 6082-T4
#   stock/side_wall.yaml          its box stock
#   programs/freeform.nc          ball D10 finishing of z = A sin(2 pi x/Lx) cos(2 pi y/Ly),
#                                 Al 7075-T6
#   stock/freeform_stock.stl      its semi-finished stock (0.3 mm allowance)
#
# Usage: sh samples/generate.sh [DIR]   (from anywhere; writes DIR/programs and
#        DIR/stock, by default next to this script; tests/samples regenerates into
#        a temporary DIR and compares with the committed files)
# Output is deterministic: the same bytes on every run (C locale, fixed decimals).
#
# Conventions of all three programs (Fanuc 0i/30i, dialect `fanuc`):
#   % at start and end, O number, N numbers on every block (N10, step 2),
#   G21 G90 G17 G40 G49 G80 safety line, Tn M06, G54, S.. M03, G43 Hn, M08,
#   G01 with modal axis words (only the axes that change), F on the first
#   cutting move, G00 retract to Z50., M05 M09, G91 G28 Z0., M30.
#   Every number carries a decimal point; 3 decimals (1 um), trailing zeros dropped.
#   LF line ends.
#
# CL points (all programs give the tool TIP, as Fanuc G43 expects with a tool
# length measured to the tip):
#   A ball end of radius R touching the surface from above has its centre on the
#   offset surface at distance R along the surface normal; the tip is the centre
#   minus R in Z. The centre height over (x, y) is the "drop-cutter" height: the
#   highest contact over every face, edge and vertex of the surface within R.
#   six_surfaces: the profile is 2D (extruded along Y): lines, circular arcs and
#     their end points, each contact computed in closed form (the offset of a
#     concave arc of radius rho is a circle of radius rho - R, of a convex one
#     rho + R, of a vertex a circle of radius R), then the highest one is taken.
#   freeform: the surface is smooth and its smallest radius of curvature
#     (18.2 mm) exceeds R = 5 mm, so the offset is exact and local: the contact
#     point (u, v) solves (u, v) + R n_xy(u, v) = (x, y) (fixed-point iteration,
#     a contraction since R * curvature < 1).
#   The CL curve of each pass is sampled on a fine grid along X (0.01 mm /
#   0.1 mm) and thinned to the CAM-like point list: consecutive points at most
#   0.5 mm apart (3D) and the curve within 0.001 mm of every chord, so points
#   crowd where the CL curve is tightly curved (the ridge of the six-surface part).
#
# Stocks: the semi-finished stock is the finished surface offset along its
# normal by a uniform allowance (the drop-cutter height of a ball of radius =
# allowance), written as a closed ASCII STL: top surface as a grid, four sides,
# bottom (a fan) at z = -40 / -30. Facet normals are the outward unit normals.
set -eu
LC_ALL=C
export LC_ALL
here=${1:-$(cd "$(dirname "$0")" && pwd)}
mkdir -p "$here/programs" "$here/stock" "$here/parts"

# ---------------------------------------------------------------------------
# Shared awk functions: number formatting, block output, thinning, STL facets.
common='
function f3(v,   s) {              # 3 decimals, trailing zeros dropped, point kept
  s = sprintf("%.3f", v)
  if (s == "-0.000") s = "0.000"
  sub(/0+$/, "", s)
  return s
}
function f4(v,   s) {              # STL numbers: 4 decimals, no needless zeros
  s = sprintf("%.4f", v)
  if (s == "-0.0000") s = "0.0000"
  sub(/0+$/, "", s); sub(/\.$/, "", s)
  return s
}
function blk(s) { printf "N%d %s\n", nblk, s > OUT; nblk += 2; blocks++ }
function cmt(s) { printf "(%s)\n", s > OUT }
# The common end of every program: retract, spindle and coolant off, home Z, M30.
function program_end() {
  blk("G00 Z50."); blk("M05 M09"); blk("G91 G28 Z0."); blk("M30")
  printf "%%\n" > OUT
  close(OUT)
}
# Modal linear move to (x, y, z): only the words that change; "" when nothing does.
function mv(x, y, z,   w, sx, sy, sz) {
  sx = f3(x); sy = f3(y); sz = f3(z); w = ""
  if (sx != lx) w = w " X" sx
  if (sy != ly) w = w " Y" sy
  if (sz != lz) w = w " Z" sz
  lx = sx; ly = sy; lz = sz
  return substr(w, 2)
}
# Thins the fine polyline PX[0..n], PZ[0..n] (monotone in x) into KEEP[0..nk-1]:
# each segment at most maxlen long (3D, y fixed) and every fine point within tol
# of its chord. Returns nk.
function thin(n, maxlen, tol,   i, j, k, best, ok, dx, dz, len, d, nk) {
  nk = 0; KEEP[nk++] = 0; i = 0
  while (i < n) {
    best = i + 1
    for (j = i + 2; j <= n; j++) {
      dx = PX[j] - PX[i]; dz = PZ[j] - PZ[i]; len = sqrt(dx * dx + dz * dz)
      if (len > maxlen) break
      ok = 1
      for (k = i + 1; k < j; k++) {
        d = ((PX[k] - PX[i]) * dz - (PZ[k] - PZ[i]) * dx) / len
        if (d > tol || d < -tol) { ok = 0; break }
      }
      if (!ok) break
      best = j
    }
    KEEP[nk++] = best; i = best
  }
  return nk
}
# One STL facet, vertices counter-clockwise seen from outside.
function facet(ax, ay, az, bx, by, bz, cx, cy, cz,   ux, uy, uz, vx, vy, vz, nx, ny, nz, l) {
  ux = bx - ax; uy = by - ay; uz = bz - az
  vx = cx - ax; vy = cy - ay; vz = cz - az
  nx = uy * vz - uz * vy; ny = uz * vx - ux * vz; nz = ux * vy - uy * vx
  l = sqrt(nx * nx + ny * ny + nz * nz); if (l > 0) { nx /= l; ny /= l; nz /= l }
  printf "facet normal %s %s %s\nouter loop\nvertex %s %s %s\nvertex %s %s %s\nvertex %s %s %s\nendloop\nendfacet\n", \
    f4(nx), f4(ny), f4(nz), f4(ax), f4(ay), f4(az), f4(bx), f4(by), f4(bz), f4(cx), f4(cy), f4(cz) > STL
  facets++
}
'

# ---------------------------------------------------------------------------
# 1. Six-surface part (Smaoui, Bouaziz, Zghal, Dessein, Baili 2011, paper 001 §4).
awk -v OUT="$here/programs/six_surfaces.nc" -v STOCK="$here/stock/six_surfaces_stock.stl" \
    -v PART="$here/parts/six_surfaces.stl" "$common"'
# Profile z = f(x), extruded along Y over [0, W]. Primitives: lines (LX0..LZ1) and
# arcs (centre AX, AZ, radius AR, x range AXA..AXB, ACV = 1 convex / 0 concave);
# the end planes are extended beyond the part so the tool runs on in air.
function line(x0, z0, x1, z1) { LX0[nl] = x0; LZ0[nl] = z0; LX1[nl] = x1; LZ1[nl] = z1; vert(x0, z0); vert(x1, z1); nl++ }
function arc(cx, cz, r, xa, xb, convex,   s) {
  AX[na] = cx; AZ[na] = cz; AR[na] = r; AXA[na] = xa; AXB[na] = xb; ACV[na] = convex
  s = convex ? 1 : -1
  vert(xa, cz + s * sqrt(r * r - (xa - cx) ^ 2)); vert(xb, cz + s * sqrt(r * r - (xb - cx) ^ 2)); na++
}
function vert(x, z) { VX[nv] = x; VZ[nv] = z; nv++ }
# Height of the profile itself at x (the highest primitive over x).
function profile(x,   best, i, m, d, z) {
  best = -1e9
  for (i = 0; i < nl; i++)
    if (x >= LX0[i] && x <= LX1[i]) { m = (LZ1[i] - LZ0[i]) / (LX1[i] - LX0[i]); if (LZ0[i] + m * (x - LX0[i]) > best) best = LZ0[i] + m * (x - LX0[i]) }
  for (i = 0; i < na; i++) {
    d = x - AX[i]
    if (x < AXA[i] || x > AXB[i]) continue
    z = ACV[i] ? AZ[i] + sqrt(AR[i] ^ 2 - d * d) : AZ[i] - sqrt(AR[i] ^ 2 - d * d)
    if (z > best) best = z
  }
  return best
}
# The solid under the profile offset by off along its normal (0: the part
# itself), over x 0..220, y 0..78, bottom ZB, as a closed ASCII STL.
function solid(off, out, name,   n, i, nk, k, x0, x1, z0, z1, nb, kk) {
  STL = out
  n = int(L / 0.05 + 0.5)
  for (i = 0; i <= n; i++) { PX[i] = i * 0.05; PZ[i] = off > 0 ? drop(PX[i], off) : profile(PX[i]) }
  nk = thin(n, 5, 0.002)
  for (k = 0; k < nk; k++) { SX[k] = PX[KEEP[k]]; SZ[k] = PZ[KEEP[k]] }
  printf "solid %s\n", name > STL
  for (k = 0; k + 1 < nk; k++) {
    x0 = SX[k]; x1 = SX[k + 1]; z0 = SZ[k]; z1 = SZ[k + 1]
    facet(x0, 0, z0, x1, 0, z1, x1, W, z1); facet(x0, 0, z0, x1, W, z1, x0, W, z0)       # top
    facet(x0, 0, ZB, x1, 0, ZB, x1, 0, z1); facet(x0, 0, ZB, x1, 0, z1, x0, 0, z0)       # front y = 0
    facet(x1, W, ZB, x0, W, ZB, x0, W, z0); facet(x1, W, ZB, x0, W, z0, x1, W, z1)       # back y = W
  }
  facet(0, W, ZB, 0, 0, ZB, 0, 0, SZ[0]); facet(0, W, ZB, 0, 0, SZ[0], 0, W, SZ[0])      # left x = 0
  facet(L, 0, ZB, L, W, ZB, L, W, SZ[nk - 1]); facet(L, 0, ZB, L, W, SZ[nk - 1], L, 0, SZ[nk - 1])
  # bottom: fan from its centre to every boundary vertex (conforming with the sides)
  nb = 0
  for (k = 0; k < nk; k++) { BX[nb] = SX[k]; BY[nb] = 0; nb++ }
  for (k = nk - 1; k >= 0; k--) { BX[nb] = SX[k]; BY[nb] = W; nb++ }
  for (k = 0; k < nb; k++) {
    kk = (k + 1) % nb
    facet(L / 2, W / 2, ZB, BX[kk], BY[kk], ZB, BX[k], BY[k], ZB)
  }
  printf "endsolid %s\n", name > STL
  close(STL)
}

# Height of the centre of a ball of radius r dropped onto the profile at x.
function drop(x, r,   best, i, m, s, u, z, d, rr) {
  best = -1e9
  for (i = 0; i < nl; i++) {            # face contact: centre on the line offset by r
    m = (LZ1[i] - LZ0[i]) / (LX1[i] - LX0[i]); s = sqrt(1 + m * m)
    u = x + r * m / s
    if (u >= LX0[i] && u <= LX1[i]) { z = LZ0[i] + m * (u - LX0[i]) + r / s; if (z > best) best = z }
  }
  for (i = 0; i < na; i++) {            # arc contact: offset circle of radius rho +- r
    d = x - AX[i]
    rr = ACV[i] ? AR[i] + r : AR[i] - r
    if (rr <= 0 || d > rr || d < -rr) continue
    u = AX[i] + AR[i] * d / rr
    if (u < AXA[i] || u > AXB[i]) continue
    z = ACV[i] ? AZ[i] + sqrt(rr * rr - d * d) : AZ[i] - sqrt(rr * rr - d * d)
    if (z > best) best = z
  }
  for (i = 0; i < nv; i++) {            # edge contact: circle of radius r round a vertex
    d = x - VX[i]
    if (d > r || d < -r) continue
    z = VZ[i] + sqrt(r * r - d * d); if (z > best) best = z
  }
  return best
}
BEGIN {
  pi = atan2(0, -1); nl = 0; na = 0; nv = 0
  R = 8; L = 220; W = 78; A = 1.0          # ball radius, part length and width, allowance
  ALPHA = 20; RHO = 40                     # incline angle (deg), arc radius
  STEP = 1.0; XIN = -10; XOUT = 230        # step-over; pass start / end (ball clear of the part)
  ZB = -40                                 # stock bottom
  t = sin(ALPHA * pi / 180) / cos(ALPHA * pi / 180)
  H = 35 * t                               # height of the inclines
  S = sqrt(RHO * RHO - 20 * 20)            # arc centre below/above the chord
  line(-60, 0, 35, 0)                      # 1 plane           x   0 ..  35
  line(35, 0, 70, H)                       # 2 incline up      x  35 ..  70, +20 deg
  arc(90, H + S, RHO, 70, 110, 0)          # 3 concave circle  x  70 .. 110, R 40
  arc(130, H - S, RHO, 110, 150, 1)        # 4 convex circle   x 110 .. 150, R 40
  line(150, H, 185, 0)                     # 5 incline down    x 150 .. 185, -20 deg
  line(185, 0, 280, 0)                     # 6 plane           x 185 .. 220

  # --- CL points of one pass (every pass is the same: the part is extruded along Y)
  n = int((XOUT - XIN) / 0.01 + 0.5)
  for (i = 0; i <= n; i++) { PX[i] = XIN + i * 0.01; PZ[i] = drop(PX[i], R) - R }
  nk = thin(n, 0.5, 0.001)
  for (k = 0; k < nk; k++) { CX[k] = PX[KEEP[k]]; CZ[k] = PZ[KEEP[k]] }
  ncl = nk
  npass = int(W / STEP + 0.5) + 1

  nblk = 10
  printf "%%\n" > OUT
  printf "O5001 (DEFLEX SAMPLE - SIX-SURFACE PART - SMAOUI 2011 PAPER 001)\n" > OUT
  cmt("GENERATED BY SAMPLES/GENERATE.SH - DO NOT EDIT")
  cmt("PART 220 X 78 MM, X ALONG THE LENGTH, Y ACROSS, PROFILE EXTRUDED ALONG Y")
  cmt("WORK ZERO G54 - X0 Y0 AT THE LEFT FRONT CORNER, Z0 ON THE TWO END PLANES")
  cmt("SURFACES ALONG X, PROFILE Z = F OF X -")
  cmt(" 1 PLANE          X 0 TO 35     Z 0")
  cmt(" 2 INCLINE UP     X 35 TO 70    +20 DEG, Z 0 TO " f3(H))
  cmt(" 3 CONCAVE CIRCLE X 70 TO 110   R 40, CENTRE X90 Z" f3(H + S) ", LOWEST Z" f3(H + S - RHO))
  cmt(" 4 CONVEX CIRCLE  X 110 TO 150  R 40, CENTRE X130 Z" f3(H - S) ", TOP Z" f3(H - S + RHO))
  cmt(" 5 INCLINE DOWN   X 150 TO 185  -20 DEG, Z " f3(H) " TO 0")
  cmt(" 6 PLANE          X 185 TO 220  Z 0")
  cmt("3 AND 4 JOIN TANGENTIALLY AT X110 - SHARP RIDGE AT X70, SHARP HOLLOWS AT X35 X150 X185")
  cmt("PAPER GIVES ONLY THE ORDER OF THE SURFACES AND 220 X 78 - LENGTHS, ANGLES, RADII CHOSEN HERE")
  cmt("TOOL T5 BALL END D16 R8, 2 FLUTES, HELIX 9 DEG, STICKOUT 80 - MATERIAL C35")
  cmt("S4000 FZ 0.1 - F800 AS IN THE PAPER, FINISHING ALLOWANCE 1.0 MM = THE PAPER AXIAL DEPTH AD")
  cmt("STOCK SAMPLES/STOCK/SIX_SURFACES_STOCK.STL - SURFACE OFFSET 1.0 ALONG THE NORMAL, BOTTOM Z-40")
  cmt("ZIG-ZAG ALONG +X AND -X, STEP-OVER 1.0 IN +Y, " npass " PASSES Y0 TO Y78, X-10 TO X230")
  cmt("TIP ON THE BALL OFFSET OF THE PROFILE, POINTS AT MOST 0.5 APART, CHORD ERROR 0.001")
  blk("G21 G90 G17 G40 G49 G80")
  blk("T5 M06")
  lx = f3(CX[0]); ly = f3(0); lz = ""
  blk("G00 G54 X" lx " Y" ly " S4000 M03")
  blk("G43 H5 " mv(CX[0], 0, 50) " M08")
  blk(mv(CX[0], 0, 5))
  blk("G01 " mv(CX[0], 0, CZ[0]) " F800.")
  for (p = 0; p < npass; p++) {
    y = p * STEP
    if (p > 0) blk(mv(p % 2 ? CX[nk - 1] : CX[0], y, p % 2 ? CZ[nk - 1] : CZ[0]))
    if (p % 2 == 0) { for (k = 1; k < nk; k++) { w = mv(CX[k], y, CZ[k]); if (w != "") blk(w) } }
    else { for (k = nk - 2; k >= 0; k--) { w = mv(CX[k], y, CZ[k]); if (w != "") blk(w) } }
  }
  program_end()

  solid(A, STOCK, "six_surfaces_stock")
  solid(0, PART, "six_surfaces_part")
  printf "six_surfaces.nc: %d blocks, %d passes of %d points; stock %d facets\n", blocks, npass, ncl, facets
}'

# ---------------------------------------------------------------------------
# 2. Side-milled wall (Morelli, Grossi, Scippa, Campatelli 2021, paper 003, test IIM):
#    flat end mill D12, 4 flutes, helix 45 deg; a_e 2.5 mm, a_p 12 mm, down-milling,
#    6366 rpm, f_z 0.1 mm -> F 2546.4 mm/min; Al 6082-T4.
#    Stock box X 0..100, Y -40..0, Z -30..0 (the wall face starts at Y0). Two passes
#    along +X, each a_e 2.5: tool centre at Y3.5 (face to Y-2.5), then Y1.0 (face to
#    Y-5.0). The material lies on the right of the feed direction with M03 (CW):
#    down-milling (climb), the wall is generated at the cutter exit angle.
awk -v OUT="$here/programs/side_wall.nc" "$common"'
BEGIN {
  nblk = 10
  printf "%%\n" > OUT
  printf "O5002 (DEFLEX SAMPLE - SIDE-MILLED WALL - MORELLI 2021 PAPER 003)\n" > OUT
  cmt("GENERATED BY SAMPLES/GENERATE.SH - DO NOT EDIT")
  cmt("STOCK BOX X0 TO X100, Y-40 TO Y0, Z-30 TO Z0 - SAMPLES/STOCK/SIDE_WALL.YAML")
  cmt("WORK ZERO G54 - X0 Y0 Z0 AT THE TOP EDGE OF THE WALL FACE, LEFT END")
  cmt("WALL 100 LONG ALONG X, FACE NORMAL +Y, MATERIAL ON -Y")
  cmt("TOOL T6 FLAT END MILL D12, 4 FLUTES, HELIX 45 DEG, STICKOUT 50 - MATERIAL AL 6082-T4")
  cmt("PAPER TEST IIM - AE 2.5 AP 12 - S6366 FZ 0.1 - F2546.4 - DOWN-MILLING, M03 ALONG +X")
  cmt("PASS 1 TOOL CENTRE Y3.5 - FACE TO Y-2.5 - PASS 2 Y1. - FACE TO Y-5. - BOTH AT Z-12.")
  blk("G21 G90 G17 G40 G49 G80")
  blk("T6 M06")
  blk("G00 G54 X-10. Y3.5 S6366 M03")
  blk("G43 H6 Z50. M08")
  blk("Z5.")
  blk("G01 Z-12. F1000.")
  blk("X110. F2546.4")
  blk("G00 Z5.")
  blk("X-10. Y1.")
  blk("G01 Z-12. F1000.")
  blk("X110. F2546.4")
  program_end()
  printf "side_wall.nc: %d blocks\n", blocks
}'
cat > "$here/stock/side_wall.yaml" <<'YAML'
# Stock of programs/side_wall.nc (generated by samples/generate.sh): the block
# before the two wall passes, work frame G54 (X0 Y0 Z0 = top edge of the wall
# face at its left end). deflex --stock box:X0,Y0,Z0,X1,Y1,Z1
stock: box:0,-40,-30,100,0,0
YAML

# ---------------------------------------------------------------------------
# 3. Freeform surface z = A sin(2 pi x / LX) cos(2 pi y / LY), A 5, LX 60, LY 80,
#    over X 0..120, Y 0..80 (two waves along X, one along Y); ball end D10,
#    Al 7075-T6, S10000, f_z 0.08 -> F1600; zig-zag along X, step-over 0.8 mm;
#    stock = surface offset 0.3 mm along its normal, bottom z = -30.
# The freeform surface and its ball offset, shared by sections 3 and 4.
freeform='
function f(x, y) { return AMP * sin(KX * x) * cos(KY * y) }
# Centre height of a ball of radius r on the offset surface above (x, y): solves
# (u, v) + r n_xy(u, v) = (x, y) for the contact point by fixed-point iteration.
function offset(x, y, r,   u, v, fx, fy, s, un, vn, it) {
  u = x; v = y
  for (it = 0; it < 200; it++) {
    fx = AMP * KX * cos(KX * u) * cos(KY * v)
    fy = -AMP * KY * sin(KX * u) * sin(KY * v)
    s = sqrt(1 + fx * fx + fy * fy)
    un = x + r * fx / s; vn = y + r * fy / s
    if ((un - u) ^ 2 + (vn - v) ^ 2 < 1e-24) break
    u = un; v = vn
  }
  fx = AMP * KX * cos(KX * un) * cos(KY * vn)
  fy = -AMP * KY * sin(KX * un) * sin(KY * vn)
  return f(un, vn) + r / sqrt(1 + fx * fx + fy * fy)
}
'

awk -v OUT="$here/programs/freeform.nc" -v STOCK="$here/stock/freeform_stock.stl" \
    -v PART="$here/parts/freeform.stl" "$common$freeform"'
# The solid under the surface offset by off along its normal (0: the part
# itself), bottom ZB, as a closed ASCII STL. Top grid: 1.5 x 2 mm for the
# stock; 0.75 x 1 mm for the part, whose facets then lie within 0.011 mm of the
# surface (sagitta of the grid diagonal at the largest curvature, 1/18.2 mm).
function solid(off, out, name,   GX, GY, nx, ny, i, j, x0, x1, y0, y1, nb, k, kk) {
  STL = out
  GX = off > 0 ? 1.5 : 0.75; GY = off > 0 ? 2 : 1; nx = int(L / GX + 0.5); ny = int(W / GY + 0.5)
  for (j = 0; j <= ny; j++) for (i = 0; i <= nx; i++) T[i, j] = off > 0 ? offset(i * GX, j * GY, off) : f(i * GX, j * GY)
  printf "solid %s\n", name > STL
  for (j = 0; j < ny; j++) for (i = 0; i < nx; i++) {
    x0 = i * GX; x1 = x0 + GX; y0 = j * GY; y1 = y0 + GY
    facet(x0, y0, T[i, j], x1, y0, T[i + 1, j], x1, y1, T[i + 1, j + 1])
    facet(x0, y0, T[i, j], x1, y1, T[i + 1, j + 1], x0, y1, T[i, j + 1])
  }
  for (i = 0; i < nx; i++) {
    x0 = i * GX; x1 = x0 + GX
    facet(x0, 0, ZB, x1, 0, ZB, x1, 0, T[i + 1, 0]); facet(x0, 0, ZB, x1, 0, T[i + 1, 0], x0, 0, T[i, 0])
    facet(x1, W, ZB, x0, W, ZB, x0, W, T[i, ny]); facet(x1, W, ZB, x0, W, T[i, ny], x1, W, T[i + 1, ny])
  }
  for (j = 0; j < ny; j++) {
    y0 = j * GY; y1 = y0 + GY
    facet(0, y1, ZB, 0, y0, ZB, 0, y0, T[0, j]); facet(0, y1, ZB, 0, y0, T[0, j], 0, y1, T[0, j + 1])
    facet(L, y0, ZB, L, y1, ZB, L, y1, T[nx, j + 1]); facet(L, y0, ZB, L, y1, T[nx, j + 1], L, y0, T[nx, j])
  }
  nb = 0                                    # bottom: fan over the boundary, counter-clockwise from above
  for (i = 0; i < nx; i++) { BX[nb] = i * GX; BY[nb] = 0; nb++ }
  for (j = 0; j < ny; j++) { BX[nb] = L; BY[nb] = j * GY; nb++ }
  for (i = nx; i > 0; i--) { BX[nb] = i * GX; BY[nb] = W; nb++ }
  for (j = ny; j > 0; j--) { BX[nb] = 0; BY[nb] = j * GY; nb++ }
  for (k = 0; k < nb; k++) { kk = (k + 1) % nb; facet(L / 2, W / 2, ZB, BX[kk], BY[kk], ZB, BX[k], BY[k], ZB) }
  printf "endsolid %s\n", name > STL
  close(STL)
}

BEGIN {
  pi = atan2(0, -1)
  AMP = 5; LX = 60; LY = 80; KX = 2 * pi / LX; KY = 2 * pi / LY
  L = 120; W = 80; R = 5; A = 0.3; ZB = -30
  STEP = 0.8; XIN = -6; XOUT = 126; H = 0.1
  npass = int(W / STEP + 0.5) + 1
  n = int((XOUT - XIN) / H + 0.5)

  nblk = 10
  printf "%%\n" > OUT
  printf "O5003 (DEFLEX SAMPLE - FREEFORM BALL-END FINISHING)\n" > OUT
  cmt("GENERATED BY SAMPLES/GENERATE.SH - DO NOT EDIT")
  cmt("SURFACE Z = 5 SIN 6X COS 4.5Y - ANGLES IN DEGREES, X Y IN MM - OVER X0 TO X120, Y0 TO Y80")
  cmt("WORK ZERO G54 - X0 Y0 AT THE LEFT FRONT CORNER, Z0 ON THE MEAN PLANE OF THE SURFACE")
  cmt("TOOL T7 BALL END D10 R5, 2 FLUTES, HELIX 30 DEG, STICKOUT 45 - MATERIAL AL 7075-T6")
  cmt("S10000 FZ 0.08 - F1600, FINISHING ALLOWANCE 0.3 ALONG THE NORMAL")
  cmt("STOCK SAMPLES/STOCK/FREEFORM_STOCK.STL - SURFACE OFFSET 0.3, BOTTOM Z-30")
  cmt("ZIG-ZAG ALONG +X AND -X, STEP-OVER 0.8 IN +Y, " npass " PASSES Y0 TO Y80, X-6 TO X126")
  cmt("TIP ON THE BALL OFFSET OF THE SURFACE, POINTS AT MOST 0.5 APART, CHORD ERROR 0.001")
  blk("G21 G90 G17 G40 G49 G80")
  blk("T7 M06")
  lx = f3(XIN); ly = f3(0); lz = ""
  blk("G00 G54 X" lx " Y" ly " S10000 M03")
  blk("G43 H7 " mv(XIN, 0, 50) " M08")
  blk(mv(XIN, 0, 5))
  for (p = 0; p < npass; p++) {
    y = p * STEP
    for (i = 0; i <= n; i++) { PX[i] = XIN + i * H; PZ[i] = offset(PX[i], y, R) - R }
    nk = thin(n, 0.5, 0.001)
    if (p == 0) blk("G01 " mv(PX[0], y, PZ[0]) " F1600.")
    if (p % 2 == 0) { for (k = 0; k < nk; k++) { w = mv(PX[KEEP[k]], y, PZ[KEEP[k]]); if (w != "") blk(w) } }
    else { for (k = nk - 1; k >= 0; k--) { w = mv(PX[KEEP[k]], y, PZ[KEEP[k]]); if (w != "") blk(w) } }
    cl += nk
  }
  program_end()

  solid(A, STOCK, "freeform_stock")
  solid(0, PART, "freeform_part")
  printf "freeform.nc: %d blocks, %d passes, %d CL points; stock %d facets\n", blocks, npass, cl, facets
}'
cat > "$here/stock/six_surfaces.yaml" <<'YAML'
# Stock of programs/six_surfaces.nc (generated by samples/generate.sh): the
# finished six-surface profile offset by 1.0 mm along its normal, X 0..220,
# Y 0..78, bottom Z-40, work frame G54. deflex --stock samples/stock/six_surfaces_stock.stl
stock: six_surfaces_stock.stl
YAML
cat > "$here/stock/freeform.yaml" <<'YAML'
# Stock of programs/freeform.nc (generated by samples/generate.sh): the freeform
# surface offset by 0.3 mm along its normal, X 0..120, Y 0..80, bottom Z-30,
# work frame G54. deflex --stock samples/stock/freeform_stock.stl
stock: freeform_stock.stl
YAML

# ---------------------------------------------------------------------------
# 4. Strategies (after Bagci & Yuncuoglu 2017, paper 000, Table 4):
#    the freeform part of section 3 finished four ways from the same stock with
#    the same tool and cutting data, so `deflex compare` can rank them:
#      strategies/zigzag_0.nc    zig-zag along X (passes at 0 deg), stepping in +Y
#      strategies/zigzag_45.nc   zig-zag at 45 deg
#      strategies/zigzag_90.nc   zig-zag along Y (passes at 90 deg), stepping in -X
#      strategies/contour.nc     contour-parallel: rectangular loops from the part
#                                edge inwards (counter-clockwise seen from above),
#                                each joined to the next by a G01 step inwards
#    T7 ball D10, S10000 F1600, step-over 2.0 mm (the paper used 3 mm with a
#    D12 ball: the same cusp-to-radius ratio order), CL points as in section 3
#    (tip on the ball offset, points at most 0.5 mm apart, chord error 0.001).
#    Zig-zag passes run over X-6..126 / Y-6..86 (the ball clear of the stock at
#    both ends) and are joined by G01 moves outside the stock.
mkdir -p "$here/strategies"
awk -v DIR="$here/strategies" "$common$freeform"'
function header(o, title, strategy) {
  nblk = 10; blocks = 0; cl = 0; lx = ""; ly = ""; lz = ""
  printf "%%\n" > OUT
  printf "O%d (DEFLEX STRATEGY SAMPLE - %s)\n", o, title > OUT
  cmt("GENERATED BY SAMPLES/GENERATE.SH - DO NOT EDIT")
  cmt("PART SAMPLES/PARTS/FREEFORM.STL - Z = 5 SIN 6X COS 4.5Y OVER X0 TO X120, Y0 TO Y80")
  cmt("STOCK SAMPLES/STOCK/FREEFORM_STOCK.STL - SURFACE OFFSET 0.3, BOTTOM Z-30")
  cmt("TOOL T7 BALL END D10 R5, 2 FLUTES, HELIX 30 DEG, STICKOUT 45 - MATERIAL AL 7075-T6")
  cmt(strategy)
  blk("G21 G90 G17 G40 G49 G80")
  blk("T7 M06")
}
function start(x, y) {
  lx = f3(x); ly = f3(y); lz = ""
  blk("G00 G54 X" lx " Y" ly " S10000 M03")
  blk("G43 H7 " mv(x, y, 50) " M08")
  blk(mv(x, y, 5))
}
function finish(name) {
  program_end()
  printf "%s: %d blocks, %d CL points\n", name, blocks, cl
}
# Samples the straight pass (x0, y0) -> (x1, y1) every H mm into PX (the arc
# length) and PZ (the tip height), thins it, and writes its points (the first
# with F when `first`); `skip` leaves out the first point (a corner the previous
# side ended on).
function pass(x0, y0, x1, y1, first, skip,   len, n, i, nk, k, t, x, y, w) {
  len = sqrt((x1 - x0) ^ 2 + (y1 - y0) ^ 2); n = int(len / H + 0.5); if (n < 1) n = 1
  for (i = 0; i <= n; i++) {
    t = i / n; PX[i] = t * len; PZ[i] = offset(x0 + t * (x1 - x0), y0 + t * (y1 - y0), R) - R
  }
  nk = thin(n, 0.5, 0.001)
  for (k = skip ? 1 : 0; k < nk; k++) {
    t = PX[KEEP[k]] / len; x = x0 + t * (x1 - x0); y = y0 + t * (y1 - y0)
    w = mv(x, y, PZ[KEEP[k]])
    if (first && k == 0) { blk("G01 " w " F1600."); first = 0 }
    else if (w != "") blk(w)
  }
  cl += nk - (skip ? 1 : 0)
}
# Clips the line c v + s u (u = (cos a, sin a), v = (-sin a, cos a)) to the
# rectangle XA..XB x YA..YB: sets S0, S1; returns whether it crosses it.
function clip(a, c,   ux, uy, px, py, lo, hi, t0, t1, tt) {
  ux = cos(a); uy = sin(a); px = -c * uy; py = c * ux; lo = -1e9; hi = 1e9
  if (ux * ux > 1e-18) { t0 = (XA - px) / ux; t1 = (XB - px) / ux; if (t0 > t1) { tt = t0; t0 = t1; t1 = tt }; if (t0 > lo) lo = t0; if (t1 < hi) hi = t1 }
  else if (px < XA || px > XB) return 0
  if (uy * uy > 1e-18) { t0 = (YA - py) / uy; t1 = (YB - py) / uy; if (t0 > t1) { tt = t0; t0 = t1; t1 = tt }; if (t0 > lo) lo = t0; if (t1 < hi) hi = t1 }
  else if (py < YA || py > YB) return 0
  S0 = lo; S1 = hi
  return hi > lo
}
# Zig-zag at deg degrees: passes c = cmin + k STEP across the part (c over the
# projections of its corners on v), alternating direction.
function zigzag(deg, o, name,   a, ux, uy, vx, vy, cmin, cmax, c, k, np, p, sa, sb, t) {
  OUT = DIR "/" name
  a = deg * pi / 180; ux = cos(a); uy = sin(a); vx = -uy; vy = ux
  cmin = 1e9; cmax = -1e9
  for (k = 0; k < 4; k++) { c = ((k % 2) ? L : 0) * vx + ((k >= 2) ? W : 0) * vy; if (c < cmin) cmin = c; if (c > cmax) cmax = c }
  np = int((cmax - cmin) / STEP - 1e-9) + 2
  header(o, "FREEFORM ZIG-ZAG " deg " DEG", "ZIG-ZAG, PASSES AT " deg " DEG TO +X, STEP-OVER " STEP ", " np " PASSES, F1600")
  for (p = 0; p < np; p++) {
    c = cmin + (p < np - 1 ? p * STEP : cmax - cmin)
    if (!clip(a, c)) continue
    sa = S0; sb = S1; if (p % 2) { t = sa; sa = sb; sb = t }
    if (p == 0) start(-c * uy + sa * ux, c * ux + sa * uy)
    pass(-c * uy + sa * ux, c * ux + sa * uy, -c * uy + sb * ux, c * ux + sb * uy, p == 0, 0)
  }
  finish(name)
}
# Contour-parallel: loops of the part outline offset inwards by j STEP,
# counter-clockwise, from a lead-in along +X outside the stock.
function contour(o, name,   nloop, j, d, x0, y0, x1, y1) {
  OUT = DIR "/" name
  nloop = int((W / 2) / STEP)
  header(o, "FREEFORM CONTOUR-PARALLEL", "CONTOUR-PARALLEL LOOPS INWARDS, COUNTER-CLOCKWISE, STEP-OVER " STEP ", " nloop + 1 " LOOPS, F1600")
  start(XA, 0)
  pass(XA, 0, 0, 0, 1, 0)
  for (j = 0; j <= nloop; j++) {
    d = j * STEP; x0 = d; y0 = d; x1 = L - d; y1 = W - d
    if (y1 - y0 < 1e-9) { pass(x0, y0, x1, y0, 0, 1); break }     # the last loop is a line
    pass(x0, y0, x1, y0, 0, 1); pass(x1, y0, x1, y1, 0, 1); pass(x1, y1, x0, y1, 0, 1); pass(x0, y1, x0, y0, 0, 1)
    if (j < nloop) pass(x0, y0, x0 + STEP, y0 + STEP, 0, 1)       # step inwards
  }
  finish(name)
}
BEGIN {
  pi = atan2(0, -1)
  AMP = 5; LX = 60; LY = 80; KX = 2 * pi / LX; KY = 2 * pi / LY
  L = 120; W = 80; R = 5; STEP = 2.0; H = 0.1
  XA = -6; XB = 126; YA = -6; YB = 86
  zigzag(0, 5101, "zigzag_0.nc")
  zigzag(45, 5102, "zigzag_45.nc")
  zigzag(90, 5103, "zigzag_90.nc")
  contour(5104, "contour.nc")
}'

# ---------------------------------------------------------------------------
# 5. Thin wall: an Al 7075-T6 block X 0..100, Y 0..60, Z -40..0 with a pocket
#    X 5..95, Y 2..55 down to a floor at Z-35, which leaves a wall 2 mm thick
#    and 35 mm high above the floor along Y 0..2 (the other walls 5 mm). The
#    part sits on its bottom face. Its finishing program cuts the wall's inner
#    face (Y2) from the roughed pocket, which left 0.1 mm on it (the stock: the
#    same block with the face at Y2.1): T6 flat D12 in Z levels 5 mm apart from
#    the top down (the wall below each level still the roughed one), a_e 0.1,
#    f_z 0.03 (a light cut: the wall gives way by some 20 um under it, the
#    tool by 2), down-milling along +X (M03, the wall on the right of the feed), the tool
#    centre at Y8, X 18..82 (the pocket's corners are left to a smaller tool),
#    entering and leaving the face on quarter arcs of radius 6 tangent to it
#    (G03), from X12 Y14 and to X88 Y14.
#      programs/thin_wall.nc   the finishing program (O5004)
#      parts/thin_wall.stl     the part as designed (closed ASCII STL)
#      stock/thin_wall.stl     the roughed part it starts from
awk -v OUT="$here/programs/thin_wall.nc" -v PART="$here/parts/thin_wall.stl" \
    -v STOCK="$here/stock/thin_wall.stl" "$common"'
# One quad a-b-c-d (counter-clockwise seen from outside) as two facets.
function quad(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz) {
  facet(ax, ay, az, bx, by, bz, cx, cy, cz)
  facet(ax, ay, az, cx, cy, cz, dx, dy, dz)
}
# The block with its pocket, the pocket face nearest Y0 at y = face: the top
# and the bottom on the grid of the pocket outline (xs, ys), the outer sides
# split where that grid meets them, so that every edge is shared by exactly two
# facets (a closed solid, no T-junction).
function block(face, file, name,   i, j) {
  STL = file; facets = 0
  printf "solid %s\n", name > STL
  XS[0] = 0; XS[1] = 5; XS[2] = 95; XS[3] = 100
  YS[0] = 0; YS[1] = face; YS[2] = 55; YS[3] = 60
  for (i = 0; i < 3; i++) for (j = 0; j < 3; j++) {
    quad(XS[i], YS[j], -40, XS[i], YS[j + 1], -40, XS[i + 1], YS[j + 1], -40, XS[i + 1], YS[j], -40)  # bottom
    if (i == 1 && j == 1) continue                                                                    # the pocket
    quad(XS[i], YS[j], 0, XS[i + 1], YS[j], 0, XS[i + 1], YS[j + 1], 0, XS[i], YS[j + 1], 0)          # top
  }
  for (i = 0; i < 3; i++) {
    quad(XS[i], 0, -40, XS[i + 1], 0, -40, XS[i + 1], 0, 0, XS[i], 0, 0)      # Y0 side, outward -Y
    quad(XS[i + 1], 60, -40, XS[i], 60, -40, XS[i], 60, 0, XS[i + 1], 60, 0)  # Y60 side, outward +Y
    quad(0, YS[i + 1], -40, 0, YS[i], -40, 0, YS[i], 0, 0, YS[i + 1], 0)      # X0 side, outward -X
    quad(100, YS[i], -40, 100, YS[i + 1], -40, 100, YS[i + 1], 0, 100, YS[i], 0)  # X100 side, outward +X
  }
  # The pocket: its four walls facing into it, its floor facing up.
  quad(5, face, 0, 95, face, 0, 95, face, -35, 5, face, -35)   # the face of the thin wall, normal +Y
  quad(95, 55, 0, 5, 55, 0, 5, 55, -35, 95, 55, -35)           # normal -Y
  quad(5, 55, 0, 5, face, 0, 5, face, -35, 5, 55, -35)         # normal +X
  quad(95, face, 0, 95, 55, 0, 95, 55, -35, 95, face, -35)     # normal -X
  quad(5, face, -35, 95, face, -35, 95, 55, -35, 5, 55, -35)   # the floor
  printf "endsolid %s\n", name > STL
  close(STL)
}
BEGIN {
  nblk = 10
  printf "%%\n" > OUT
  printf "O5004 (DEFLEX SAMPLE - THIN WALL FINISH - 2 MM AL WALL 35 MM HIGH)\n" > OUT
  cmt("GENERATED BY SAMPLES/GENERATE.SH - DO NOT EDIT")
  cmt("PART SAMPLES/PARTS/THIN_WALL.STL - STOCK SAMPLES/STOCK/THIN_WALL.STL")
  cmt("BLOCK X0 TO X100, Y0 TO Y60, Z-40 TO Z0 - POCKET X5 TO X95, Y2 TO Y55, FLOOR Z-35")
  cmt("WALL Y0 TO Y2 - FACE Y2 FINISHED FROM Y2.1 - MATERIAL AL 7075-T6")
  cmt("TOOL T6 FLAT END MILL D12, 4 FLUTES, HELIX 45 DEG, STICKOUT 50")
  cmt("AE 0.1 AP 5 - S8000 FZ 0.03 - F960 - DOWN-MILLING ALONG +X - LEVELS Z-5 TO Z-35")
  blk("G21 G90 G17 G40 G49 G80")
  blk("T6 M06")
  blk("G00 G54 X12. Y14. S8000 M03")
  blk("G43 H6 Z50. M08")
  blk("Z5.")
  for (z = -5; z >= -35; z -= 5) {
    blk("G01 Z" f3(z) " F1000.")
    blk("G03 X18. Y8. I6. J0. F960.")
    blk("G01 X82.")
    blk("G03 X88. Y14. I0. J6.")
    blk("G00 Z5.")
    blk("X12.")
  }
  program_end()
  block(2, PART, "thin_wall_part")
  block(2.1, STOCK, "thin_wall_stock")
  printf "thin_wall.nc: %d blocks; part and stock %d facets each\n", blocks, facets
}'
cat > "$here/stock/thin_wall.yaml" <<'YAML'
# Stock of programs/thin_wall.nc (generated by samples/generate.sh): the block
# with its pocket roughed, 0.1 mm left on the thin wall's face (Y2.1), work
# frame G54. deflex --stock samples/stock/thin_wall.stl
stock: thin_wall.stl
YAML
