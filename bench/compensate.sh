#!/bin/sh
# Issue 5 benchmark: end-to-end compensation (read, simulate, mirror iterations,
# write, read-back check). 1) the six-surface sample (41,010 blocks, STL stock);
# 2) a generated raster finishing program of $BLOCKS blocks (default 100,000) on
# a box stock. Prints the medians (hyperfine), CL points evaluated per second
# (CL points x simulations / time) and peak memory.
set -eu
cd "$(dirname "$0")/.."
sh scripts/install-deps.sh --bench
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target deflex
mkdir -p bench/out
echo "$(nproc) cores, $(uname -m)"
run() {  # name, program, stock, extra options
  name=$1; prog=$2; stock=$3; shift 3
  hyperfine --runs ${RUNS:-3} --export-json "bench/out/compensate_$name.json" -n "compensate $name" \
    "build/deflex compensate $prog --stock $stock $* -o bench/out/${name}_comp.nc --report bench/out/report_$name"
  pts=$(sed -n 's/.*"cl_points": \([0-9]*\).*/\1/p' "bench/out/report_$name/summary.json")
  its=$(sed -n 's/.*"iterations": \([0-9]*\).*/\1/p' "bench/out/report_$name/summary.json")
  med=$(sed -n 's/.*"median": \([0-9.]*\).*/\1/p' "bench/out/compensate_$name.json" | head -n 1)
  echo "$name: $pts CL points, $its iterations (+1 nominal simulation), median $med s:" \
    "$(awk -v p="$pts" -v i="$its" -v t="$med" 'BEGIN { printf "%.0f CL points evaluated/s", p * (i + 1) / t }')"
  /usr/bin/time -f "$name: peak memory %M KiB" build/deflex compensate "$prog" --stock "$stock" "$@" -o /dev/null 2>&1 | tail -n 1
}
run six_surfaces samples/programs/six_surfaces.nc samples/stock/six_surfaces_stock.stl
n=${BLOCKS:-100000}
f=bench/data/finish_$n.nc
[ -f "$f" ] || sh bench/gen_program.sh "$n" "$f" >/dev/null
# The generated raster spans X 0..200, Y 0..0.25*rows, Z -3..1: a box with 0.3 mm above the highest point.
rows=$(( (n - 10) / 501 ))
run "raster_$n" "$f" "box:-10,-10,-10,210,$(awk -v r="$rows" 'BEGIN { print r * 0.25 + 10 }'),1.3" --tool T5
