#!/bin/sh
# Engagement + force speed benchmark (issue 4 item 8): ball-end D10 finishing on
# the default Z-map. Usage: bench/engage.sh [BUILD_DIR]   (default: build)
set -eu
cd "$(dirname "$0")/.."
BUILD=${1:-build}
cmake --build "$BUILD" --target deflex_tests >/dev/null
exec "$BUILD/deflex_tests" -tc="bench*" --no-skip
