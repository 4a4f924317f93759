#!/usr/bin/env bash
# The web decode benchmark in one command (issue 28, "Speed"): full decode of the 1.6M-face
# Loop mesh in node (the WebAssembly decoder) against the native library, and the browser
# test's time from the first byte to the first drawn frame. Writes web/bench/decode.md and
# prints it.
#
#   web/bench/run_decode.sh [--runs N] [--browser TEST_BUILD_DIR] [--browser-runs N]
#
# The mesh is tests/bench's (run_scale.sh, run_decode.sh): nefertiti after 2 steps of Loop
# subdivision, 1,599,008 faces, made by pm_make_big_mesh (big_mesh.h) and cached; pmenc
# encodes it lossless and with --quantize 14. decode.mjs then times, N times (7 unless given,
# at least 5) and alternating, the WebAssembly decoder and pm_bench_decode_stream on each
# stream, wall-clock and CPU time; each cell is a median. Builds the benchmarks in build-bench/ (or $PM_BENCH_BUILD,
# with the packages tests/bench needs, installed when missing) and the decoder with
# web/build.sh in BUILD/web.
#
# The shared meshes: ../shared/meshes beside the repository, or $PM_SHARED_MESHES_DIR.
# --browser: also runs Web.browser (ctest) in that test build --browser-runs times (3) and
# reports each run's "first byte to first frame". Without it, the table's browser part says
# it was not run.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
meshes="${PM_SHARED_MESHES_DIR:-$repo/../shared/meshes}"
report="$repo/web/bench/decode.md"

runs=7
browser_build=""
browser_runs=3
while (($#)); do
  case "$1" in
    --runs) runs="${2:-}"; shift ;;
    --browser) browser_build="$(realpath "${2:-}")"; shift ;;
    --browser-runs) browser_runs="${2:-}"; shift ;;
    *) echo "usage: run_decode.sh [--runs N] [--browser TEST_BUILD_DIR] [--browser-runs N]" >&2; exit 2 ;;
  esac
  shift
done
if ! [[ "$runs" =~ ^[0-9]+$ ]] || ((runs < 5)); then
  echo "run_decode.sh: --runs must be at least 5 (each cell is a median)" >&2
  exit 2
fi

if [[ ! -f "$meshes/nefertiti.obj" ]]; then
  echo >&2
  echo "*** NOTE: $meshes/nefertiti.obj is missing: the 1.6M-face mesh is made from it." >&2
  echo "*** $report was left as it was." >&2
  exit 0
fi

# shellcheck source=../../tests/bench/bench_setup.sh
source "$repo/tests/bench/bench_setup.sh"
bench_install run_decode.sh
bench_configure "$repo" "$build"
cmake --build "$build" -j"$(nproc)" --target pmenc pm_make_big_mesh pm_bench_decode_stream
bash "$repo/web/build.sh" "$build/web" >/dev/null

bench="$build/tests/bench"
work="$bench/web-decode"
mkdir -p "$work"
trap 'rm -f "$report.tmp"' EXIT
mesh="$work/nefertiti-loop2.ply"
if [[ ! -s "$mesh" || "$meshes/nefertiti.obj" -nt "$mesh" ]]; then
  echo "run_decode.sh: making nefertiti-loop2.ply (nefertiti.obj after 2 Loop steps)" >&2
  "$bench/pm_make_big_mesh" "$meshes/nefertiti.obj" 2 "$mesh" -q
fi
# Encoded every time: the streams are the current pmenc's (3 seconds each).
"$build/apps/pmenc" -q "$mesh" -o "$work/nefertiti-loop2.pm"
"$build/apps/pmenc" -q --quantize 14 "$mesh" -o "$work/nefertiti-loop2-q14.pm"

load_before="$(cut -d' ' -f1-3 /proc/loadavg)"
started="$(date -u '+%Y-%m-%d %H:%M')"
table="$(nice node "$repo/web/bench/decode.mjs" "$build/web/dist" "$bench/pm_bench_decode_stream" "$runs" \
         "$work/nefertiti-loop2.pm" "$work/nefertiti-loop2-q14.pm")"
load_after="$(cut -d' ' -f1-3 /proc/loadavg)"

browser_rows=()
if [[ -n "$browser_build" ]]; then
  for ((i = 1; i <= browser_runs; ++i)); do
    echo "run_decode.sh: Web.browser, run $i of $browser_runs" >&2
    load="$(cut -d' ' -f1 /proc/loadavg)"
    log="$work/browser-$i.log"
    ctest --test-dir "$browser_build" -R '^Web\.browser$' -V >"$log" 2>&1 ||
      { tail -20 "$log" >&2; echo "run_decode.sh: Web.browser failed (its output: $log)" >&2; exit 1; }
    line="$(grep -o -m1 'first byte to first frame: [0-9]* ms.*' "$log")" ||
      { echo "run_decode.sh: Web.browser passed without printing its first frame's time (see $log)" >&2; exit 1; }
    counts="$(sed 's/.*while streaming: //; s/,/ /g' <<<"$line")"
    browser_rows+=("| $(date -u '+%H:%M') UTC | $load | $(sed 's/first byte to first frame: \([0-9]*\) ms.*/\1/' <<<"$line") | $(awk '{ print $1 }' <<<"$counts") | $(wc -w <<<"$counts") |")
  done
fi

commit="$(bench_commit "$repo" lib formats web tests/bench ':!web/bench/decode.md')"
cpu="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
# (awk reads emcc's every line: with head, emcc could die of SIGPIPE, and pipefail end the script)
emcc_version="$(NODE_PATH=/usr/share/nodejs emcc --version 2>/dev/null | awk 'NR == 1 { sub(/.*\) /, ""); sub(/ \(.*/, ""); print }')"
{
  echo "# Web decode benchmark"
  echo
  echo "Issue 28's speed rows: full decode of the 1.6M-face Loop mesh in node (the WebAssembly"
  echo "decoder) against the native library, and the browser's first frame. Regenerate with"
  echo "\`bash web/bench/run_decode.sh --browser build\` (build: a test build, for Web.browser)."
  echo
  echo "- machine: $(uname -m), $cpu, $(nproc) hardware threads, node $(node --version), emscripten $emcc_version (-O3)"
  echo "- date: $started UTC; commit $commit"
  echo "- load average (1, 5, 15 min): $load_before before, $load_after after (a machine shared with other builds: every time here includes the neighbours' work; the ratio is what this table is for)"
  echo "- the mesh: nefertiti.obj after 2 Loop steps (tests/bench's pm_make_big_mesh, as run_scale.sh and tests/bench/run_decode.sh make it), 1,599,008 faces; \`pmenc\` lossless and \`pmenc --quantize 14\`"
  echo "- the same work on both sides, from the stream's bytes in memory: read_pm, then extract_level at full detail. WebAssembly: \`CoreDecoder\` append + finish, then \`level()\` (which also copies the typed arrays out of the module's memory). Native: \`pm_bench_decode_stream\` (tests/bench/decode_stream.cpp), timed inside its process. Median of $runs runs, the two alternating, after one unmeasured WebAssembly decode (V8 optimizes the module's hot functions while they first run). Wall-clock time, and CPU time (node's process, the native program's; single-threaded decoders): on a loaded machine, CPU time is the time each was given, and the fairer ratio."
  echo
  echo "$table"
  echo
  echo "Goal (issue 28): the node full decode within 2 times the native decoder's time."
  echo
  echo "## First byte to first frame (browser)"
  echo
  echo "From \`Web.browser\` (web/tests/browser.test.mjs prints it): Chromium headless with SwiftShader (WebGL on the CPU), a 1,310,720-face 14-bit stream served throttled, the worker and the module started when the page opens."
  echo
  if ((${#browser_rows[@]})); then
    echo "| run | load average (1 min) | first byte to first frame (ms) | faces in the first frame | face counts drawn while streaming |"
    echo "|---|---:|---:|---:|---:|"
    printf '%s\n' "${browser_rows[@]}"
  else
    echo "Not run this time (\`--browser BUILD_DIR\` runs it)."
  fi
} >"$report.tmp"
mv "$report.tmp" "$report"
cat "$report"
