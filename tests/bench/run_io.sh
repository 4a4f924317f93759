#!/usr/bin/env bash
# The reading and writing benchmark in one command (issue 10: "mesh reading and writing
# throughput in MB/s for OBJ and PLY, against OpenMesh IO"): pm_bench_io (io_bench.cpp) reads
# and writes OBJ and binary PLY with pm's readers and writers and with OpenMesh's IO, in one
# process, ours and OpenMesh's interleaved, and reports the median of each.
#
# On nefertiti × 16 (1.6M faces, a 62 MB OBJ), and with --big (or PM_IO_BIG=1) also on
# stanford-bunny × 64 (4.4M faces), both made by Loop subdivision (pm_make_big_mesh,
# big_mesh.h). Writes tests/bench/io.md and prints it. Installs what is missing with apt,
# builds in build-bench/ (or $PM_BENCH_BUILD).
#
#   run_io.sh [--big] [--runs N]
#
# --runs: runs per row, 7 by default (at least 5). See tests/bench/README.md, "Reading and
# writing".
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
meshes="$repo/../shared/meshes"
report="$repo/tests/bench/io.md"

big="${PM_IO_BIG:-0}"
# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_big_and_runs run_io.sh "$@"
bench_install run_io.sh

# The inputs are made from the shared meshes: without them the committed table stays.
for source in nefertiti.obj stanford-bunny.obj; do
  if [[ ! -f "$meshes/$source" ]]; then
    echo >&2
    echo "*** NOTE: $meshes/$source is missing: the large meshes are made from it." >&2
    echo "*** Put the test meshes there (see its README.md) and run this again." >&2
    echo "*** $report was left as it was." >&2
    exit 0
  fi
done

bench_configure "$repo" "$build"
cmake --build "$build" -j"$(nproc)" --target pm_make_big_mesh pm_bench_io

bench="$build/tests/bench"
work="$bench/io"
mkdir -p "$work"
trap 'rm -f "$report.tmp"' EXIT

# make_mesh SOURCE STEPS NAME: the OBJ, kept in $work while its source is unchanged.
make_mesh() {
  local source="$1" steps="$2" name="$3"
  local obj="$work/$name.obj"
  if [[ ! -s "$obj" || "$meshes/$source" -nt "$obj" ]]; then
    echo "run_io.sh: making $name.obj ($source after $steps Loop steps)" >&2
    "$bench/pm_make_big_mesh" "$meshes/$source" "$steps" "$obj" -q >&2
  fi
  echo "$obj"
}

inputs=("$(make_mesh nefertiti.obj 2 nefertiti-loop2)")
if ((big)); then
  inputs+=("$(make_mesh stanford-bunny.obj 3 stanford-bunny-loop3)")
fi

commit="$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)"
if [[ -n "$(git -C "$repo" status --porcelain -- lib formats 2>/dev/null)" ]]; then
  commit="$commit with uncommitted changes in lib/ or formats/"
fi
cpu="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
om_version="$(dpkg-query -W -f='${Version}' libopenmesh-dev 2>/dev/null || echo unknown)"
{
  echo "# Reading and writing benchmark"
  echo
  echo "Issue 10: mesh reading and writing throughput in MB/s for OBJ and PLY, pm's readers and writers against OpenMesh's IO, in one process on the same files (\`pm_bench_io\`, io_bench.cpp). Regenerate with \`bash tests/bench/run_io.sh --big\` (without \`--big\`, the 4.4M-face mesh is left out); what each row measures is in [README.md](README.md), \"Reading and writing\"."
  echo
  echo "- machine: $(uname -m), $cpu, $(nproc) hardware threads (Linux $(uname -r)), $(free -g | awk '/^Mem:/ { print $2 }') GB of memory"
  echo "- date: $(date -u '+%Y-%m-%d %H:%M') UTC"
  echo "- commit: $commit"
  echo "- load average at the start (1, 5, 15 min): $(cut -d' ' -f1-3 /proc/loadavg) (a shared machine: the neighbours' work is in every time; ours and OpenMesh's runs alternate, so it weighs on both)"
  echo "- peer: OpenMesh $om_version (\`OpenMesh::IO::read_mesh\` and \`write_mesh\` on a \`TriMesh_ArrayKernelT<>\`)"
  echo "- runs: $runs per row, each row the median; MB/s is the file's size (for a write, the writer's own output) over that median, 1 MB = 10^6 bytes"
} >"$report.tmp"

nice "$bench/pm_bench_io" "${inputs[@]}" --runs "$runs" --work "$work" >>"$report.tmp"
if ((!big)); then
  {
    echo
    echo "The 4.4M-face mesh (stanford-bunny.obj after 3 Loop steps) was not run: \`run_io.sh --big\` adds it."
  } >>"$report.tmp"
fi

mv "$report.tmp" "$report"
cat "$report"
