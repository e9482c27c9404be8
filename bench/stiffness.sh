#!/bin/sh
# Benchmark: C(h) of every sample tool on the sample machine, by the
# beam model (target < 10 ms for the table) and the solid model at the default
# mesh (target < 60 s; a second run comes from the cache). Whole-process times
# by hyperfine: they bound the model's own time from above.
set -eu
cd "$(dirname "$0")/.."
sh bench/build.sh
mkdir -p bench/out
cache=$(mktemp -d)
echo "$(nproc) cores, $(uname -m)"
# The beam table in-process (process start-up alone, ~0.05 s, is far more than the table):
cmake --build build --target deflex_bench >/dev/null
build/deflex_bench --benchmark_filter=beam --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
hyperfine --warmup 2 --runs 20 --export-json bench/out/stiffness_beam.json \
  "build/deflex stiffness --tool-file samples/tools.yaml --tool T5 --machine mill3 --method beam --format json"
for t in T1 T2 T3 T4 T5; do
  hyperfine --runs 1 --export-json bench/out/stiffness_solid_$t.json \
    --prepare "rm -rf $cache/*" \
    -n "solid $t (no cache)" "DEFLEX_CACHE_DIR=$cache build/deflex stiffness --tool-file samples/tools.yaml --tool $t --machine mill3 --method solid --format json"
done
hyperfine --warmup 1 --runs 5 -n "solid T5 (cached)" \
  "DEFLEX_CACHE_DIR=$cache build/deflex stiffness --tool-file samples/tools.yaml --tool T5 --machine mill3 --method solid --format json"
rm -rf "$cache"
