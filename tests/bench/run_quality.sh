#!/usr/bin/env bash
# The quality benchmark in one command (issue 3): installs the bench-only dependencies that
# are missing, builds pm_bench_quality in build-bench/, runs it on ../shared/meshes and writes
# tests/bench/quality.md, then prints it. Extra arguments go to pm_bench_quality
# (e.g. --targets 0.5,0.1 or --no-vtk). Then its texture-coordinate part (issue 4):
# run_uv.sh, which writes tests/bench/uv.md. See tests/bench/README.md.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
meshes="$repo/../shared/meshes"
report="$repo/tests/bench/quality.md"

# Bench-only dependencies: the product needs none of these but libopenmesh-dev.
missing=()
for package in g++ cmake libopenmesh-dev libcli11-dev libzstd-dev libmeshoptimizer-dev \
               zlib1g-dev python3-vtk9; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" ||
    missing+=("$package")
done
if ((${#missing[@]})); then
  echo "run_quality.sh: installing ${missing[*]}" >&2
  sudo=""
  [[ $(id -u) -eq 0 ]] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"
fi

if [[ ! -d "$meshes" ]]; then
  echo >&2
  echo "*** NOTE: $meshes is missing: there is nothing to benchmark." >&2
  echo "*** Put the test meshes there (see its README.md) and run this again." >&2
  echo "*** $report was left as it was." >&2
  exit 0
fi

cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release -DPM_BUILD_BENCH=ON \
  -DPM_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j"$(nproc)" --target pm_bench_quality

# Written to a temporary file first, so a failed run leaves the committed table in place.
trap 'rm -f "$report.tmp"' EXIT
nice "$build/tests/bench/pm_bench_quality" "$meshes" --out "$report.tmp" "$@" >/dev/null
mv "$report.tmp" "$report"
cat "$report"

# The UV columns: pmenc with its attributes against meshopt on the seam-split buffer.
echo
bash "$repo/tests/bench/run_uv.sh"
