#!/bin/sh
# Benchmark: end-to-end compensation (read, the as-written
# simulation beside the mirror pass, write, read-back check; a program longer
# than a piece runs in pieces). 1) the six-surface sample (41,010 blocks, STL
# stock, D16 ball); 2) a generated raster finishing program of each size in
# $SIZES blocks (default $BLOCKS, else 100,000) on its semi-finished stock
# (STRESS=1 adds the $BLOCKS raster out of a box). Prints the medians
# (hyperfine), program CL points per second end to end (CL points / median
# wall time), engagement evaluations of the mirror pass per CL point, and peak
# memory; with 1M and 10M in SIZES, the ratio of their peaks; REPORT=1 adds a
# run of each size with --report.
set -eu
cd "$(dirname "$0")/.."
sh bench/build.sh
mkdir -p bench/out
echo "$(nproc) cores, $(uname -m)"
run() {  # name, program, stock, extra options
  name=$1; prog=$2; stock=$3; shift 3
  hyperfine --runs ${RUNS:-3} --export-json "bench/out/compensate_$name.json" -n "compensate $name" \
    "build/deflex compensate $prog --stock $stock $* -o bench/out/${name}_comp.nc"
  # One more run for its figures (stderr) and peak memory.
  /usr/bin/time -f "$name: peak memory %M KiB" build/deflex compensate "$prog" --stock "$stock" "$@" \
    -o "bench/out/${name}_comp.nc" 2>"bench/out/${name}_time.txt"
  pts=$(sed -n 's/.*predicted error, compensated:.* of \([0-9]*\) points.*/\1/p' "bench/out/${name}_time.txt")
  evs=$(sed -n 's/.*mirror: \([0-9]*\) engagement evaluations.*/\1/p' "bench/out/${name}_time.txt")
  med=$(sed -n 's/.*"median": \([0-9.]*\).*/\1/p' "bench/out/compensate_$name.json" | head -n 1)
  echo "$name: $pts CL points, median $med s: $(awk -v p="$pts" -v t="$med" 'BEGIN { printf "%.0f", p / t }') CL points/s end to end;" \
    "mirror pass $(awk -v e="$evs" -v p="$pts" 'BEGIN { printf "%.2f", e / p }') engagement evaluations per CL point"
  tail -n 1 "bench/out/${name}_time.txt"
}
run six_surfaces samples/programs/six_surfaces.nc samples/stock/six_surfaces_stock.stl
# With the part model (normals and the gouge check from the design
# surface): at most 25% slower than without it.
run six_surfaces_part samples/programs/six_surfaces.nc samples/stock/six_surfaces_stock.stl --part samples/parts/six_surfaces.stl
[ -n "${PART_ONLY:-}" ] && exit 0
# The raster at each size of SIZES (default: BLOCKS, else 100000;
# SIZES="100000 1000000 10000000" for the issue's table). 10,000,000 blocks
# are 10 spring passes over the 1,000,000-block raster's area and stock
# (gen_program.sh LAYERS), so peak memory compares program lengths on the
# same Z-map; without --report (the points are streamed, not kept).
for n in ${SIZES:-${BLOCKS:-100000}}; do
  layers=1; area=$n
  [ "$n" -gt 1000000 ] && { layers=$((n / 1000000)); area=1000000; }
  f=bench/data/finish_$n.nc
  [ -f "$f" ] || sh bench/gen_program.sh "$n" "$f" "$layers" >/dev/null
  # Finishing: the stock is the surface plus a 0.5 mm allowance (bench/gen_stock.sh),
  # judged at +-2 um (the first row takes the whole allowance with the full ball).
  st=bench/data/stock_${area}_0.5.stl
  [ -f "$st" ] || sh bench/gen_stock.sh "$area" "$st" 0.5 >/dev/null
  if [ "$n" -gt 1000000 ]; then
    # One run (minutes); peak memory and wall time from GNU time.
    /usr/bin/time -f "raster_$n: %e s wall, peak memory %M KiB" build/deflex compensate "$f" --stock "$st" \
      --tool T5 --tolerance 0.002 -o "bench/out/raster_${n}_comp.nc" 2>"bench/out/raster_${n}_time.txt"
    grep -E "predicted error, as written|raster_$n" "bench/out/raster_${n}_time.txt"
  else
    run "raster_$n" "$f" "$st" --tool T5 --tolerance 0.002
  fi
done
# The criterion: the 10M peak within 10% of the 1M one.
if [ -f bench/out/raster_1000000_time.txt ] && [ -f bench/out/raster_10000000_time.txt ]; then
  a=$(sed -n 's/.*peak memory \([0-9]*\) KiB.*/\1/p' bench/out/raster_1000000_time.txt)
  b=$(sed -n 's/.*peak memory \([0-9]*\) KiB.*/\1/p' bench/out/raster_10000000_time.txt)
  echo "peak memory 10M / 1M: $(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.3f", b / a }')"
fi
# REPORT=1: each size once more with --report (points.csv written as the
# points come, what report.html draws kept on disk): one run, GNU time.
if [ -n "${REPORT:-}" ]; then
  for n in ${SIZES:-${BLOCKS:-100000}}; do
    area=$n; [ "$n" -gt 1000000 ] && area=1000000
    /usr/bin/time -f "raster_$n --report: %e s wall, peak memory %M KiB" build/deflex compensate \
      "bench/data/finish_$n.nc" --stock "bench/data/stock_${area}_0.5.stl" --tool T5 --tolerance 0.002 \
      --report "bench/out/report_$n" -o "bench/out/raster_${n}_comp.nc" 2>"bench/out/report_${n}_time.txt"
    tail -n 1 "bench/out/report_${n}_time.txt"
    ls -l "bench/out/report_$n"
  done
fi
if [ -n "${STRESS:-}" ]; then
  # Stress: the same raster from a box 0.3 mm above the highest point; the first
  # row slots 2-4 mm deep and deflects 0.2-0.3 mm.
  n=${BLOCKS:-100000}; f=bench/data/finish_$n.nc
  rows=$(( (n - 10) / 501 ))
  half=$(awk -v r="$rows" 'BEGIN { print r * 0.125 + 10 }')  # the rows are centred on Y0
  run "raster_box_$n" "$f" "box:-10,-$half,-10,210,$half,1.3" --tool T5
fi
