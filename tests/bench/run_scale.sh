#!/usr/bin/env bash
# The memory and scale benchmark in one command (issue 9's memory item, issue 10's
# whole-process and in-process encode tables): wall time and peak memory (/usr/bin/time -v)
# of whole processes on large meshes made by Loop subdivision (pm_make_big_mesh, big_mesh.h):
#
#   pmenc big.obj -o big.pm, pmdec big.pm -o full.obj          ours (the one collapse loop,
#                                                               without its measured distance
#                                                               from 1M faces; --fast-from 0
#                                                               with it)
#   OpenMesh-mkbalancedpm big.obj -o big.om.pm                  OpenMesh's progressive mesh
#   pm_bench_scale_peers meshopt big.obj                        load, meshopt_simplify to 1%
#   pm_bench_scale_peers openmesh big.obj                       load, DecimaterT to 1%
#
# and the encoders' own time inside the process: pm_bench_encode (pm::encode with each
# metric) beside the peers' simplification times.
#
# on nefertiti × 16 (1.6M faces), and with --big (or PM_SCALE_BIG=1) on stanford-bunny × 64
# (4.4M faces; about 15 minutes more on two cores). Writes tests/bench/scale.md and prints
# it. Installs what is missing with apt, builds in build-bench/ (or $PM_BENCH_BUILD).
#
#   run_scale.sh [--big] [--runs N] [--fast-runs N]
#
# --runs: runs of the slow tools (mkbalancedpm, the OpenMesh decimater, pmenc --fast-from 0
# and pm::encode with the measured distance), 1 by default since they take minutes here;
# --fast-runs: runs of pmdec, pmenc, pm::encode --fast with either metric and meshopt (5). Each row reports the median of its runs. See tests/bench/README.md, "Scale and memory".
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${PM_BENCH_BUILD:-$repo/build-bench}"
meshes="$repo/../shared/meshes"
report="$repo/tests/bench/scale.md"

big="${PM_SCALE_BIG:-0}"
runs=1
fast_runs=5
while (($#)); do
  case "$1" in
    --big) big=1 ;;
    --runs) runs="$2"; shift ;;
    --fast-runs) fast_runs="$2"; shift ;;
    *) echo "usage: run_scale.sh [--big] [--runs N] [--fast-runs N]" >&2; exit 2 ;;
  esac
  shift
done

# `time` is GNU time (/usr/bin/time -v gives the peak resident set); libopenmesh-apps has
# OpenMesh-mkbalancedpm.
# shellcheck source=bench_setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/bench_setup.sh"
bench_install run_scale.sh time libopenmesh-apps

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
cmake --build "$build" -j"$(nproc)" --target pmenc pmdec pm_make_big_mesh pm_bench_scale_peers pm_bench_encode

bin="$build/apps"
bench="$build/tests/bench"
work="$bench/scale"
mkdir -p "$work"
trap 'rm -f "$report.tmp"' EXIT

# --- measuring one process -----------------------------------------------------------------

# measure LABEL CMD...: runs CMD under /usr/bin/time -v (niced, as the other benchmarks), and
# appends "wall_seconds peak_kib" to $work/LABEL.runs. A failed command stops the script:
# a table with a failed run in it would be wrong.
measure() {
  local label="$1"
  shift
  local log="$work/$label.time"
  if ! nice /usr/bin/time -v -o "$log" "$@" >"$work/$label.stdout" 2>"$work/$label.stderr"; then
    echo "run_scale.sh: $label failed: $*" >&2
    tail -5 "$work/$label.stderr" >&2
    exit 1
  fi
  # GNU time's wall clock is h:mm:ss.ss or m:ss.ss.
  awk -F': ' '
    /Elapsed \(wall clock\)/ { n = split($2, p, ":"); s = 0; for (i = 1; i <= n; ++i) s = s * 60 + p[i] }
    /Maximum resident set size/ { kib = $2 }
    END { printf "%.2f %d\n", s, kib }' "$log" >>"$work/$label.runs"
}

# inprocess LABEL FIELD CMD...: runs CMD (niced) and appends the seconds it printed after
# FIELD (pm_bench_encode's "wall", the peers' "simplify_s=") to $work/LABEL.inproc: the time
# of the simplification alone, inside the process, without reading the mesh.
inprocess() {
  local label="$1" field="$2"
  shift 2
  if ! nice "$@" >"$work/$label.stdout" 2>"$work/$label.stderr"; then
    echo "run_scale.sh: $label failed: $*" >&2
    tail -5 "$work/$label.stderr" >&2
    exit 1
  fi
  inprocess_seconds "$label" "$field"
}
inprocess_seconds() { field "$1" "$2" >>"$work/$1.inproc"; }  # field: bench_setup.sh

# median, mib, per_face, ratio, seconds, thousands: bench_setup.sh.

# --- one mesh ------------------------------------------------------------------------------

# run_mesh SOURCE STEPS NAME: makes the OBJ (kept in $work while its source is unchanged),
# runs every tool on it and appends the mesh's section to the report.
run_mesh() {
  local source="$1" steps="$2" name="$3"
  local obj="$work/$name.obj"
  bench_loop_mesh "$bench/pm_make_big_mesh" "$meshes/$source" "$steps" "$obj"
  local faces vertices obj_bytes
  faces=$(grep -c '^f ' "$obj")
  vertices=$(grep -c '^v ' "$obj")
  obj_bytes=$(stat -c %s "$obj")
  rm -f "$work/$name".*.runs "$work/$name".*.inproc "$work/$name".*.user

  local i
  for ((i = 1; i <= runs; ++i)); do
    echo "run_scale.sh: $name: OpenMesh-mkbalancedpm, run $i of $runs" >&2
    measure "$name.mkbalancedpm" OpenMesh-mkbalancedpm -o "$work/$name.om.pm" "$obj"
    echo "run_scale.sh: $name: OpenMesh DecimaterT to 1%, run $i of $runs" >&2
    measure "$name.openmesh" "$bench/pm_bench_scale_peers" openmesh "$obj"
    inprocess_seconds "$name.openmesh" simplify_s
    # The collapse loop with its measured distance, which pmenc leaves out from 1,000,000
    # faces (--fast-from): minutes here.
    echo "run_scale.sh: $name: pmenc --fast-from 0 and pm::encode measured, run $i of $runs" >&2
    measure "$name.pmenc_measured" "$bin/pmenc" --fast-from 0 "$obj" -o "$work/$name.measured.pm"
    inprocess "$name.encode_measured" wall "$bench/pm_bench_encode" "$obj" --metric quadric
    sed -n "s/.*user \([0-9.]*\).*/\1/p" "$work/$name.encode_measured.stdout" | head -1 >>"$work/$name.encode_measured.user"
  done
  for ((i = 1; i <= fast_runs; ++i)); do
    echo "run_scale.sh: $name: pmenc, pmdec, meshopt and pm::encode, run $i of $fast_runs" >&2
    measure "$name.pmenc" "$bin/pmenc" "$obj" -o "$work/$name.pm"
    measure "$name.pmdec" "$bin/pmdec" "$work/$name.pm" -o "$work/$name.full.obj"
    measure "$name.meshopt" "$bench/pm_bench_scale_peers" meshopt "$obj"
    inprocess_seconds "$name.meshopt" simplify_s
    inprocess "$name.encode_quadric" wall "$bench/pm_bench_encode" "$obj" --metric quadric --fast
    sed -n "s/.*user \([0-9.]*\).*/\1/p" "$work/$name.encode_quadric.stdout" | head -1 >>"$work/$name.encode_quadric.user"
    inprocess "$name.encode_schroeder" wall "$bench/pm_bench_encode" "$obj" --metric schroeder --fast
  done
  # The full-detail output is the input again: checked by its face count, then dropped.
  local full_faces
  full_faces=$(grep -c '^f ' "$work/$name.full.obj")
  [[ "$full_faces" -eq "$faces" ]] ||
    { echo "run_scale.sh: pmdec wrote $full_faces faces, not $faces" >&2; exit 1; }
  rm -f "$work/$name.full.obj"

  local enc_kib dec_kib
  enc_kib=$(median "$work/$name.pmenc.runs" 2)
  dec_kib=$(median "$work/$name.pmdec.runs" 2)
  {
    echo
    echo "## $source after $steps Loop steps: $(thousands "$faces") faces, $(thousands "$vertices") vertices"
    echo
    echo "Input: \`$name.obj\`, $(mib $((obj_bytes / 1024))) MiB (pm's OBJ writer). Output: \`$name.pm\` $(thousands "$(stat -c %s "$work/$name.pm")") bytes, OpenMesh's \`$name.om.pm\` $(thousands "$(stat -c %s "$work/$name.om.pm")") bytes."
    echo
    echo "| process | runs | wall (s) | peak RSS (MiB) | bytes per input face | pmenc / this | pmdec / this |"
    echo "|---|---:|---:|---:|---:|---:|---:|"
    local label title n wall kib
    for label in pmenc pmenc_measured pmdec mkbalancedpm meshopt openmesh; do
      case "$label" in
        pmenc) title="**\`pmenc $name.obj -o $name.pm\`** (ours, the default: the whole sequence to the base mesh; on a million faces or more without the measured distance, as \`--fast\`)" ;;
        pmenc_measured) title="**\`pmenc --fast-from 0 $name.obj -o $name.measured.pm\`** (ours, the collapse loop with its measured distance, pmenc's default below a million faces)" ;;
        pmdec) title="**\`pmdec $name.pm -o full.obj\`** (ours: full detail)" ;;
        mkbalancedpm) title="\`OpenMesh-mkbalancedpm -o $name.om.pm $name.obj\` (OpenMesh's whole sequence)" ;;
        meshopt) title="meshopt: load (minimal reader), \`meshopt_simplify\` to 1%" ;;
        openmesh) title="OpenMesh: \`read_mesh\`, DecimaterT (ModQuadricT + ModNormalFlippingT) to 1%" ;;
      esac
      n=$(wc -l <"$work/$name.$label.runs")
      wall=$(median "$work/$name.$label.runs" 1)
      kib=$(median "$work/$name.$label.runs" 2)
      echo "| $title | $n | $(seconds "$wall") | $(mib "$kib") | $(per_face "$kib" "$faces") | $(ratio "$enc_kib" "$kib") | $(ratio "$dec_kib" "$kib") |"
    done
    local mkbalancedpm_wall
    mkbalancedpm_wall=$(median "$work/$name.mkbalancedpm.runs" 1)
    echo
    echo "Whole process, issue 10: \`OpenMesh-mkbalancedpm\` takes $(ratio "$mkbalancedpm_wall" "$(median "$work/$name.pmenc.runs" 1)") the time of \`pmenc\` (the goal: 10×), $(ratio "$mkbalancedpm_wall" "$(median "$work/$name.pmenc_measured.runs" 1)") that of \`pmenc --fast-from 0\`."
    echo
    echo "**Encode in-process** (issue 10): the simplification alone, timed inside the process after the mesh is read: \`pm::encode\` (\`pm_bench_encode\`: repair, the whole collapse sequence, the progressive mesh; not writing the .pm), and the peers' own timing of their simplification (\`pm_bench_scale_peers\`: \`meshopt_simplify\` to 1%, OpenMesh's DecimaterT to 1%, the last 1% being the few collapses left to its full sequence). Medians of the runs."
    echo
    echo "| encoder | runs | seconds | this / meshopt_simplify | OpenMesh DecimaterT / this |"
    echo "|---|---:|---:|---:|---:|"
    local meshopt_s openmesh_s this_s
    meshopt_s=$(median "$work/$name.meshopt.inproc" 1)
    openmesh_s=$(median "$work/$name.openmesh.inproc" 1)
    for label in encode_quadric encode_schroeder encode_measured meshopt openmesh; do
      case "$label" in
        encode_quadric) title="**pm::encode**, quadric, \`fast\` (\`pmenc\`'s default on a million faces or more: no measured distance; in regions on two threads (EncodeOptions::fast_partition_vertices), $(seconds "$(median "$work/$name.encode_quadric.user" 1)") s of CPU)" ;;
        encode_schroeder) title="**pm::encode**, schroeder, \`fast\` (likewise)" ;;
        encode_measured) title="**pm::encode**, quadric, with the measured distance (\`pmenc --fast-from 0\`; in regions, $(seconds "$(median "$work/$name.encode_measured.user" 1)") s of CPU)" ;;
        meshopt) title="meshopt_simplify to 1%" ;;
        openmesh) title="OpenMesh DecimaterT (ModQuadricT + ModNormalFlippingT) to 1%" ;;
      esac
      this_s=$(median "$work/$name.$label.inproc" 1)
      echo "| $title | $(wc -l <"$work/$name.$label.inproc") | $(seconds "$this_s") | $(ratio "$this_s" "$meshopt_s") | $(ratio "$openmesh_s" "$this_s") |"
    done
    echo
    echo "Issue 10's encode goals: at most 1.5× meshopt_simplify's time, and at least 20× faster than OpenMesh's decimater."
    echo
    echo "Peers' results, from their own output (the last run): meshopt $(sed 's/.*faces_out=\([0-9]*\).*/\1/' "$work/$name.meshopt.stdout") faces in $(sed 's/.*simplify_s=\([0-9.]*\).*/\1/' "$work/$name.meshopt.stdout") s after $(sed 's/.*load_s=\([0-9.]*\).*/\1/' "$work/$name.meshopt.stdout") s of loading; OpenMesh's decimater $(sed 's/.*faces_out=\([0-9]*\).*/\1/' "$work/$name.openmesh.stdout") faces in $(sed 's/.*simplify_s=\([0-9.]*\).*/\1/' "$work/$name.openmesh.stdout") s after $(sed 's/.*load_s=\([0-9.]*\).*/\1/' "$work/$name.openmesh.stdout") s of loading."
  } >>"$report.tmp"
}

# --- the report ----------------------------------------------------------------------------

# The programs' own footprint, for reading the per-face numbers: pmenc and pmdec doing nothing.
rm -f "$work"/baseline.*.runs
measure baseline.pmenc "$bin/pmenc" --version
measure baseline.pmdec "$bin/pmdec" --version

commit="$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)"
if [[ -n "$(git -C "$repo" status --porcelain -- lib formats apps 2>/dev/null)" ]]; then
  commit="$commit with uncommitted changes in lib/, formats/ or apps/"
fi
cpu="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
om_version="$(dpkg-query -W -f='${Version}' libopenmesh-apps 2>/dev/null || echo unknown)"
mo_version="$(dpkg-query -W -f='${Version}' libmeshoptimizer-dev 2>/dev/null || echo unknown)"
{
  echo "# Memory and scale benchmark"
  echo
  echo "Issue 9 (peak memory of pmenc and pmdec per input face) and issue 10's whole-process and in-process encode tables: each tool is one process under \`/usr/bin/time -v\`, on meshes made by Loop subdivision. Regenerate with \`bash tests/bench/run_scale.sh --big\` (without \`--big\`, the 4.4M-face mesh is left out); how each number is measured is in [README.md](README.md), \"Scale and memory\"."
  echo
  echo "- machine: $(uname -m), $cpu, $(nproc) hardware threads (Linux $(uname -r)), $(free -g | awk '/^Mem:/ { print $2 }') GB of memory"
  echo "- date: $(date -u '+%Y-%m-%d %H:%M') UTC"
  echo "- commit: $commit"
  echo "- load average at the start (1, 5, 15 min): $(cut -d' ' -f1-3 /proc/loadavg) (a shared machine: the neighbours' work is in every wall-clock time)"
  echo "- peers: OpenMesh $om_version (libopenmesh-apps), meshoptimizer $mo_version"
  echo "- runs: $runs of OpenMesh-mkbalancedpm, the OpenMesh decimater and the measured rows (\`pmenc --fast-from 0\`, pm::encode with the measured distance); $fast_runs of pmenc, pmdec, pm::encode \`fast\` (either metric) and meshopt; each row is the median of its runs$( ((runs == 1)) && echo " (so the slow tools' rows are single runs)")"
  echo "- bytes per input face: peak resident set / input faces, the program's own footprint included (pmenc alone, \`--version\`: $(mib "$(median "$work/baseline.pmenc.runs" 2)") MiB; pmdec: $(mib "$(median "$work/baseline.pmdec.runs" 2)") MiB)"
} >"$report.tmp"

run_mesh nefertiti.obj 2 nefertiti-loop2
if ((big)); then
  run_mesh stanford-bunny.obj 3 stanford-bunny-loop3
else
  {
    echo
    echo "The 4.4M-face mesh (stanford-bunny.obj after 3 Loop steps) was not run: \`run_scale.sh --big\` adds it (about 15 minutes more)."
  } >>"$report.tmp"
fi

mv "$report.tmp" "$report"
cat "$report"
