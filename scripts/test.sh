#!/bin/sh
# Install what is missing (including LinuxCNC's rs274, the independent
# interpreter the tests compare against), build, and run every test.
#   scripts/test.sh             Release build in build/ (what CI runs)
#   scripts/test.sh --sanitize  the same suite under AddressSanitizer + UBSan, any
#                               report fatal, in build-sanitize/ with clang 14;
#                               that build also holds the fuzz targets (scripts/fuzz.sh),
#                               each of which the suite runs for 10 s,
#                               so the machine compiles the instrumented tree once
set -eu
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--sanitize" ]; then
  sh scripts/install-deps.sh --test --fuzz
  CXX=clang++-14 cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=Release -DDEFLEX_FUZZ=ON >/dev/null
  cmake --build build-sanitize -j2
  # Leaks inside third-party libraries we cannot fix are listed, with the
  # reason, in scripts/lsan.supp; our own code has no entry there.
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:check_initialization_order=1"
  export LSAN_OPTIONS="suppressions=$(pwd)/scripts/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$(pwd)/scripts/ubsan.supp"
  cd build-sanitize && ctest --output-on-failure -j2
  exit
fi
[ $# -eq 0 ] || { echo "test.sh: unknown option $1 (--sanitize)" >&2; exit 2; }
sh scripts/install-deps.sh --test
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2
cd build && ctest --output-on-failure -j2
