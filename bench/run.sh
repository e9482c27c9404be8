#!/bin/sh
# Benchmark: a generated 1,000,000-block finishing program (~25 MB, not
# committed) through `deflex path`, `deflex check`, `deflex rewrite` (read + interpret + write)
# and LinuxCNC's standalone rs274 on the same file; medians by hyperfine, peak
# memory by GNU time. Run from anywhere; results in bench/out/.
set -eu
cd "$(dirname "$0")/.."
sh bench/build.sh
mkdir -p bench/out
# SIZES="1000000 10000000" reads both (10M: 10 passes over the 1M area).
for n in ${SIZES:-${BLOCKS:-1000000}}; do
  f=bench/data/finish_$n.nc
  layers=1; [ "$n" -gt 1000000 ] && layers=$((n / 1000000))
  [ -f "$f" ] || sh bench/gen_program.sh "$n" "$f" "$layers" >/dev/null
  echo "input: $f, $(wc -l < "$f") lines, $(wc -c < "$f") bytes; $(nproc) cores, $(uname -m)"
  hyperfine --warmup 1 --runs ${RUNS:-5} --export-json "bench/out/read_write_$n.json" \
    -n "deflex path" "build/deflex path --dialect linuxcnc $f > /dev/null" \
    -n "deflex check" "build/deflex check $f > /dev/null 2>&1" \
    -n "deflex rewrite (round trip)" "build/deflex rewrite $f -o bench/out/roundtrip.nc" \
    -n "rs274 (LinuxCNC)" "rs274 -g -t bench/rs274.tbl $f bench/out/rs274.txt < /dev/null > /dev/null 2>&1"
  cmp "$f" bench/out/roundtrip.nc && echo "round trip: byte-identical"
  for cmd in "path --dialect linuxcnc $f" "check $f" "rewrite $f -o bench/out/roundtrip.nc"; do
    /usr/bin/time -f "peak memory of deflex ${cmd%% *}: %M KiB (input $(( $(wc -c < "$f") / 1024 )) KiB)" \
      build/deflex $cmd > /dev/null 2>bench/out/read_time.txt || true
    tail -n 1 bench/out/read_time.txt
  done
done
