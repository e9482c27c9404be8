#!/bin/sh
# Engagement + force speed benchmark: ball-end D10 finishing on
# the default Z-map (long passes, CAM-like short moves, 0.1 mm cells), and the
# short moves with a bull nose D10 r1. On a shared machine run it twice: the
# figures vary by 2x with the load. Usage: bench/engage.sh [BUILD_DIR]   (default: build)
set -eu
cd "$(dirname "$0")/.."
BUILD=${1:-build}
cmake --build "$BUILD" --target deflex_tests >/dev/null
exec "$BUILD/deflex_tests" -tc="bench*" --no-skip
