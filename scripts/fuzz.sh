#!/usr/bin/env bash
# Builds the libFuzzer targets (clang 14, ASan + UBSan; preset `fuzz`, build-fuzz/)
# and runs each for N seconds on one core (--jobs targets at a time), printing the number
# of executions per target. Exit status 1 if any target found a crash; the
# crashing input is left in build-fuzz/findings/<target>/ (copy it to
# tests/fuzz/regressions/<target>/ and add a doctest case, see docs/hardening.md).
#   scripts/fuzz.sh                      # every target, 60 s each
#   scripts/fuzz.sh --seconds 20 gmsh    # one target (names: gmsh medit vtk vtu tetgen nrrd lua junit reflog sweep_table sweep_plan summary render_record)
#   scripts/fuzz.sh --build-only
#   scripts/fuzz.sh --seconds 30 --jobs 2   # two targets at a time (CI: scripts/test.sh)
#   scripts/fuzz.sh --runs 1000000 --seconds 7200 nrrd   # stop at 1e6 executions (or the time)
#   scripts/fuzz.sh --max-len 4096 --runs 1000000 --seconds 10800 lua  # shorter inputs, faster
# Long run (>= 1e6 execs per target; the corpus grows in build-fuzz/corpus/):
#   scripts/fuzz.sh --seconds 3600
set -euo pipefail
cd "$(dirname "$0")/.."
all=(gmsh medit vtk vtu tetgen nrrd stl obj ply off lua junit reflog sweep_table sweep_plan summary render_record)
seconds=60
runs=-1
max_len=65536
jobs=1
build_only=0
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --seconds=*) seconds="${1#*=}"; shift ;;
    --runs) runs="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --jobs=*) jobs="${1#*=}"; shift ;;
    --runs=*) runs="${1#*=}"; shift ;;
    --max-len) max_len="$2"; shift 2 ;;
    --max-len=*) max_len="${1#*=}"; shift ;;
    --build-only) build_only=1; shift ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
for t in "${targets[@]}"; do
  [[ " ${all[*]} " == *" $t "* ]] || { echo "fuzz.sh: unknown target '$t' (${all[*]})" >&2; exit 2; }
done

command -v clang++-14 >/dev/null || { echo "fuzz.sh: needs clang++-14 and libclang-rt-14-dev" >&2; exit 2; }
[ -f build-fuzz/CMakeCache.txt ] || cmake --preset fuzz >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target "${targets[@]/#/fuzz_}"
[ "$build_only" = 1 ] && exit 0

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/hardening/lsan.supp:print_suppressions=0"
# One target: fuzzes, then writes its result row to build-fuzz/fuzz-<t>.row.
fuzz_one() {
  local t=$1
  local corpus=build-fuzz/corpus/$t findings=build-fuzz/findings/$t log=build-fuzz/fuzz-$t.log
  mkdir -p "$corpus" "$findings"
  dict=tests/fuzz/dict/$t.dict
  # In-process fuzzing (no libFuzzer -jobs: that forks and logs to ./fuzz-N.log).
  args=(-max_total_time="$seconds" -runs="$runs" -timeout=10 -rss_limit_mb=2048
        -max_len="$max_len" -print_final_stats=1 -artifact_prefix="$findings/")
  [ -f "$dict" ] && args+=(-dict="$dict")
  dirs=("$corpus")  # new inputs go to the first folder; seeds and past crashes are read
  for d in tests/fuzz/corpus/$t tests/fuzz/regressions/$t; do [ -d "$d" ] && dirs+=("$d"); done
  local rc=0 execs rate cov res
  build-fuzz/tests/fuzz/fuzz_$t "${args[@]}" "${dirs[@]}" >"$log" 2>&1 || rc=$?
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1 || true)
  rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1 || true)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || true)
  if [ $rc -eq 0 ]; then res=ok; else res="CRASH (rc $rc; $log, $findings/)"; fi
  printf '%-12s %12s %10s %8s  %s\n' "$t" "${execs:-?}" "${rate:-?}" "${cov:-?}" "$res" >"build-fuzz/fuzz-$t.row"
}

# Up to $jobs targets at a time, each an in-process fuzzer on one core.
for t in "${targets[@]}"; do
  rm -f "build-fuzz/fuzz-$t.row"
  fuzz_one "$t" &
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
done
wait
failed=0
printf '%-12s %12s %10s %8s  %s\n' target execs exec/s cov result
for t in "${targets[@]}"; do
  row=$(cat "build-fuzz/fuzz-$t.row" 2>/dev/null || echo "$t  (no result)")
  echo "$row"
  [[ "$row" == *" ok" ]] || failed=1
done
exit $failed
