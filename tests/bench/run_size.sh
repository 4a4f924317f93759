#!/usr/bin/env bash
# The size and random-access benchmark in one command (issue 5): writes tests/bench/size.md.
#
#   1. On every mesh of ../shared/meshes (pm_bench_size, one row each): pm's .pm, lossless
#      and with 14-bit positions, beside zstd -19 of the raw binary mesh, OpenMesh's .pm
#      (OpenMesh-mkbalancedpm) and Draco (draco_encoder -qp 14 -cl 10), in bytes and bits
#      per vertex.
#   2. On the ~1M-face mesh (stanford-bunny after 2 Loop steps, pm_make_big_mesh): the time
#      pmdec takes to write the 1%, 10% and 100% levels, medians of 5 runs: a coarse level
#      decompresses only the chunks it needs.
#
# Installs what is missing with apt (draco, libopenmesh-apps), builds in build-bench/ (or
# $PM_BENCH_BUILD). Encoding the 1M-face mesh takes a few minutes; its .pm is kept in the
# build directory while pmenc and the mesh are unchanged.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
meshes="$repo/../shared/meshes"
report="$repo/tests/bench/size.md"
runs=5

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_install run_size.sh draco libopenmesh-apps time

if [[ ! -d "$meshes" ]]; then
  echo >&2
  echo "*** NOTE: $meshes is missing: the size table is measured on the shared meshes." >&2
  echo "*** Put the test meshes there (see its README.md) and run this again." >&2
  echo "*** $report was left as it was." >&2
  exit 0
fi

bench_configure "$repo" "$build"
cmake --build "$build" -j"$(nproc)" --target pmenc pmdec pm_bench_size pm_make_big_mesh
bin="$build/apps"
bench="$build/tests/bench"
work="$bench/size"
mkdir -p "$work"
trap 'rm -f "$report.tmp"' EXIT

commit="$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)"
if ! git -C "$repo" diff --quiet HEAD -- lib formats apps 2>/dev/null; then
  commit="$commit with uncommitted changes"
fi
cpu="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"

{
  echo "# Size and random-access benchmark"
  echo
  echo "Issue 5. Regenerate with \`bash tests/bench/run_size.sh\`; see [README.md](README.md), \"Size\"."
  echo
  echo "- machine: $(uname -m), $cpu, $(nproc) hardware threads"
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "- commit: $commit"
  echo "- peers: zstd $(zstd --version 2>/dev/null | grep -o 'v[0-9.]*' | head -1), OpenMesh $(dpkg-query -W -f='${Version}' libopenmesh-apps 2>/dev/null), Draco $(dpkg-query -W -f='${Version}' draco 2>/dev/null)"
  echo
  echo "## Sizes on ../shared/meshes"
  echo
  echo "Bytes, with bits per input vertex in parentheses. *raw zstd*: zstd -19 of float32 xyz per vertex and uint32 per triangle corner; *raw+attr*: the same plus the attributes the .pm carries (texture-coordinate and normal tables as float32, a uint32 id per corner for each, float32 colours, uint32 materials), for meshes that have them. *pm lossless*: pmenc's default stream (every float bit, every attribute, every level of detail). *pm geometry only*: \`pmenc --drop-attributes\`, for meshes with attributes: what OpenMesh's .pm holds. *draco q14*: \`draco_encoder -qp 14 -cl 10\` (10-bit texture coordinates, 8-bit normals: its defaults), one level. *pm q14*: \`pmenc --quantize 14 --quantize-uv 10 --quantize-normal 8\` (and so its default \`--error-bits 5\`), every level (the default order: splits in layers of independent splits within windows of 1/16 of the vertices). *pm q14 layered*: the same with \`--layered\` (layers within whole chunks: smaller, but levels inside a chunk are coarser than the greedy order's, so it is not the default). *pm q14 greedy*: the same with \`--layer-window 0\` (the simplifier's order)."
  echo
  echo "| mesh | vertices | faces | raw zstd | raw+attr zstd | OpenMesh .pm | pm lossless | pm / raw(+attr) | pm / OpenMesh | pm geometry only | pm geometry / OpenMesh | draco q14 | pm q14 | pm q14 / draco | pm q14 layered | layered / draco | pm q14 greedy | greedy / draco | attributes |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
} >"$report.tmp"

rows="$work/rows.md"
: >"$rows"
for mesh in "$meshes"/*.obj "$meshes"/*.off "$meshes"/*.ply; do
  [[ -f "$mesh" ]] || continue
  echo "run_size.sh: $(basename "$mesh")" >&2
  nice "$bench/pm_bench_size" "$mesh" --work "$work" >>"$rows"
done
cat "$rows" >>"$report.tmp"

# The acceptance, counted from the table's ratio columns (fields 9, 10, 12, 15, 17 and 19 of
# each row, the first field being empty).
awk -F'|' '
  { n++; if ($9 + 0 < 1) a++; if ($10 + 0 <= 0.5) b++; if ($12 + 0 <= 0.5) g++; if ($15 + 0 <= 1.25) c++; if ($17 + 0 <= 1.25) l++; if ($19 + 0 <= 1.25) r++ }
  END {
    printf "\n**Lossless smaller than raw(+attr) zstd: %d of %d. At most half of OpenMesh'"'"'s .pm: %d of %d with every attribute, %d of %d on geometry alone. q14 at most 1.25 times Draco: %d of %d (layered: %d of %d; greedy order: %d of %d).**\n", a, n, b, n, g, n, c, n, l, n, r + 0, n
  }' "$rows" >>"$report.tmp"

# --- random access on the ~1M-face mesh ----------------------------------------------------
big="$work/stanford-bunny-loop2.obj"
if [[ ! -s "$big" || "$meshes/stanford-bunny.obj" -nt "$big" ]]; then
  echo "run_size.sh: making $(basename "$big")" >&2
  "$bench/pm_make_big_mesh" "$meshes/stanford-bunny.obj" 2 "$big" -q
fi
big_pm="$work/stanford-bunny-loop2.pm"
if [[ ! -s "$big_pm" || "$bin/pmenc" -nt "$big_pm" || "$big" -nt "$big_pm" ]]; then
  echo "run_size.sh: pmenc $(basename "$big") (a few minutes)" >&2
  nice "$bin/pmenc" "$big" -o "$big_pm" -q
fi
faces=$(grep -c '^f ' "$big")

declare -A seconds written
for ratio in 0.01 0.1 1; do
  : >"$work/extract.runs"
  for ((i = 1; i <= runs; ++i)); do
    nice /usr/bin/time -f %e -o "$work/extract.time" "$bin/pmdec" "$big_pm" --ratio "$ratio" -q \
      -o "$work/extract.obj"
    cat "$work/extract.time" >>"$work/extract.runs"
  done
  seconds[$ratio]=$(median "$work/extract.runs" 1)
  written[$ratio]=$(grep -c '^f ' "$work/extract.obj")
done
rm -f "$work/extract.obj"
chunks=$("$bin/pmdec" "$big_pm" --info | awk '/^chunks/ { print $2 }')

{
  echo
  echo "## Random access: one level of the ~1M-face mesh"
  echo
  echo "\`$(basename "$big")\`: $faces faces (stanford-bunny after 2 Loop steps), \`$(basename "$big_pm")\` $(stat -c %s "$big_pm") bytes in ${chunks:-?} chunks. Whole \`pmdec big.pm --ratio R -o out.obj\` processes (reading the file, decompressing the chunks the level needs, replaying, writing the OBJ), median of $runs runs."
  echo
  echo "| level | faces written | seconds | full / this |"
  echo "|---|---:|---:|---:|"
  for ratio in 0.01 0.1 1; do
    awk -v r="$ratio" -v f="${written[$ratio]}" -v s="${seconds[$ratio]}" -v full="${seconds[1]}" \
      'BEGIN { printf "| %g%% | %d | %.3f | %.1f× |\n", r * 100, f, s, full / s }'
  done
} >>"$report.tmp"

mv "$report.tmp" "$report"
cat "$report"
