#!/bin/sh
# Benchmark: the report of a 1,000,000-block program. 1) how long
# `simulate --report` takes beyond `simulate` (points.csv, cusp heights,
# summary.json, report.html); 2) how long headless Chromium takes to load
# report.html and run its scripts (3D views, top views, plots) beyond loading
# an empty page. Medians of $RUNS (default 3) by hyperfine; BLOCKS sets the size.
set -eu
cd "$(dirname "$0")/.."
sh bench/build.sh
command -v chromium >/dev/null || sh scripts/install-deps.sh --test
mkdir -p bench/out
echo "$(nproc) cores, $(uname -m)"
n=${BLOCKS:-1000000}
f=bench/data/finish_$n.nc
[ -f "$f" ] || sh bench/gen_program.sh "$n" "$f" >/dev/null
st=bench/data/stock_${n}_0.5.stl
[ -f "$st" ] || sh bench/gen_stock.sh "$n" "$st" 0.5 >/dev/null
sim="build/deflex simulate $f --stock $st --tool T5 --tolerance 0.002"
hyperfine --runs "${RUNS:-3}" --export-json bench/out/report_write.json \
  -n "simulate" "$sim" -n "simulate --report" "rm -rf bench/out/report_$n && $sim --report bench/out/report_$n"
page=$(pwd)/bench/out/report_$n/report.html
ls -l "$page" "bench/out/report_$n/points.csv"
browser="chromium --headless --no-sandbox --enable-unsafe-swiftshader --use-angle=swiftshader --window-size=1400,4000 --user-data-dir=bench/out/chromium --dump-dom"
echo '<!DOCTYPE html><html><body></body></html>' > bench/out/empty.html
hyperfine --runs "${RUNS:-3}" --warmup 1 --export-json bench/out/report_open.json \
  -n "empty page" "$browser file://$(pwd)/bench/out/empty.html > /dev/null 2>&1" \
  -n "report.html" "$browser file://$page > bench/out/report_dom.html 2>/dev/null"
grep -q 'data-ready="yes"' bench/out/report_dom.html && echo "report.html: scripts ran to the end, no error"
