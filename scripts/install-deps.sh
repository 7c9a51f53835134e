#!/usr/bin/env bash
# Installs softcut's build and test dependencies from Debian 12 packages.
# Used by the README's first command and by .ci/run. Safe to run twice.
set -euo pipefail
pkgs=(
  build-essential cmake ninja-build pkg-config ccache
  libeigen3-dev libsuitesparse-dev liblua5.4-dev lua5.4
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  libstb-dev doctest-dev zlib1g-dev
  nlohmann-json3-dev  # JSON strings escaped by a well-kept library: summary.json is valid for every byte
  libopenblas0-pthread  # optimised BLAS/LAPACK behind CHOLMOD's supernodal factor (reference BLAS is ~10x slower)
  libxml2-utils  # xmllint: the tests validate softcut check --junit against tests/data/junit.xsd
  clang-14 libclang-rt-14-dev llvm-14  # the test suite's sanitizer + libFuzzer build (scripts/test.sh), symbolized traces
)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#pkgs[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
