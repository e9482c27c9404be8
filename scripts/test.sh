#!/bin/sh
# Install what is missing (including LinuxCNC's rs274, the independent
# interpreter the tests compare against), build, and run every test.
set -eu
cd "$(dirname "$0")/.."
sh scripts/install-deps.sh --test
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2
cd build && ctest --output-on-failure -j2
