#!/usr/bin/env bash
# Hashes what every shipped scenario writes (displacement logs, VTU files,
# PNG frames, contact sheet), for checking that a refactor changes no output:
#   scripts/golden.sh build/softcut > before.txt   # on the old code
#   scripts/golden.sh build/softcut > after.txt    # on the new code
#   diff before.txt after.txt                      # must be empty
# summary.json is left out (it holds timings); everything else must match
# byte for byte. Uses a private cache folder, so cache hits cannot hide changes.
set -euo pipefail
bin=$(realpath "${1:?usage: scripts/golden.sh PATH/TO/softcut}")
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export SOFTCUT_CACHE_DIR="$work/cache"
# One thread: OpenBLAS's threaded kernels (inside CHOLMOD) round differently
# with another thread count, and the default count follows the load average.
export SOFTCUT_THREADS=1
# Each scenario as shipped (frames included), then on the CG and whole-mesh backends.
for s in scenarios/*.lua; do
  for variant in default cpu monolithic; do
    name=$(basename "$s" .lua).$variant
    args=(); [[ $variant == default ]] || args=(--backend "$variant" --no-render)
    "$bin" run "$s" --quiet --out "$work/$name" "${args[@]}" >/dev/null 2>"$work/$name.err" ||
      { echo "$name failed:" >&2; cat "$work/$name.err" >&2; exit 1; }
    (cd "$work/$name" && find . -type f ! -name summary.json -print0 | sort -z | xargs -0 sha256sum |
      sed "s#  \./#  $name/#")
  done
done
