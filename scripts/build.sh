#!/usr/bin/env bash
# Configures and builds softcut into build/ (Release): the softcut program
# only, which is what the README's first command needs; with --all also the
# test suites (scripts/test.sh --quick). Other arguments go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
target=(--target softcut)
args=()
for a in "$@"; do
  if [ "$a" = --all ]; then target=(); else args+=("$a"); fi
done
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${args[@]}" >/dev/null
cmake --build build --parallel "$(nproc)" "${target[@]}"
