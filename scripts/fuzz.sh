#!/bin/sh
# Fuzz every reader of hostile input with libFuzzer for SECONDS in total, split
# evenly across the targets (default 300):
#   sh scripts/fuzz.sh 300
# Installs clang if missing, builds the targets in build-sanitize/ (clang,
# ASan + UBSan, the tree scripts/test.sh --sanitize also uses), runs each on its
# growing corpus build-sanitize/fuzz-corpus/<target>/ seeded from fuzz/seeds/<target>/,
# and prints executions and corpus size per target. A crash leaves its input in
# build-sanitize/fuzz-crashes/ and makes the script exit 1; turn it into a case in
# tests/bad/ (or a unit test) and fix it.
set -eu
cd "$(dirname "$0")/.."
secs=${1:-300}
targets="gcode machine tools tool_import material stl zmap points_csv probe_log dprnt ply frf"
sh scripts/install-deps.sh --fuzz
CXX=clang++-14 cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=Release -DDEFLEX_FUZZ=ON >/dev/null
# shellcheck disable=SC2046
cmake --build build-sanitize -j2 $(for t in $targets; do printf ' --target fuzz_%s' "$t"; done)
n=$(echo $targets | wc -w)
per=$((secs / n)); [ "$per" -ge 1 ] || per=1
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export LSAN_OPTIONS="suppressions=$(pwd)/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$(pwd)/scripts/ubsan.supp"
out=build-sanitize/fuzz-out; mkdir -p "$out" build-sanitize/fuzz-crashes
status=0
for t in $targets; do
  corpus=build-sanitize/fuzz-corpus/$t
  mkdir -p "$corpus"
  # -timeout: one input running 10 s is a hang, a finding like a crash.
  if ! "build-sanitize/fuzz/fuzz_$t" -max_total_time="$per" -timeout=10 -rss_limit_mb=4096 \
       -print_final_stats=1 -artifact_prefix="build-sanitize/fuzz-crashes/$t-" \
       "$corpus" "fuzz/seeds/$t" >"$out/$t.log" 2>&1; then
    status=1
  fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/$t.log" | tail -1)
  found=$(ls build-sanitize/fuzz-crashes | grep -c "^$t-" || true)
  printf '%-9s %10s executions in %ss, corpus %5s inputs, %s crash/hang/leak files\n' \
    "$t" "${execs:-?}" "$per" "$(ls "$corpus" | wc -l)" "$found"
done
[ "$status" -eq 0 ] || echo "fuzz.sh: a target stopped on a finding: see $out/*.log and build-sanitize/fuzz-crashes/" >&2
exit "$status"
