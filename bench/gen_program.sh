#!/bin/sh
# gen_program.sh N OUT [LAYERS]: writes a Fanuc-style ball-end raster finishing
# program of about N blocks over a wavy surface (numbers with decimal points, N
# on every block, modal X/Y/Z words as CAM systems write them). LAYERS > 1 (for
# 10,000,000 blocks: 10) runs the raster of N / LAYERS blocks that many times
# over the same area, each pass 0.05 mm above the next and the last on the
# surface (spring passes): a longer program on the same stock and Z-map, so
# that memory can be compared between program lengths. Needs only awk.
set -eu
n=${1:-1000000}; out=${2:-bench/data/finish_${n}.nc}; layers=${3:-1}
mkdir -p "$(dirname "$out")"
awk -v n="$n" -v layers="$layers" 'BEGIN {
  print "%"; print "O2000 (GENERATED RASTER FINISH)"
  print "N1 G00 G17 G21 G40 G49 G80 G90"; print "N2 T5 M06"; printf "N3 G54 G00 X0. Y%.3f S8000 M03\n", -0.125 * int(int((n / layers - 10) / 501) - 1)
  print "N4 G43 H5 Z25. M08"; print "N5 G01 Z-1. F2500."
  ln = 6; per = 500; rows = int((n / layers - 10) / (per + 1)); dx = 200.0 / per
  # The rows are centred on Y0 so that 1,000,000 blocks (rows 0.25 mm apart,
  # 499 mm) stay inside the Y travel of the sample machine of +-250 mm.
  y0 = -0.125 * int(rows - 1)
  for (l = 0; l < layers; l++) {
    up = 0.05 * (layers - 1 - l)
    if (l) { printf "N%d G00 Z25.\n", ln++; printf "N%d X0. Y%.3f\n", ln++, y0; printf "N%d G01 Z-1. F2500.\n", ln++ }
    for (r = 0; r < rows; r++) {
      y = y0 + r * 0.25
      printf "N%d Y%.3f\n", ln++, y
      for (i = 1; i <= per; i++) {
        x = (r % 2 == 0) ? i * dx : 200.0 - i * dx
        z = -1.0 - 2.0 * sin(x / 15.0) * cos(y / 20.0) + up
        printf "N%d X%.3f Z%.4f\n", ln++, x, z
      }
    }
  }
  printf "N%d G00 Z25.\n", ln++; printf "N%d M05 M09\n", ln++; printf "N%d M30\n", ln++; print "%"
}' > "$out"
echo "$out"
