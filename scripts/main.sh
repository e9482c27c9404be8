#!/bin/sh
# The main job on the bundled sample: install what is missing, build, then
# compensate the six-surface part of Smaoui et al. 2011 (ball D16, 80 mm
# stick-out, C35) on its semi-finished stock for the sample machine, with its
# part model (the design surface: normals and the gouge check), show that only
# coordinates changed, and judge the result by simulating it against the
# original. Defaults (machine mill3, tool and material libraries, material C35,
# tolerance) come from config.yaml. Results go to out/.
set -eu
cd "$(dirname "$0")/.."
sh scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2
prog=samples/programs/six_surfaces.nc
stock=samples/stock/six_surfaces_stock.stl
part=samples/parts/six_surfaces.stl
mkdir -p out
echo "== deflex check $prog --part $part"
build/deflex check $prog --part $part
echo "== deflex compensate $prog --stock $stock --part $part -o out/six_surfaces_comp.nc --report out/report"
build/deflex compensate $prog --stock $stock --part $part -o out/six_surfaces_comp.nc --report out/report
echo "== deflex diff $prog out/six_surfaces_comp.nc (summary)"
build/deflex diff $prog out/six_surfaces_comp.nc | tail -n 1
echo "== deflex simulate out/six_surfaces_comp.nc --reference $prog --part $part"
build/deflex simulate out/six_surfaces_comp.nc --reference $prog --stock $stock --part $part
echo "== out/report/summary.json"
cat out/report/summary.json
echo "== the report: open it in a browser (works offline)"
echo "$(pwd)/out/report/report.html"
