#!/usr/bin/env bash
# Issue 25's acceptance in one command: every benchmark its lines name, one after the other
# in one run (so that their numbers share the machine's hour), then tests/bench/issue25.md,
# the account line by line (issue25_summary.py: each line's numbers, read from the tables
# just written, and whether it holds). Prints it.
#
#   run_issue25.sh [--runs N]     (N >= 5, default 5: each time is a median of N runs)
#
# In order (each script installs what is missing and builds in build-bench/, or
# $PM_BENCH_BUILD; tests/bench/README.md says what each measures):
#   run_fast.sh --runs N                 fast.md: the loop with its measure, shared meshes
#   run_fast.sh --fast --runs N          fast_unmeasured.md: without it
#   run_fast.sh --loop-meshes --runs N   fast_loop_meshes.md: the 1.6M- and 4.4M-face meshes
#   run_textured.sh --runs N             textured.md: the ~1M-face textured mesh, whole process
#                                        and in-process
#   run_quality.sh                       quality.md against 3cb92db and meshopt, and uv.md
#   run_attr_quality.sh                  attr_quality.md: the error with attributes kept
# About 30 minutes on 2 cores. A table that was not written in this run stops the script
# before the account (it would read an older run's numbers).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bench="$repo/tests/bench"
meshes="${PM_SHARED_MESHES_DIR:-$repo/../shared/meshes}"

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_runs run_issue25.sh "$@"
if [[ ! -d "$meshes" ]]; then
  echo "run_issue25.sh: $meshes is missing: the shared meshes are what issue 25 measures;" \
    "tests/bench/issue25.md was left as it was" >&2
  exit 1
fi
# The fast tables' scripts read the meshes from $PM_BENCH_MESHES; the others from
# $PM_SHARED_MESHES_DIR.
export PM_BENCH_MESHES="$meshes" PM_SHARED_MESHES_DIR="$meshes"

started="$(date -u '+%Y-%m-%d %H:%M UTC')"
load="$(cut -d' ' -f1-3 /proc/loadavg)"
marker="$(mktemp)"
trap 'rm -f "$marker" "$bench/issue25.md.tmp"' EXIT
sleep 1  # a table written in this second is newer than the marker

step() {
  echo "run_issue25.sh: $* ($(date -u '+%H:%M'))" >&2
  bash "$@" >/dev/null
}
step "$bench/run_fast.sh" --runs "$runs"
step "$bench/run_fast.sh" --fast --runs "$runs"
step "$bench/run_fast.sh" --loop-meshes --runs "$runs"
step "$bench/run_textured.sh" --runs "$runs"
step "$bench/run_quality.sh"
step "$bench/run_attr_quality.sh"

for table in fast fast_unmeasured fast_loop_meshes textured quality uv attr_quality; do
  if [[ ! "$bench/$table.md" -nt "$marker" ]]; then
    echo "run_issue25.sh: tests/bench/$table.md was not written by this run;" \
      "tests/bench/issue25.md was left as it was" >&2
    exit 1
  fi
done
python3 "$bench/issue25_summary.py" "$bench" "$started" "$load" >"$bench/issue25.md.tmp"
mv "$bench/issue25.md.tmp" "$bench/issue25.md"
cat "$bench/issue25.md"
