#!/bin/sh
# build.sh [SOURCE [BUILD]]: what every benchmark needs first, in one place:
# the benchmark tools (hyperfine, GNU time, LinuxCNC's rs274, Google
# Benchmark) and a Release build of `deflex` from SOURCE (default: this
# repository) in BUILD (default: SOURCE/build). Run from the repository root.
set -eu
src=${1:-.}
build=${2:-$src/build}
sh scripts/install-deps.sh --bench
cmake -S "$src" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target deflex
