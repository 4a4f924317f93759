#!/usr/bin/env bash
# The picture of a view-dependent level of detail (issue 7): the Stanford bunny encoded by
# pmenc, refined for a camera in front of its head (pm::SelectiveRefinement::set_view, 1080
# pixels high, 60 degrees, 20-pixel tolerance), seen from three sides and coloured by level
# (blue: base mesh, green, red: the finest splits), with and without its edges. Builds
# pmenc and pm_view_picture in build-bench/ (or $PM_BENCH_BUILD) and writes
# tests/bench/images/view_bunny.png and view_bunny_wire.png. See tests/bench/README.md,
# "View-dependent refinement".
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
bunny="$repo/../shared/meshes/stanford-bunny.obj"
images="$repo/tests/bench/images"

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_install render_view.sh

if [[ ! -f "$bunny" ]]; then
  echo "*** NOTE: $bunny is missing: the images were left as they were." >&2
  exit 0
fi

bench_configure "$repo" "$build"
cmake --build "$build" -j"$(nproc)" --target pmenc pm_view_picture

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$build/apps/pmenc" "$bunny" -o "$work/bunny.pm" -q
# The camera: in front of the bunny's head, looking along its body toward the tail.
camera=(--eye -0.2,0.15,0.1 --target 0.05,0.1,-0.02 --fov 60 --height 1080 --pixel-error 20)
mkdir -p "$images"
"$build/tests/bench/pm_view_picture" "$work/bunny.pm" "${camera[@]}" --size 400 \
  -o "$images/view_bunny.png"
"$build/tests/bench/pm_view_picture" "$work/bunny.pm" "${camera[@]}" --size 400 --wire \
  -o "$images/view_bunny_wire.png"
ls -l "$images"/view_bunny*.png
