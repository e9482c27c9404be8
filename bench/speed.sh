#!/bin/sh
# The speed table (docs/benchmarks.md, "Speed, side by side"): this build
# against an earlier one, in one run on one machine, so that the two are
# measured under the same conditions.
#
#   sh bench/speed.sh                 this build against PREV (default: the
#                                     revision in bench/prev-revision)
#   PREV=<git revision>               built once into bench/out/prev-<rev>/
#   PREV_BIN=/path/to/deflex          an earlier binary instead (of PREV, whose
#                                     machine profile it reads)
#   RUNS=3                            runs per median (hyperfine)
#   BLOCKS=1000000                    the raster's size (bench/gen_program.sh)
#   QUICK=1                           the six-surface sample and path only
#
# Rows: `compensate` and `simulate` of the generated raster on its
# semi-finished stock (as bench/compensate.sh), `compensate` of the six-surface
# sample, `compensate` of the raster on 1 and on 2 threads (this build), and
# `path` against LinuxCNC's rs274 on the raster program. Each: the median wall
# time, CL points per second (the points of the program / the median), Z-map
# cells updated per second (this build's `-v`; an older one may not print
# them) and the peak memory (GNU time, one more run). The table goes to
# bench/out/speed.md and standard output.
set -eu
cd "$(dirname "$0")/.."
sh bench/build.sh
mkdir -p bench/out
runs=${RUNS:-3}
n=${BLOCKS:-1000000}

# The earlier build.
if [ -n "${PREV_BIN:-}" ]; then
  prev=$PREV_BIN
else
  rev=$(git rev-parse --short "${PREV:-$(cat bench/prev-revision)}")
  prev=bench/out/prev-$rev/deflex
  if [ ! -x "$prev" ]; then
    src=bench/out/prev-$rev/src
    rm -rf "$src"
    mkdir -p "$src"
    git archive "$rev" | tar -x -C "$src"
    sh bench/build.sh "$src" "bench/out/prev-$rev/build"
    cp "bench/out/prev-$rev/build/deflex" "$prev"
  fi
fi
new=build/deflex
# The earlier build reads the machine profile of its own revision: a key added
# since (a newer section) would be an unknown key to it.
prev_rev=$(git rev-parse --short "${PREV:-$(cat bench/prev-revision)}")
git show "$prev_rev:samples/machines/mill3.yaml" > bench/out/prev-mill3.yaml
old_machine="--machine bench/out/prev-mill3.yaml"
# Its material and tool libraries too (a work material's elastic: is newer).
git show "$prev_rev:samples/materials.yaml" > bench/out/prev-materials.yaml
git show "$prev_rev:samples/tools.yaml" > bench/out/prev-tools.yaml
old_libs="--material-file bench/out/prev-materials.yaml --tool-file bench/out/prev-tools.yaml"
echo "machine: $(nproc) cores, $(uname -m), $(sed -n 's/^model name[^:]*: //p' /proc/cpuinfo | head -n 1)"
echo "this build: $($new --version 2>&1 | head -n 1); earlier: $($prev --version 2>&1 | head -n 1)"

f=bench/data/finish_$n.nc
st=bench/data/stock_${n}_0.5.stl
[ -f "$f" ] || sh bench/gen_program.sh "$n" "$f" >/dev/null
[ -f "$st" ] || sh bench/gen_stock.sh "$n" "$st" 0.5 >/dev/null
raster="$f --stock $st --tool T5 --tolerance 0.002"
six="samples/programs/six_surfaces.nc --stock samples/stock/six_surfaces_stock.stl"

table=bench/out/speed.md
{
  echo "| run | build | median wall | CL points/s | Z-map cells updated/s | peak memory |"
  echo "|---|---|---|---|---|---|"
} > "$table"

# row NAME BUILD-LABEL BINARY COMMAND...: median of $runs, then one run under
# GNU time with -v for the figures and the peak memory.
row() {
  name=$1; label=$2; bin=$3; shift 3
  json=bench/out/speed_$$.json
  hyperfine --runs "$runs" --export-json "$json" -n "$name" "$bin $* > /dev/null 2>&1" > /dev/null
  med=$(sed -n 's/.*"median": \([0-9.]*\).*/\1/p' "$json" | head -n 1)
  rm -f "$json"
  log=bench/out/speed_$$.log
  /usr/bin/time -f "peak %M KiB" "$bin" "$@" -v > "$log.out" 2> "$log" || true
  # compensate: "... of N points outside" (stderr); simulate: "N CL points: ..." (stdout)
  pts=$(cat "$log" "$log.out" |
    sed -n 's/.*predicted error[^:]*:.* of \([0-9]*\) points.*/\1/p; s/.*: \([0-9]*\) CL points: .*/\1/p' | head -n 1)
  # The cells of the main stage (an earlier one may sweep a little).
  cells=$(sed -n 's/.*\(compensating\|simulating\) done in .*Z-map: \([0-9.e+]*\) cells updated.*/\2/p' "$log" | head -n 1)
  rm -f "$log.out"
  peak=$(sed -n 's/^peak \([0-9]*\) KiB/\1/p' "$log")
  rm -f "$log"
  rate=$(awk -v p="${pts:-0}" -v t="$med" 'BEGIN { if (p > 0) printf "%.0f", p / t; else printf "-" }')
  crate=$(awk -v c="${cells:-0}" -v t="$med" 'BEGIN { if (c > 0) printf "%.3g", c / t; else printf "-" }')
  mem=$(awk -v k="${peak:-0}" 'BEGIN { printf "%.0f MB", k / 1024 }')
  line="| $name | $label | $(awk -v t="$med" 'BEGIN { printf "%.2f s", t }') | $rate | $crate | $mem |"
  echo "$line" | tee -a "$table"
}

row "simulate six-surface sample" earlier "$prev" simulate $six $old_machine $old_libs
row "simulate six-surface sample" this "$new" simulate $six
row "compensate six-surface sample" earlier "$prev" compensate $six $old_machine $old_libs -o bench/out/speed_out.nc
row "compensate six-surface sample" this "$new" compensate $six -o bench/out/speed_out.nc
if [ -z "${QUICK:-}" ]; then
  row "compensate raster $n" earlier "$prev" compensate $raster $old_machine $old_libs -o bench/out/speed_out.nc
  row "compensate raster $n" this "$new" compensate $raster -o bench/out/speed_out.nc
  row "simulate raster $n" earlier "$prev" simulate $raster $old_machine $old_libs
  row "simulate raster $n" this "$new" simulate $raster
  row "compensate raster $n, --threads 1" this "$new" compensate $raster --threads 1 -o bench/out/speed_out.nc
  row "compensate raster $n, --threads 2" this "$new" compensate $raster --threads 2 -o bench/out/speed_out.nc
fi
# path against rs274: the medians only.
hyperfine --runs "$runs" --export-json bench/out/speed_path.json \
  -n "deflex path (this)" "$new path --dialect linuxcnc $f > /dev/null" \
  -n "deflex path (earlier)" "$prev path --dialect linuxcnc $old_machine $f > /dev/null" \
  -n "rs274 (LinuxCNC)" "rs274 -g -t bench/rs274.tbl $f bench/out/rs274.txt < /dev/null > /dev/null 2>&1" > /dev/null
sed -n 's/.*"command": "\(.*\)",/\1/p; s/.*"median": \([0-9.]*\).*/\1/p' bench/out/speed_path.json | paste - - |
  awk -F'\t' '{ printf "| %s | | %.2f s | | | |\n", $1, $2 }' | tee -a "$table"
echo "table: $table"
