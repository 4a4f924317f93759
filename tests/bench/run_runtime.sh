#!/usr/bin/env bash
# The runtime benchmark in one command (issue 6): installs what is missing, builds
# pm_bench_runtime in build-bench/ (or $PM_BENCH_BUILD), runs it on the Stanford bunny after
# two steps of Loop subdivision (1,111,216 faces), writes tests/bench/runtime.md and prints
# it. Extra arguments go to pm_bench_runtime (e.g. --runs 9). The first run encodes the mesh
# both ways (a few minutes); the .pm files are cached in the build directory for the next.
# See tests/bench/README.md, "Runtime".
set -euo pipefail

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
# The acceptance mesh is made from stanford-bunny.obj: without it the committed table stays.
bench_start run_runtime.sh runtime.md stanford-bunny.obj pm_bench_runtime

bench_write_report nice "$build/tests/bench/pm_bench_runtime" --mesh "$meshes/stanford-bunny.obj" \
  "$@"
