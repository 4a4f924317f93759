#!/usr/bin/env bash
# The one collapse loop against meshopt in one command (issue 25): builds pm_bench_fast in
# build-bench/, runs it on ../shared/meshes (or $PM_BENCH_MESHES) and writes
# tests/bench/fast.md (the levels' quality against meshopt_simplify's at 50/10/2%, and the
# loop's time on one thread against meshopt_simplify's to 1%, medians of 5 runs), then prints
# it. Extra arguments go to pm_bench_fast (e.g. --runs 9); with --metric schroeder first, the
# loop runs Schroeder's metric and the table goes to tests/bench/fast_schroeder.md instead;
# with --fast, the loop without its measured distance, to tests/bench/fast_unmeasured.md;
# with --loop-meshes, on nefertiti after two Loop steps and the bunny after three (made with
# pm_make_big_mesh where run_scale.sh keeps them, once) with the loop pmenc runs on them
# (from a million faces, without the measured distance), to tests/bench/fast_loop_meshes.md
# (about 6 minutes). The former default loop (3cb92db) is quality.md's reference. See
# tests/bench/README.md.
set -euo pipefail

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bench_install run_fast.sh
meshes="${PM_BENCH_MESHES:-$root/../shared/meshes}"  # beside the checkout, or as given
report=fast
if [[ "${1:-}" == --metric && "${2:-}" == schroeder ]]; then report=fast_schroeder; fi
if [[ " $* " == *" --fast "* ]]; then report=fast_unmeasured; fi
loop_meshes=0
if [[ " $* " == *" --loop-meshes "* ]]; then report=fast_loop_meshes loop_meshes=1; fi
bench_need_meshes "$meshes" "$root/tests/bench/$report.md"
build="${PM_BENCH_BUILD:-$root/build-bench}"
bench_configure "$root" "$build"
cmake --build "$build" -j"$(nproc)" --target pm_bench_fast pm_make_big_mesh
if ((loop_meshes)); then
  # The meshes of run_scale.sh's tables, in its work directory (made once, kept while their
  # sources are unchanged), linked into a directory of their own for pm_bench_fast.
  made="$build/tests/bench/scale"
  only="$build/tests/bench/loop_meshes"
  mkdir -p "$made" "$only"
  for spec in nefertiti.obj:2:nefertiti-loop2 stanford-bunny.obj:3:stanford-bunny-loop3; do
    IFS=: read -r source steps name <<<"$spec"
    bench_loop_mesh "$build/tests/bench/pm_make_big_mesh" "$meshes/$source" "$steps" "$made/$name.obj"
    ln -sf "$made/$name.obj" "$only/$name.obj"
  done
  meshes="$only"
fi

# Written to a temporary file first, so a failed run leaves the committed table in place.
out="$root/tests/bench/$report.md"
trap 'rm -f "$out.tmp"' EXIT
"$build/tests/bench/pm_bench_fast" "$meshes" --out "$out.tmp" "$@" >/dev/null
mv "$out.tmp" "$out"
cat "$out"
