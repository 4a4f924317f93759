#!/usr/bin/env bash
# The quality benchmark in one command (issue 3): installs the bench-only dependencies that
# are missing, builds pm_bench_quality in build-bench/, runs it on ../shared/meshes and writes
# tests/bench/quality.md, then prints it. Extra arguments go to pm_bench_quality
# (e.g. --targets 0.5,0.1 or --no-vtk). Then its texture-coordinate part (issue 4):
# run_uv.sh, which writes tests/bench/uv.md. See tests/bench/README.md.
# Issue 25's reference, the former default loop as of commit 3cb92db, stays measurable now
# that the library has one collapse loop: this script builds that commit's pmenc (and nothing
# else) from its sources in $build/reference-3cb92db/, once, and the benchmark runs it beside
# today's rows (one per metric, the one loop).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
meshes="${PM_SHARED_MESHES_DIR:-$repo/../shared/meshes}"  # beside the checkout, or as given
report="$repo/tests/bench/quality.md"

# Bench-only dependencies: the product needs none of these but libopenmesh-dev.
# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_install run_quality.sh python3-vtk9

if [[ ! -d "$meshes" ]]; then
  echo >&2
  echo "*** NOTE: $meshes is missing: there is nothing to benchmark." >&2
  echo "*** Put the test meshes there (see its README.md) and run this again." >&2
  echo "*** $report was left as it was." >&2
  exit 0
fi

reference_commit=3cb92db
reference="$build/reference-$reference_commit"
if ! git -C "$repo" cat-file -e "$reference_commit^{commit}" 2>/dev/null; then
  echo "run_quality.sh: commit $reference_commit (issue 25's reference loop) is not in $repo (a shallow clone? git fetch --unshallow)" >&2
  exit 1
fi
if [[ ! -x "$reference/build/apps/pmenc" ]]; then
  echo "run_quality.sh: building pmenc of commit $reference_commit in $reference" >&2
  rm -rf "$reference"
  mkdir -p "$reference/src"
  git -C "$repo" archive "$reference_commit" | tar -x -C "$reference/src"
  cmake -S "$reference/src" -B "$reference/build" -DCMAKE_BUILD_TYPE=Release -DPM_BUILD_TESTS=OFF >/dev/null
  cmake --build "$reference/build" -j"$(nproc)" --target pmenc
fi

bench_configure "$repo" "$build"
cmake --build "$build" -j"$(nproc)" --target pm_bench_quality

# Written to a temporary file first, so a failed run leaves the committed table in place.
trap 'rm -f "$report.tmp"' EXIT
nice "$build/tests/bench/pm_bench_quality" "$meshes" --out "$report.tmp" \
  --reference-pmenc "$reference/build/apps/pmenc" --reference-label "$reference_commit" "$@" >/dev/null
mv "$report.tmp" "$report"
cat "$report"

# The UV columns: pmenc with its attributes against meshopt on the seam-split buffer.
echo
bash "$repo/tests/bench/run_uv.sh"
