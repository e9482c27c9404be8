#!/bin/sh
# The main job on the bundled sample: install what is missing, build, then
# check the sample program against the sample machine and print its tool path.
set -eu
cd "$(dirname "$0")/.."
sh scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2
echo "== deflex check samples/programs/pocket_finish.nc --machine mill3"
build/deflex check samples/programs/pocket_finish.nc --machine mill3
echo "== deflex path samples/programs/pocket_finish.nc --lines"
build/deflex path samples/programs/pocket_finish.nc --lines
