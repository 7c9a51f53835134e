#!/usr/bin/env bash
# softcut sweep on a real Slurm (issue #18): brings up a private one-node
# cluster (slurm_one_node.sh: munged + slurmctld + slurmd under a temporary
# folder), submits the shipped docs/sweep.sbatch as a 3-task array job running
# an 8-run sweep, waits, merges, and checks the table equals the one a local
# `softcut sweep -j 2` of the same grid merges to; tears the cluster down
# however it ends. Exit 77 (ctest: skipped) with the reason when the daemons
# cannot start here (not root, Slurm not installed).
#   sweep_slurm.sh SOFTCUT_BIN SOURCE_DIR
set -euo pipefail
softcut=$1 src=$2
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/softcut-slurm-XXXXXX")
cluster=$work/cluster
cleanup() {
  "$here/slurm_one_node.sh" down "$cluster" || true
  rm -rf "$work"
}
trap cleanup EXIT

rc=0
env_line=$("$here/slurm_one_node.sh" up "$cluster") || rc=$?
if [ "$rc" = 77 ]; then
  echo "sweep_slurm: SKIPPED: the one-node Slurm cluster cannot start on this machine (reason above)"
  exit 77
fi
[ "$rc" = 0 ] || { echo "sweep_slurm: slurm_one_node.sh up failed ($rc)"; exit 1; }
eval "$env_line"  # SLURM_CONF

cat >"$work/bar.lua" <<'LUA'
local P = softcut.params{ f = 0.01, young = 5e3 }
local s = softcut.scenario{ name = 'bar', duration = 0.2, fps = 10 }
s:mesh{ generate = 'box', options = { max = { 0.1, 0.02, 0.02 }, nx = 5, ny = 2, nz = 2 } }
s:material{ young = P.young, poisson = 0.4 }
local tip = softcut.select.box{ min = { 0.1, -1, -1 }, max = { 1, 1, 1 } }
s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }
s:load{ name = 'tip', nodes = tip, force = { 0, 0, -P.f } }
s:expect{ name = 'sag', at = 0.2, nodes = tip, component = 'z', min = -1 }
return s
LUA
grid=(--grid f=0.001,0.01,0.1,1 --grid young=5e3,1e4)
cd "$work"
export SOFTCUT="$softcut" SOFTCUT_THREADS=1

job=$(sbatch --parsable --array=0-2 --cpus-per-task=1 "$src/docs/sweep.sbatch" bar.lua "${grid[@]}" --out slurm)
job=${job%%;*}
echo "sweep_slurm: submitted array job $job (3 tasks)"
for _ in $(seq 1 600); do  # at most 120 s
  [ -n "$(squeue -h -j "$job" 2>/dev/null)" ] || break
  sleep 0.2
done
if [ -n "$(squeue -h -j "$job" 2>/dev/null)" ]; then
  echo "sweep_slurm: FAIL: job $job still queued or running after 120 s"; squeue; exit 1
fi
for t in 0 1 2; do
  out="slurm-${job}_$t.out"
  [ -f "$out" ] || { echo "sweep_slurm: FAIL: task $t wrote no $out"; exit 1; }
  grep -q "SLURM_ARRAY_TASK_ID=$t (min 0, count 3)" "$out" || { echo "sweep_slurm: FAIL: task $t did not run its shard:"; cat "$out"; exit 1; }
done
"$softcut" sweep merge slurm >merge.txt 2>&1 || true  # one run fails its expectation by design
grep -q "merged 8 runs: 7 passed, 1 failed" merge.txt || { echo "sweep_slurm: FAIL: merge said:"; cat merge.txt; exit 1; }

"$softcut" sweep bar.lua "${grid[@]}" -j 2 --out local >local.txt 2>&1 || true
"$softcut" sweep merge local >/dev/null 2>&1 || true
cmp slurm/sweep.csv local/sweep.csv || { echo "sweep_slurm: FAIL: the tables differ"; diff slurm/sweep.csv local/sweep.csv; exit 1; }
cmp slurm/sweep.json local/sweep.json || { echo "sweep_slurm: FAIL: the JSON tables differ"; exit 1; }
echo "sweep_slurm: 8 runs in 3 Slurm array tasks merged to the same table as one local run"
