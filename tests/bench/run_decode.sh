#!/usr/bin/env bash
# The decode benchmark in one command (issue 10: "decode: full replay in-process, splits per
# second, against OpenMesh's vertex_split replay of its own .pm, and against Draco's decode
# of the same mesh"): pm_bench_decode (decode_bench.cpp) decodes pmenc's .pm (lossless and
# 14-bit), OpenMesh's .pm and Draco's stream of the same mesh to full detail, in one process,
# interleaved, and reports the median of each.
#
# On nefertiti × 16 (1.6M faces), and with --big (or PM_DECODE_BIG=1) also on
# stanford-bunny × 64 (4.4M faces), made by Loop subdivision (big_mesh.h). Both progressive
# meshes are encoded once and cached in the build directory (minutes the first time). Writes
# tests/bench/decode.md and prints it. Installs what is missing with apt (libdraco-dev,
# draco), builds in build-bench/ (or $PM_BENCH_BUILD).
#
#   run_decode.sh [--big] [--runs N]
#
# See tests/bench/README.md, "Decode".
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
meshes="$repo/../shared/meshes"
report="$repo/tests/bench/decode.md"

big="${PM_DECODE_BIG:-0}"
# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_big_and_runs run_decode.sh "$@"
bench_install run_decode.sh draco

for source in nefertiti.obj stanford-bunny.obj; do
  if [[ ! -f "$meshes/$source" ]]; then
    echo >&2
    echo "*** NOTE: $meshes/$source is missing: the large meshes are made from it." >&2
    echo "*** $report was left as it was." >&2
    exit 0
  fi
done

bench_configure "$repo" "$build"
cmake --build "$build" -j"$(nproc)" --target pm_bench_decode

args=(--mesh "$meshes/nefertiti.obj:2")
((big)) && args+=(--mesh "$meshes/stanford-bunny.obj:3")
trap 'rm -f "$report.tmp"' EXIT
nice "$build/tests/bench/pm_bench_decode" "${args[@]}" --runs "$runs" --out "$report.tmp" >/dev/null
mv "$report.tmp" "$report"
cat "$report"
