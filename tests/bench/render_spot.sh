#!/usr/bin/env bash
# Pictures of spot's levels of detail with a checker texture on its UVs (issue 4), so that a
# person can see the seams hold: builds pm_bench_uv and pm_render in build-bench/, makes the
# LODs (pmenc, and meshopt_simplify on the seam-split vertex buffer, as uv.md measures
# them), and writes tests/bench/images/*.png. See tests/bench/images/README.md.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
spot="$repo/../shared/meshes/spot.obj"
images="$repo/tests/bench/images"

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_install render_spot.sh

if [[ ! -f "$spot" ]]; then
  echo "*** NOTE: $spot is missing: the images were left as they were." >&2
  exit 0
fi

bench_configure "$repo" "$build"
cmake --build "$build" -j"$(nproc)" --target pm_bench_uv pm_render

lods="$(mktemp -d)"
trap 'rm -rf "$lods"' EXIT
# The LODs as uv.md measures them: spot_010_pmenc.obj, spot_010_meshopt.obj, ...
"$build/tests/bench/pm_bench_uv" "$spot" --targets 0.1,0.02 --dump "$lods" >/dev/null

render="$build/tests/bench/pm_render"
# Front left and back right: between them they show the seams on the head, the flanks, the
# legs and around the tail. Every picture is framed by the original's box, so they line up.
front=(--view 150,20)
back=(--view 330,20)
mkdir -p "$images"
"$render" "$spot" "${front[@]}" --zoom 1.2 -o "$images/spot_100.png"
for level in 010 002; do
  "$render" "$lods/spot_${level}_pmenc.obj" --frame "$spot" "${front[@]}" --zoom 1.2 \
    -o "$images/spot_${level}.png"
  "$render" "$lods/spot_${level}_meshopt.obj" --frame "$spot" "${front[@]}" --zoom 1.2 \
    -o "$images/spot_${level}_meshopt.png"
done
# All five side by side, from both sides: the original, pmenc 10% and 2%, meshopt 10% and 2%.
"$render" "$spot" "$lods/spot_010_pmenc.obj" "$lods/spot_002_pmenc.obj" \
  "$lods/spot_010_meshopt.obj" "$lods/spot_002_meshopt.obj" "${front[@]}" "${back[@]}" \
  --zoom 1.2 --size 256 -o "$images/spot_compare.png"
# The same with the edges drawn, to see where the seams run through the triangles.
"$render" "$spot" "$lods/spot_010_pmenc.obj" "$lods/spot_002_pmenc.obj" \
  "$lods/spot_010_meshopt.obj" "$lods/spot_002_meshopt.obj" "${front[@]}" \
  --zoom 1.2 --size 256 --wire --wire-width 0.6 -o "$images/spot_compare_wire.png"
ls -l "$images"/*.png
