#!/bin/sh
# The package on a machine with no build tools: run as root on a fresh Debian 12
# (../shared/tools/fresh-debian.sh . 'sh scripts/test-package.sh'). Builds the
# .deb, removes every build dependency again, installs the .deb with apt (which
# brings what it declares and nothing else), and as a user would, from /tmp:
# the sample job, the man page, the completion.
set -eu
cd "$(dirname "$0")/.."
sh scripts/package.sh
deb=$(ls "$(pwd)"/build/deflex_*.deb)
export DEBIAN_FRONTEND=noninteractive
# Back to a machine without compilers, headers or libraries: apt must bring them.
apt-get purge -y -qq build-essential cmake ninja-build pkg-config 'lib*-dev' help2man >/dev/null 2>&1
apt-get autoremove --purge -y -qq >/dev/null
apt-get install -y -qq "$deb" man-db bash-completion >/dev/null
dpkg -s deflex | sed -n 's/^Depends: /deflex Depends: /p'
cd /tmp
echo "== deflex --version (from /tmp)"
deflex --version
echo "== deflex compensate the installed sample"
deflex compensate /usr/share/deflex/samples/programs/six_surfaces.nc \
  --stock /usr/share/deflex/samples/stock/six_surfaces_stock.stl -o /tmp/six_surfaces_comp.nc
test -s /tmp/six_surfaces_comp.nc
echo "== the workpiece's compliance (gmsh and the CHOLMOD plugin as installed)"
deflex stiffness --part /usr/share/deflex/samples/parts/thin_wall.stl --fixture box:-1,-1,-41,101,61,-39.9 \
  --at 50,2,0 --material Al7075-T6 --mesh-mm 4 | grep 'principal' -A1
echo "== import deflex (Debian's python3 finds /usr/lib/python3/dist-packages)"
/usr/bin/python3 -c "import deflex; print(deflex.data_dir()); print(deflex.compliance('T5', machine='mill3', heights_mm=[0]).matrix_mm_per_N[0, 0, 0], 'mm/N')"
echo "== man deflex-compensate"
man -w deflex-compensate
man deflex-compensate | head -n 6
echo "== completion of 'deflex compensate x.nc --machine ' (loaded as bash loads it, on first use)"
# In an empty folder: a path is a machine too, so files and folders would be offered.
cd "$(mktemp -d)"
got=$(bash -c '. /usr/share/bash-completion/bash_completion; _completion_loader deflex
COMP_WORDS=(deflex compensate x.nc --machine ""); COMP_CWORD=4; _deflex; echo "${COMPREPLY[@]}"')
echo "$got"
[ "$got" = mill3 ]
echo "package test: passed"
