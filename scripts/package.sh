#!/bin/sh
# Builds the Debian package of deflex (CPack, the rules of CMakeLists.txt):
# build/deflex_VERSION_ARCH.deb. It installs deflex in /usr/bin, its data in
# /usr/share/deflex, the man pages, the bash completion and the Python package
# (/usr/lib/python3/dist-packages/deflex); its Depends are the Debian libraries
# the binary links, its Recommends what the Python package needs.
# scripts/test-package.sh installs it on a fresh Debian 12 and runs the sample job.
set -eu
cd "$(dirname "$0")/.."
sh scripts/install-deps.sh --package
# Installed under /usr (the data folder compiled in as the fallback where
# /proc is missing; only profile/search.cpp depends on it).
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=/usr >/dev/null
cmake --build build -j2 --target deflex deflex_man _deflex
rm -f build/deflex_*.deb
(cd build && cpack -G DEB >/dev/null)
ls build/deflex_*.deb
