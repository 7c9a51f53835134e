#!/usr/bin/env bash
# Line coverage of engine/ and lua/ by the whole ctest suite: builds with
# --coverage -O0 (preset `coverage`) into build-coverage/, runs ctest, then
# summarises gcov's JSON output per folder (no gcovr/lcov needed: gcc 12's
# gcov and python3). A line counts once however many objects include it
# (headers) and is covered if any test executed it. Extra args go to ctest.
# Per-file numbers with the uncovered lines: build-coverage/coverage-files.txt.
#   scripts/coverage.sh            # build, test, report
#   scripts/coverage.sh --report   # report only (after a run)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ "${1:-}" != "--report" ]; then
  cmake --preset coverage >/dev/null
  cmake --build build-coverage -j"${JOBS:-2}"
  find build-coverage -name '*.gcda' -delete
  # The "full disk" tests run processes under a file-size limit (RLIMIT_FSIZE):
  # at exit their libgcov rewrites every .gcda truncated, losing the counts of
  # all earlier tests. They run last, their profile sent to a scratch folder.
  (cd build-coverage && ctest --parallel "${JOBS:-2}" --timeout 900 -E 'full disk' "$@") || echo "coverage.sh: some tests failed (coverage still reported)"
  (cd build-coverage && GCOV_PREFIX="$work/discard" ctest --timeout 900 -R 'full disk' "$@") || echo "coverage.sh: some tests failed (coverage still reported)"
fi
# gcov --json-format writes <name>.gcov.json.gz into the current folder. Every
# compiled object counts (its .gcno), so code no test runs shows as 0%.
find "$root/build-coverage" -name '*.gcno' >"$work/list"
(cd "$work" && xargs -a list -n 50 gcov --json-format --preserve-paths >/dev/null 2>&1 || true)
python3 - "$root" "$work" <<'PY'
import gzip, json, os, sys, glob, collections
root, work = sys.argv[1], sys.argv[2]
lines = collections.defaultdict(dict)  # file -> line -> covered
for f in glob.glob(os.path.join(work, "*.gcov.json.gz")):
    with gzip.open(f) as fh:
        data = json.load(fh)
    for src in data["files"]:
        path = os.path.normpath(os.path.join(data.get("current_working_directory", ""), src["file"]))
        rel = os.path.relpath(path, root)
        if not (rel.startswith("engine/") or rel.startswith("lua/")):
            continue
        d = lines[rel]
        for ln in src["lines"]:
            d[ln["line_number"]] = d.get(ln["line_number"], False) or ln["count"] > 0
folders = collections.defaultdict(lambda: [0, 0])
for rel, d in lines.items():
    parts = rel.split("/")
    key = "/".join(parts[:2]) if parts[0] == "engine" else "lua"
    for k in {key, parts[0], "total"}:  # a set: lua/ is both key and top folder
        folders[k][0] += sum(d.values()); folders[k][1] += len(d)
# Per file, most uncovered lines first, with the uncovered line numbers.
with open(os.path.join(root, "build-coverage", "coverage-files.txt"), "w") as out:
    for rel, d in sorted(lines.items(), key=lambda kv: -(len(kv[1]) - sum(kv[1].values()))):
        miss = sorted(n for n, c in d.items() if not c)
        out.write("%-48s %5d/%5d %6.1f%%  uncovered: %s\n" % (rel, len(d) - len(miss), len(d),
                  100.0 * (len(d) - len(miss)) / max(len(d), 1), ",".join(map(str, miss))))
print("%-16s %8s %8s %7s" % ("folder", "covered", "lines", "cover"))
for k in sorted(folders, key=lambda k: (k == "total", k.count("/") == 0, k)):
    c, n = folders[k]
    print("%-16s %8d %8d %6.1f%%" % (k, c, n, 100.0 * c / max(n, 1)))
print("per file: build-coverage/coverage-files.txt")
PY
