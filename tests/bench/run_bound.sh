#!/usr/bin/env bash
# How tight the recorded errors are, in one command (issue 25): builds pm_bench_bound in
# build-bench/, runs it on ../shared/meshes (or $PM_BENCH_MESHES) and writes
# tests/bench/bound.md (the one collapse loop's recorded error at 50/10/2% of the faces, with
# its measure and without it, against the exact largest distance of an input vertex to the
# level, and the encode's time on one thread, median of 5 runs), then prints it. Extra
# arguments go to pm_bench_bound (e.g. --runs 9). See tests/bench/README.md.
set -euo pipefail

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bench_install run_bound.sh
meshes="${PM_BENCH_MESHES:-$root/../shared/meshes}"  # beside the checkout, or as given
bench_need_meshes "$meshes" "$root/tests/bench/bound.md"
build="${PM_BENCH_BUILD:-$root/build-bench}"
bench_configure "$root" "$build"
cmake --build "$build" -j"$(nproc)" --target pm_bench_bound

# Written to a temporary file first, so a failed run leaves the committed table in place.
out="$root/tests/bench/bound.md"
trap 'rm -f "$out.tmp"' EXIT
"$build/tests/bench/pm_bench_bound" "$meshes" --out "$out.tmp" "$@" >/dev/null
mv "$out.tmp" "$out"
cat "$out"
