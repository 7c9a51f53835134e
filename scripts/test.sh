#!/usr/bin/env bash
# Builds softcut and runs the whole test suite (unit tests, scenario tests
# through the CLI). Exit status is ctest's.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
./scripts/build.sh
cd build
ctest --output-on-failure --parallel "$(nproc)" --timeout 900
