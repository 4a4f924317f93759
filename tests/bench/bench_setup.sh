# shellcheck shell=bash
# Sourced by the benchmark scripts: what each of them needs before it runs.
#   bench_start TOOL REPORT MESH TARGET... what a script that writes one table does first: sets
#                                          repo (this checkout), build ($PM_BENCH_BUILD, else
#                                          build-bench/), meshes ($PM_SHARED_MESHES_DIR, else
#                                          ../shared/meshes) and report (tests/bench/REPORT);
#                                          bench_install TOOL; bench_need_meshes for MESH in
#                                          $meshes ("": the folder); configures build and
#                                          builds the targets
#   bench_write_report COMMAND...          runs COMMAND --out $report.tmp (its output dropped),
#                                          then moves the table to $report and prints it: a
#                                          failed run leaves the committed table in place
#   bench_install TOOL [EXTRA_PACKAGE...]  installs the missing Debian packages the benchmarks
#                                          build with, plus the script's own extras
#   bench_configure REPO BUILD             configures BUILD for the benchmarks (tests off)
#   bench_big_and_runs TOOL ARGS...        parses [--big] [--runs N] into $big (kept when
#                                          not given) and $runs (7 unless given, at least 5)
#   bench_runs TOOL ARGS...                parses [--runs N] into $runs (5 unless given, at
#                                          least 5: each row is a median)
#   bench_commit REPO PATHSPEC...          prints HEAD's short hash, "with uncommitted
#                                          changes" after it when the paths have some
#   bench_loop_mesh MAKE SOURCE STEPS OBJ  makes OBJ, SOURCE after STEPS Loop steps (MAKE:
#                                          pm_make_big_mesh), unless OBJ is newer than SOURCE
#   bench_textured_mesh REPO BUILD         makes BUILD/tests/bench/textured/textured-loop4.obj
#                                          (samples/textured.obj after 4 Loop steps keeping its
#                                          attributes) unless it is newer than both its sources;
#                                          prints its path
#   bench_need_meshes MESHES REPORT [MESH] exits (0) with a note when the folder MESHES, or
#                                          the mesh MESH in it, is missing, leaving REPORT as it
#                                          was
# And the scripts that write their table themselves (run_scale.sh, run_textured.sh,
# run_size.sh) share its cells' helpers:
#   median FILE COLUMN                     the median of a column of numbers (the mean of the
#                                          middle two when even)
#   mib KIB, per_face KIB FACES            MiB with one decimal; bytes per face, whole
#   ratio A B, seconds S, thousands N      "1.23×"; 2 decimals under 10 s, else 1; 1,234,567
#   field LABEL NAME                       the number after NAME= or NAME (space) in
#                                          $work/LABEL.stdout (a run's own report)

bench_install() {
  local tool=$1
  shift
  local missing=() package
  # The library's own (libtinygltf-dev and nlohmann-json3-dev: glTF, which configuring pm
  # needs, as .ci/deps installs them), then the peers'.
  for package in g++ cmake libopenmesh-dev libcli11-dev libzstd-dev libtinygltf-dev nlohmann-json3-dev \
                 libmeshoptimizer-dev libdraco-dev zlib1g-dev "$@"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" ||
      missing+=("$package")
  done
  ((${#missing[@]})) || return 0
  echo "$tool: installing ${missing[*]}" >&2
  local sudo=""
  [[ $(id -u) -eq 0 ]] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"
}

bench_configure() {
  cmake -S "$1" -B "$2" -DCMAKE_BUILD_TYPE=Release -DPM_BUILD_BENCH=ON -DPM_BUILD_TESTS=OFF >/dev/null
}

# bench_parse_runs TOOL DEFAULT_RUNS BIG_ALLOWED ARGS...: the two below.
bench_parse_runs() {
  local tool=$1 usage="[--runs N]"
  runs=$2
  local big_allowed=$3
  shift 3
  ((big_allowed)) && usage="[--big] $usage"
  while (($#)); do
    case "$1" in
      --big) ((big_allowed)) || { echo "usage: $tool $usage" >&2; exit 2; }; big=1 ;;
      --runs) runs="${2:-}"; shift ;;
      *) echo "usage: $tool $usage" >&2; exit 2 ;;
    esac
    shift
  done
  if ! [[ "$runs" =~ ^[0-9]+$ ]] || ((runs < 5)); then
    echo "$tool: --runs must be at least 5 (each row is a median)" >&2
    exit 2
  fi
}
bench_big_and_runs() { local tool=$1; shift; bench_parse_runs "$tool" 7 1 "$@"; }
bench_runs() { local tool=$1; shift; bench_parse_runs "$tool" 5 0 "$@"; }

bench_commit() {
  local repo=$1
  shift
  local commit
  commit="$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)"
  [[ -z "$(git -C "$repo" status --porcelain -- "$@" 2>/dev/null)" ]] || commit="$commit with uncommitted changes"
  echo "$commit"
}

bench_need_meshes() {
  local need="$1${3:+/$3}"
  [[ -e "$need" ]] && return 0
  echo >&2
  echo "*** NOTE: $need is missing: there is nothing to benchmark." >&2
  echo "*** Put the test meshes in $1 (see its README.md) and run this again." >&2
  echo "*** $2 was left as it was." >&2
  exit 0
}

bench_loop_mesh() {
  local make=$1 source=$2 steps=$3 obj=$4
  if [[ ! -s "$obj" || "$source" -nt "$obj" ]]; then
    echo "making $(basename "$obj") ($(basename "$source") after $steps Loop steps)" >&2
    "$make" "$source" "$steps" "$obj" -q
  fi
}

bench_textured_mesh() {
  local repo=$1 build=$2
  local bench="$build/tests/bench" source_obj="$repo/samples/textured.obj"
  local obj="$bench/textured/textured-loop4.obj"
  mkdir -p "$bench/textured"
  if [[ ! -s "$obj" || "$source_obj" -nt "$obj" || "$bench/pm_make_big_mesh" -nt "$obj" ]]; then
    echo "making textured-loop4.obj (samples/textured.obj after 4 Loop steps)" >&2
    "$bench/pm_make_big_mesh" "$source_obj" 4 "$obj" --keep-attributes -q
    cp "$repo/samples/textured.mtl" "$bench/textured/"
  fi
  echo "$obj"
}

bench_start() {
  local tool=$1 name=$2 mesh=$3
  shift 3
  repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
  build="${PM_BENCH_BUILD:-$repo/build-bench}"
  meshes="${PM_SHARED_MESHES_DIR:-$repo/../shared/meshes}"
  report="$repo/tests/bench/$name"
  bench_install "$tool"
  bench_need_meshes "$meshes" "$report" "$mesh"
  bench_configure "$repo" "$build"
  cmake --build "$build" -j"$(nproc)" --target "$@"
}

bench_write_report() {
  trap 'rm -f "$report.tmp"' EXIT
  "$@" --out "$report.tmp" >/dev/null
  mv "$report.tmp" "$report"
  cat "$report"
}

# --- cells of a table ----------------------------------------------------------------------
median() {
  sort -g -k"$2,$2" "$1" | awk -v c="$2" '{ v[NR] = $c }
    END { if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}
mib() { awk -v k="$1" 'BEGIN { printf "%.1f", k / 1024 }'; }
per_face() { awk -v k="$1" -v f="$2" 'BEGIN { printf "%.0f", k * 1024 / f }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f×", a / b }'; }
seconds() { awk -v s="$1" 'BEGIN { printf (s < 10 ? "%.2f" : "%.1f"), s }'; }
thousands() { sed ':a;s/\B[0-9]\{3\}\>/,&/;ta' <<<"$1"; }
field() { sed -n "s/.*$2[= ]\([0-9.]*\).*/\1/p" "$work/$1.stdout" | head -1; }
