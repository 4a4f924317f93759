#!/usr/bin/env bash
# Batch conversion benchmark: how much faster `pmenc -j 2` converts a corpus than `-j 1`,
# and how much memory a conversion needs per input face.
#
#   bash tests/bench/batch_bench.sh [BUILD_DIR] [RUNS]     (defaults: build, 5)
#
# The corpus is the acceptance corpus of tests/test_batch.cpp: 60 inputs in nested folders,
# copies of the samples and of the smaller meshes of ../shared/meshes (when there) and the
# invalid models of Debian's assimp-testmodels. Runs of -j 1 and -j 2 alternate, so that a
# change in the machine's load hits both alike; the tables give medians. Not a test: the
# times depend on the machine and on what else runs on it (the load is printed).
set -euo pipefail
source_dir="$(cd "$(dirname "$0")/../.." && pwd)"
build_dir="$(cd "${1:-$source_dir/build}" && pwd)"
runs="${2:-5}"
pmenc="$build_dir/apps/pmenc"
[[ -x "$pmenc" ]] || { echo "no $pmenc: build first (cmake --build $build_dir)" >&2; exit 2; }
[[ -x /usr/bin/time ]] || { echo "no /usr/bin/time: apt-get install time" >&2; exit 2; }
shared="$source_dir/../shared/meshes"
invalid=/usr/share/assimp/models/invalid
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# --- the corpus ------------------------------------------------------------------------
corpus="$work/corpus"
add() { mkdir -p "$(dirname "$corpus/$2")"; cp "$1" "$corpus/$2"; }
"$pmenc" "$source_dir/samples/nonmanifold.obj" -o "$work/variant.pm" -q
for ext in ply off stl; do
  "$build_dir/apps/pmdec" "$work/variant.pm" -o "$work/variant.$ext" -q
  for i in 0 1 2; do add "$work/variant.$ext" "formats/$ext/$i/nonmanifold.$ext"; done
done
[[ -d "$shared" ]] || echo "warning: $shared not found: samples stand in for cow and spot" >&2
for i in 0 1; do
  add "$source_dir/samples/sphere.obj" "models/set$i/sphere.obj"
  add "$source_dir/samples/terrain_holes.obj" "models/set$i/terrain/terrain_holes.obj"
  add "$source_dir/samples/block_features.obj" "models/set$i/block_features.obj"
  add "$source_dir/samples/block_features.obj" "models/set$i/deeper/still/block.OBJ"
  if [[ -d "$shared" ]]; then
    add "$shared/cow.obj" "models/set$i/cow.obj"
    add "$shared/spot.obj" "models/set$i/spot.obj"
  else
    add "$source_dir/samples/block_features.obj" "models/set$i/cow.obj"
    add "$source_dir/samples/sphere.obj" "models/set$i/spot.obj"
  fi
done
for i in $(seq 0 23); do
  if ((i % 2)); then sample=polygons.obj; else sample=nonmanifold.obj; fi
  add "$source_dir/samples/$sample" "small/$((i % 4))/$i/$sample"
done
: > "$work/invalid.txt"
if [[ -d "$invalid" ]]; then
  mkdir -p "$work/invalid"
  cp "$invalid"/* "$work/invalid/"
  ls "$work"/invalid/* > "$work/invalid.txt"
else
  echo "warning: $invalid not found (assimp-testmodels): no invalid inputs" >&2
fi
inputs=$(( $(find "$corpus" -type f | wc -l) + $(wc -l < "$work/invalid.txt") ))

# --- -j 1 against -j 2 ---------------------------------------------------------------------
declare -A times
run() {  # run JOBS: one timed conversion of the corpus into a fresh directory
  rm -rf "$work/out"
  local start end status=0
  start=$(date +%s.%N)
  "$pmenc" -r "$corpus" --from-list "$work/invalid.txt" --out-dir "$work/out" -j "$1" -q \
    2>/dev/null || status=$?
  end=$(date +%s.%N)
  # 8: the invalid inputs failed, as they must; anything else is a real failure.
  if [[ $status -ne 0 && $status -ne 8 ]]; then echo "pmenc -j $1 exited with $status" >&2; exit 1; fi
  times[$1]+="$(awk -v a="$start" -v b="$end" 'BEGIN {print b - a}') "
}
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
for ((r = 0; r < runs; ++r)); do run 1; run 2; done
load_after=$(cut -d' ' -f1-3 /proc/loadavg)
median() { tr ' ' '\n' | grep . | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
minimum() { tr ' ' '\n' | grep . | sort -g | head -1; }
maximum() { tr ' ' '\n' | grep . | sort -g | tail -1; }
m1=$(echo "${times[1]}" | median)
echo "## pmenc -j 1 and -j 2 on $inputs inputs ($runs runs each, $(nproc) cores)"
echo
echo "Load average (1, 5, 15 min): $load_before before, $load_after after."
echo
echo "| jobs | median s | min s | max s | speedup (median) |"
echo "|---|---|---|---|---|"
for j in 1 2; do
  m=$(echo "${times[$j]}" | median)
  printf '| %d | %.2f | %.2f | %.2f | %.2f |\n' "$j" "$m" "$(echo "${times[$j]}" | minimum)" \
    "$(echo "${times[$j]}" | maximum)" "$(awk -v a="$m1" -v b="$m" 'BEGIN {print a / b}')"
done

# --- memory per face ---------------------------------------------------------------------
# Peak resident set of one pmenc (-j 1), less that of the smallest input (the program's
# own), over the input's faces.
peak_kib() {  # peak_kib MESH: prints the peak in KiB; the input's faces go to $work/faces
  /usr/bin/time -f '%M' -o "$work/rss" "$pmenc" "$1" -o "$work/m.pm" --json -q |
    sed 's/.*"input_faces":\([0-9]*\).*/\1/' > "$work/faces"
  cat "$work/rss"
}
baseline=$(peak_kib "$source_dir/samples/polygons.obj")
echo
echo "## Peak memory of pmenc per input face"
echo
echo "Baseline (polygons.obj, 18 faces): $baseline KiB."
echo
echo "| mesh | faces | peak RSS MiB | bytes per face |"
echo "|---|---|---|---|"
meshes=("$source_dir/samples/sphere.obj" "$source_dir/samples/terrain_holes.obj")
for m in cow.obj fandisk.obj rocker-arm.obj armadillo.off stanford-bunny.obj nefertiti.obj; do
  [[ -f "$shared/$m" ]] && meshes+=("$shared/$m")
done
for m in "${meshes[@]}"; do
  kib=$(peak_kib "$m")
  faces=$(cat "$work/faces")
  printf '| %s | %d | %.1f | %.0f |\n' "$(basename "$m")" "$faces" \
    "$(awk -v k="$kib" 'BEGIN {print k / 1024}')" \
    "$(awk -v k="$kib" -v b="$baseline" -v f="$faces" 'BEGIN {print (k - b) * 1024 / f}')"
done
