#!/usr/bin/env bash
# The texture-coordinate benchmark in one command (issue 4): installs what is missing, builds
# pm_bench_uv in build-bench/, runs it on the meshes with texture coordinates among
# ../shared/meshes and samples/textured.obj, writes tests/bench/uv.md and prints it. Extra
# arguments go to pm_bench_uv (e.g. --targets 0.1,0.02). run_quality.sh runs this too.
# --fast (first): pmenc's rows from the fast loop (EncodeOptions::fast), into uv_fast.md.
# See tests/bench/README.md, "Texture coordinates".
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
meshes="${PM_SHARED_MESHES_DIR:-$repo/../shared/meshes}"
report="$repo/tests/bench/uv.md"
fast=()
if [[ "${1:-}" == "--fast" ]]; then
  shift
  fast=(--fast)
  report="$repo/tests/bench/uv_fast.md"
fi

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_install run_uv.sh

# spot, the acceptance mesh, is in ../shared/meshes: without it the committed table stays.
if [[ ! -d "$meshes" ]]; then
  echo >&2
  echo "*** NOTE: $meshes is missing: spot.obj, the mesh of issue 4's acceptance, is there." >&2
  echo "*** Put the test meshes there (see its README.md) and run this again." >&2
  echo "*** $report was left as it was." >&2
  exit 0
fi

bench_configure "$repo" "$build"
cmake --build "$build" -j"$(nproc)" --target pm_bench_uv

# Written to a temporary file first, so a failed run leaves the committed table in place.
trap 'rm -f "$report.tmp"' EXIT
nice "$build/tests/bench/pm_bench_uv" "$meshes" "$repo/samples/textured.obj" \
  --out "$report.tmp" ${fast[@]+"${fast[@]}"} "$@" >/dev/null
mv "$report.tmp" "$report"
cat "$report"
