#!/bin/sh
# Install deflex's build and test dependencies from Debian 12 packages.
# Idempotent: packages already present are skipped; apt-get runs only when
# something is missing. Must run as root (or with sudo available).
#   scripts/install-deps.sh          build + run dependencies (pybind11, Python's headers and NumPy:
#                                    the Python bindings in python/)
#   scripts/install-deps.sh --test   also what the test suite needs: LinuxCNC's rs274, Chromium and
#                                    libpng (report_browser), bash-completion (cli_completion),
#                                    pytest and matplotlib (python: python/tests, examples/),
#                                    CalculiX (stiffness_calculix)
#   scripts/install-deps.sh --bench  also hyperfine for bench/
#   scripts/install-deps.sh --fuzz   also clang 14 and its runtimes (ASan, UBSan, libFuzzer)
#   scripts/install-deps.sh --package  also what CPack's .deb needs (file, dpkg-shlibdeps)
set -eu
pkgs="build-essential cmake ninja-build pkg-config git ca-certificates
libeigen3-dev libboost-program-options-dev libyaml-cpp-dev nlohmann-json3-dev doctest-dev libtbb-dev
libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
libocct-data-exchange-dev libgmsh-dev libcgal-dev libssl-dev zlib1g-dev libjs-three libjs-dygraphs help2man libceres-dev
pybind11-dev python3-dev python3-numpy"
for a in "$@"; do
  case "$a" in
    --test)  pkgs="$pkgs linuxcnc-uspace chromium libpng-dev bash-completion python3-pytest python3-matplotlib calculix-ccx" ;;
    --bench) pkgs="$pkgs hyperfine time linuxcnc-uspace libbenchmark-dev" ;;
    --fuzz)  pkgs="$pkgs clang-14 libclang-rt-14-dev" ;;
    --package) pkgs="$pkgs file dpkg-dev" ;;
    *) echo "install-deps.sh: unknown option $a" >&2; exit 2 ;;
  esac
done
missing=""
for p in $pkgs; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
echo "install-deps.sh: installing$missing" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# shellcheck disable=SC2086
$SUDO apt-get install -y -qq --no-install-recommends $missing >/dev/null
