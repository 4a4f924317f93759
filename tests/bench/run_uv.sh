#!/usr/bin/env bash
# The texture-coordinate benchmark in one command (issue 4): installs what is missing, builds
# pm_bench_uv in build-bench/, runs it on the meshes with texture coordinates among
# ../shared/meshes and samples/textured.obj, writes tests/bench/uv.md and prints it. Extra
# arguments go to pm_bench_uv (e.g. --targets 0.1,0.02). run_quality.sh runs this too.
# See tests/bench/README.md, "Texture coordinates".
set -euo pipefail

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
# spot, the acceptance mesh, is in the meshes' folder: without it the committed table stays.
bench_start run_uv.sh uv.md "" pm_bench_uv

bench_write_report nice "$build/tests/bench/pm_bench_uv" "$meshes" "$repo/samples/textured.obj" "$@"
