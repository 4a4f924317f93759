#!/usr/bin/env bash
# Issue 25's "Quality with attributes kept" table in one command: the geometric error of
# spot, samples/textured.obj and the ~1M-face textured mesh (textured.obj after 4 Loop steps
# keeping every attribute, as run_textured.sh makes it) at 50%, 10% and 2% of the faces, for
# pmenc (the one collapse loop) with attributes kept and dropped, and meshopt_simplify on the
# seam-split buffer. Installs what is missing, builds in
# build-bench/ (or $PM_BENCH_BUILD), writes tests/bench/attr_quality.md and prints it. Extra
# arguments go to pm_bench_attr_quality (e.g. --targets 0.1). See tests/bench/README.md,
# "Geometric error with attributes kept".
set -euo pipefail

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_start run_attr_quality.sh attr_quality.md spot.obj pm_bench_attr_quality pm_make_big_mesh

big="$(bench_textured_mesh "$repo" "$build")"
bench_write_report "$build/tests/bench/pm_bench_attr_quality" "$meshes/spot.obj" \
  "$repo/samples/textured.obj" "$big" "$@"
