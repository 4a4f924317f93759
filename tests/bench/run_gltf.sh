#!/usr/bin/env bash
# The glTF chain's bytes against separate files (issue 29) in one command: pm_bench_gltf
# (gltf_bench.cpp) on the samples and, when present, the shared meshes. Writes
# tests/bench/gltf.md and prints it. Installs what is missing with apt, builds in
# build-bench/ (or $PM_BENCH_BUILD). Sizes only: no timing, one run.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
meshes="${PM_SHARED_MESHES:-$repo/../shared/meshes}"  # the shared meshes, wherever they are
# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_install run_gltf.sh libtinygltf-dev nlohmann-json3-dev
bench_configure "$repo" "$build"
cmake --build "$build" -j"$(nproc)" --target pm_bench_gltf >/dev/null

inputs=("$repo"/samples/textured.obj "$repo"/samples/sphere.obj "$repo"/samples/block_features.obj)
if [[ -d "$meshes" ]]; then
  for name in cow.obj spot.obj fandisk.obj nefertiti.obj; do
    [[ -f "$meshes/$name" ]] && inputs+=("$meshes/$name")
  done
else
  echo "run_gltf.sh: $meshes not found: the samples only" >&2
fi
"$build/tests/bench/pm_bench_gltf" "$repo/tests/bench/gltf.md" "${inputs[@]}"
