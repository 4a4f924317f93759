#!/usr/bin/env bash
# The view-dependent refinement benchmark in one command (issue 7): installs what is missing,
# builds pm_make_big_mesh, pmenc and pm_bench_view in build-bench/ (or $PM_BENCH_BUILD), makes
# the ~1M-face mesh (the Stanford bunny after two steps of Loop subdivision, 1,111,216 faces,
# as run_runtime.sh) and its .pm (a few minutes, kept in the build directory for the next
# run; delete view-bench/ there to encode again), runs a 200-frame orbit, writes
# tests/bench/view.md and prints it. Extra arguments go to pm_bench_view (e.g. --runs 5).
# See tests/bench/README.md, "View-dependent refinement".
set -euo pipefail

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
# The ~1M-face mesh of issue 7 is made from stanford-bunny.obj.
bench_start run_view.sh view.md stanford-bunny.obj pm_make_big_mesh pmenc pm_bench_view

data="$build/view-bench"
mkdir -p "$data"
if [[ ! -f "$data/bunny1m.pm" ]]; then
  "$build/tests/bench/pm_make_big_mesh" "$meshes/stanford-bunny.obj" 2 "$data/bunny1m.ply"
  "$build/apps/pmenc" "$data/bunny1m.ply" -o "$data/bunny1m.pm.tmp"
  mv "$data/bunny1m.pm.tmp" "$data/bunny1m.pm"
fi

bench_write_report nice "$build/tests/bench/pm_bench_view" --pm "$data/bunny1m.pm" --frames 200 "$@"
