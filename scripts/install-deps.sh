#!/usr/bin/env bash
# Installs softcut's build and test dependencies from Debian 12 packages.
# Used by the README's first command and, with --test, by scripts/test.sh
# (.ci/run). Safe to run twice.
#   --video also ffmpeg, which `softcut run --video` and `softcut render --video`
#           pipe their frames to (H.264); not needed otherwise
#   --test  also what only the test suite needs: a one-node Slurm cluster for
#           the sweep test (installed with its services kept from starting),
#           meshio (an independent VTU reader the VTU writer's tests read back with),
#           ffmpeg (the video tests encode and probe with it)
set -euo pipefail
test_pkgs=()
case "${1:-}" in
  --test) test_pkgs=(slurmctld slurmd slurm-client  # pulls in munge; tests/app/sweep_slurm.sh
                    calculix-ccx  # CalculiX: the independent truth of tests/fidelity (large deformation)
                    python3-meshio  # tests/data/read_vtu_meshio.py: the VTU files read back by another reader
                    ffmpeg) ;;  # video.mp4 encoded, and read back by ffprobe in the tests
  --video) test_pkgs=(ffmpeg) ;;  # softcut run --video: H.264 through the ffmpeg program
  "") ;;
  *) echo "install-deps: unknown option $1 (--video, --test or nothing)" >&2; exit 2 ;;
esac
pkgs=(
  build-essential cmake ninja-build pkg-config ccache
  libeigen3-dev libsuitesparse-dev liblua5.4-dev lua5.4
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  libstb-dev doctest-dev zlib1g-dev
  libpng-dev  # 16-bit depth and 8-bit label images (stb_image_write writes 8-bit colour only)
  libcgal-dev  # CGAL Mesh_3: smooth, graded, labelled organ meshes (engine/mesh/mesher, docs/meshing.md)
  libpugixml-dev  # pugixml: VTU files read as XML (entities, CDATA, comments), not by a hand-written tag scanner
  libcli11-dev  # CLI11: the commands' options declared once, parsed and shown in --help from one declaration
  nlohmann-json3-dev  # JSON strings escaped by a well-kept library: summary.json is valid for every byte
  libopenblas0-pthread  # optimised BLAS/LAPACK behind CHOLMOD's supernodal factor (reference BLAS is ~10x slower)
  libxml2-utils  # xmllint: the tests validate softcut check --junit against tests/data/junit.xsd
  clang-14 libclang-rt-14-dev llvm-14  # the test suite's sanitizer + libFuzzer build (scripts/test.sh), symbolized traces
)
pkgs+=("${test_pkgs[@]}")
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
# The Slurm and munge daemons must not start as system services: the sweep
# test starts its own, under a temporary folder. policy-rc.d (101: "action
# forbidden") keeps the packages' scripts from starting them, when none is set.
policy=""
if [ ${#test_pkgs[@]} -gt 0 ] && [ ! -e /usr/sbin/policy-rc.d ]; then
  policy=/usr/sbin/policy-rc.d
  printf '#!/bin/sh\nexit 101\n' | $SUDO tee "$policy" >/dev/null
  $SUDO chmod +x "$policy"
  trap '$SUDO rm -f "$policy"' EXIT
fi
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
