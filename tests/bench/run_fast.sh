#!/usr/bin/env bash
# The fast loop's benchmark in one command (issue 25): builds pm_bench_fast in build-bench/,
# runs it on ../shared/meshes and writes tests/bench/fast.md (quality of the fast loop's
# levels against the default loop's and meshopt_simplify's at 50/10/2%, and its encode time
# on one thread against meshopt_simplify's to 1%, medians of 5 runs), then prints it. Extra
# arguments go to pm_bench_fast (e.g. --runs 9). See tests/bench/README.md.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
meshes="$repo/../shared/meshes"
report="$repo/tests/bench/fast.md"

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_install run_fast.sh

if [[ ! -d "$meshes" ]]; then
  echo >&2
  echo "*** NOTE: $meshes is missing: there is nothing to benchmark." >&2
  echo "*** Put the test meshes there (see its README.md) and run this again." >&2
  echo "*** $report was left as it was." >&2
  exit 0
fi

bench_configure "$repo" "$build"
cmake --build "$build" -j"$(nproc)" --target pm_bench_fast

trap 'rm -f "$report.tmp"' EXIT
"$build/tests/bench/pm_bench_fast" "$meshes" --out "$report.tmp" "$@" >/dev/null
mv "$report.tmp" "$report"
cat "$report"
