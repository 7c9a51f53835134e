#!/usr/bin/env bash
# scripts/SoftcutScenarioTests.cmake as a user project uses it: a project with
# a passing scenario (its reference recorded), one whose expectation fails, one
# in a subfolder that requires a helper module below it (sub/lib/helper.lua),
# and the module itself get one ctest test each; the failing one fails, the
# module is skipped.
#   scenario_tests_helper.sh SOFTCUT_BIN SOURCE_DIR
set -euo pipefail
softcut=$1 src=$2
proj=$(mktemp -d "${TMPDIR:-/tmp}/softcut-helper-XXXXXX")
trap 'rm -rf "$proj"' EXIT
mkdir -p "$proj/scenarios/sub/lib"
bar() {  # bar NAME EXPECT-RESULT [FIRST-LINE]
  cat <<LUA
${3:-}
local s = softcut.scenario{ name = '$1', duration = 0.2, fps = 10 }
s:mesh{ generate = 'box', options = { max = { 0.1, 0.02, 0.02 }, nx = 5, ny = 2, nz = 2 } }
s:material{ young = 5e3, poisson = 0.4 }
s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }
s:load{ name = 'tip', nodes = softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } }, force = { 0, 0, -0.01 } }
s:expect{ name = 'holds', at = 0.2, check = function(f) return $2, 'as written' end }
return s
LUA
}
bar good true >"$proj/scenarios/good.lua"
bar bad false >"$proj/scenarios/bad.lua"
bar deep "require('lib.helper').ok()" >"$proj/scenarios/sub/deep.lua"
printf 'return { ok = function() return true end }\n' >"$proj/scenarios/sub/lib/helper.lua"
"$softcut" check --record "$proj/scenarios/good.lua" "$proj/scenarios/sub/deep.lua" >/dev/null
cat >"$proj/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.20)
project(uses_softcut NONE)
enable_testing()
include($src/scripts/SoftcutScenarioTests.cmake)
softcut_add_scenario_tests(scenarios SOFTCUT $softcut PREFIX "s: " TIMEOUT 120)
CMAKE
cmake -S "$proj" -B "$proj/build" >/dev/null
out=$(ctest --test-dir "$proj/build" 2>&1 || true)
echo "$out"
want() { grep -Eq "$1" <<<"$out" || { echo "scenario_tests_helper: FAIL: no line matching '$1'"; exit 1; }; }
want 'Test +#[0-9]+: s: bad \.+\*+Failed'
want 'Test +#[0-9]+: s: good \.+ +Passed'
want 'Test +#[0-9]+: s: sub/deep \.+ +Passed'
want 'Test +#[0-9]+: s: sub/lib/helper \.+\*+Skipped'
want 'tests passed, 1 tests failed out of 4'
echo "scenario_tests_helper: 4 tests, bad failed, module skipped"
