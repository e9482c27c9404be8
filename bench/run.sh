#!/bin/sh
# Issue 2 benchmark: a generated 1,000,000-block finishing program (~25 MB, not
# committed) through `deflex path`, `deflex rewrite` (read + interpret + write)
# and LinuxCNC's standalone rs274 on the same file; medians by hyperfine, peak
# memory by GNU time. Run from anywhere; results in bench/out/.
set -eu
cd "$(dirname "$0")/.."
sh scripts/install-deps.sh --bench
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target deflex
n=${BLOCKS:-1000000}
f=bench/data/finish_$n.nc
[ -f "$f" ] || sh bench/gen_program.sh "$n" "$f" >/dev/null
mkdir -p bench/out
echo "input: $f, $(wc -l < "$f") lines, $(wc -c < "$f") bytes; $(nproc) cores, $(uname -m)"
hyperfine --warmup 1 --runs ${RUNS:-5} --export-json bench/out/read_write.json \
  -n "deflex path" "build/deflex path --dialect linuxcnc $f > /dev/null" \
  -n "deflex rewrite (round trip)" "build/deflex rewrite $f -o bench/out/roundtrip.nc" \
  -n "rs274 (LinuxCNC)" "rs274 -g -t bench/rs274.tbl $f bench/out/rs274.txt < /dev/null > /dev/null 2>&1"
cmp "$f" bench/out/roundtrip.nc && echo "round trip: byte-identical"
for cmd in "path --dialect linuxcnc $f" "rewrite $f -o bench/out/roundtrip.nc"; do
  /usr/bin/time -f "peak memory of deflex ${cmd%% *}: %M KiB (input $(( $(wc -c < "$f") / 1024 )) KiB)" \
    build/deflex $cmd > /dev/null
done
