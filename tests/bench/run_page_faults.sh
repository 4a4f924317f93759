#!/usr/bin/env bash
# pmenc's and pmdec's large blocks on huge pages (apps/large_pages.h), measured: each process
# with the advice (the default) and without it (PM_HUGE_PAGES=0), alternating, wall time,
# peak memory and minor page faults (/usr/bin/time), medians. Writes tests/bench/page_faults.md
# and prints it.
#
# Rows, on the 950,272-face textured mesh of textured.md (bench_textured_mesh) and on
# nefertiti (../shared/meshes, when there):
#
#   pmenc --fast textured-loop4.obj        the loop without its measure, the stream written
#   pmenc textured-loop4.obj               the default (with the measure below a million faces)
#   pmdec textured-loop4.pm -o full.ply    full detail
#   pmdec --ratio 0.1 textured-loop4.pm    a level of a tenth of the faces
#   pmenc nefertiti.obj                    a mesh of 100K faces
#
#   run_page_faults.sh [--runs N]     (N >= 5, default 5; about 80 s per run here)
#
# Installs what is missing with apt, builds in build-bench/ (or $PM_BENCH_BUILD).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
meshes="${PM_SHARED_MESHES_DIR:-$repo/../shared/meshes}"
report="$repo/tests/bench/page_faults.md"

# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_runs run_page_faults.sh "$@"

bench_install run_page_faults.sh time
bench_configure "$repo" "$build"
cmake --build "$build" -j"$(nproc)" --target pmenc pmdec pm_make_big_mesh

bin="$build/apps"
work="$build/tests/bench/page_faults"
mkdir -p "$work"
trap 'rm -f "$report.tmp"' EXIT
obj="$(bench_textured_mesh "$repo" "$build")"
"$bin/pmenc" -q --fast "$obj" -o "$work/textured.pm"  # pmdec's input

# measure LABEL CMD...: CMD under /usr/bin/time, "wall_seconds peak_kib minor_faults" appended
# to $work/LABEL.runs; a failed command stops the script.
measure() {
  local label="$1"
  shift
  if ! /usr/bin/time -f "%e %M %R" -o "$work/$label.time" "$@" >/dev/null 2>"$work/$label.stderr"; then
    echo "run_page_faults.sh: $label failed: $*" >&2
    tail -5 "$work/$label.stderr" >&2
    exit 1
  fi
  tail -1 "$work/$label.time" >>"$work/$label.runs"
}

labels=(pmenc_fast pmenc_default pmdec_full pmdec_tenth)
titles=("\`pmenc --fast textured-loop4.obj\`" "\`pmenc textured-loop4.obj\` (its measure)"
        "\`pmdec textured-loop4.pm -o full.ply\` (full detail)" "\`pmdec --ratio 0.1 textured-loop4.pm -o tenth.ply\`")
command_of() {  # command_of LABEL: the row's command, in the array cmd
  case "$1" in
    pmenc_fast) cmd=("$bin/pmenc" -q --fast "$obj" -o "$work/out.pm") ;;
    pmenc_default) cmd=("$bin/pmenc" -q "$obj" -o "$work/out.pm") ;;
    pmdec_full) cmd=("$bin/pmdec" -q "$work/textured.pm" -o "$work/full.ply") ;;
    pmdec_tenth) cmd=("$bin/pmdec" -q --ratio 0.1 "$work/textured.pm" -o "$work/tenth.ply") ;;
    pmenc_nefertiti) cmd=("$bin/pmenc" -q "$meshes/nefertiti.obj" -o "$work/out.pm") ;;
  esac
}
if [[ -e "$meshes/nefertiti.obj" ]]; then
  labels+=(pmenc_nefertiti)
  titles+=("\`pmenc nefertiti.obj\` (99,938 faces)")
else
  echo "*** NOTE: $meshes/nefertiti.obj is missing: its row is left out." >&2
fi

commit="$(bench_commit "$repo" lib formats apps)"
load="$(cut -d' ' -f1-3 /proc/loadavg)"
started="$(date -u '+%Y-%m-%d %H:%M')"
rm -f "$work"/*.runs
for ((i = 1; i <= runs; ++i)); do
  echo "run_page_faults.sh: run $i of $runs" >&2
  for label in "${labels[@]}"; do
    # Alternating, and which goes first alternates too.
    if ((i % 2)); then order=(advised plain); else order=(plain advised); fi
    command_of "$label"
    for kind in "${order[@]}"; do
      if [[ $kind == plain ]]; then
        measure "${label}_$kind" env PM_HUGE_PAGES=0 "${cmd[@]}"
      else
        measure "${label}_$kind" env -u PM_HUGE_PAGES "${cmd[@]}"
      fi
    done
  done
done

cpu="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
pct() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%+.0f%%", 100 * (a / b - 1) }'; }
{
  echo "# Large blocks on huge pages: pmenc and pmdec with and without"
  echo
  echo "pmenc and pmdec advise every block of 4 MiB or more onto transparent huge pages (apps/large_pages.h: their operator new; \`PM_HUGE_PAGES=0\` turns it off). Each process with the advice and without it, alternating; wall time, peak resident memory and minor page faults by /usr/bin/time, each the median of its runs. Regenerate with \`bash tests/bench/run_page_faults.sh\`."
  echo
  echo "- machine: $(uname -m), $cpu, $(nproc) hardware threads (Linux $(uname -r)), $(free -g | awk '/^Mem:/ { print $2 }') GB of memory; transparent huge pages: $(cat /sys/kernel/mm/transparent_hugepage/enabled 2>/dev/null || echo none)"
  echo "- date: $started UTC"
  echo "- commit: $commit"
  echo "- load average at the start (1, 5, 15 min): $load, at the end: $(cut -d' ' -f1-3 /proc/loadavg) (a shared machine: the neighbours' work is in every wall-clock time)"
  echo "- runs: $runs of each; the mesh: textured.md's (\`samples/textured.obj\` after 4 Loop steps, attributes kept, 950,272 faces), its .pm by \`pmenc --fast\`"
  echo
  echo "| process | wall (s), advised | without | change | peak (MiB), advised | without | change | minor faults, advised | without |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
  for k in "${!labels[@]}"; do
    a="$work/${labels[$k]}_advised.runs" p="$work/${labels[$k]}_plain.runs"
    wa=$(median "$a" 1) wp=$(median "$p" 1) ka=$(median "$a" 2) kp=$(median "$p" 2)
    fa=$(median "$a" 3) fp=$(median "$p" 3)
    echo "| ${titles[$k]} | $(seconds "$wa") | $(seconds "$wp") | $(pct "$wa" "$wp") | $(mib "$ka") | $(mib "$kp") | $(pct "$ka" "$kp") | $(thousands "${fa%.*}") | $(thousands "${fp%.*}") |"
  done
} >"$report.tmp"
mv "$report.tmp" "$report"
cat "$report"
