#!/usr/bin/env bash
# The README's many-machines recipes (section "Many files"), run as printed. Each recipe is the
# text between "<!-- recipe: NAME" and "<!-- /recipe -->" in README.md; the test changes only
# /data/assets (to a temporary corpus of valid and invalid meshes) and, for GNU parallel,
# the ssh hosts (to as many -j slots on this machine: no ssh server is at hand here).
#
#   run.sh slurm SOURCE_DIR PMENC     starts munged, slurmctld and slurmd itself, with a
#       configuration of its own in a temporary directory (loopback addresses, free ports),
#       submits the job array (round "clean"), then again with one array task cancelled by
#       scancel while it converts and the array submitted once more (round "resumed").
#   run.sh parallel SOURCE_DIR PMENC  runs the GNU parallel recipe (round "clean"), then the
#       same command again (round "rerun": everything is there already).
#
# After each round: every valid input has its .pm, byte-identical to a local pmenc run, and
# nothing else is in out/ (no temporary, nothing for an invalid input); each input has one
# line in the last run's JSON Lines, in the log of the shard `pmenc --dry-run --shard I/N`
# gives it, invalid inputs as failed; over the round's runs each valid input was converted
# once ("ok" once, "skipped" after). At the end no process of this test is left: the daemons
# it started are stopped by their ids, and any process still working in its temporary
# directory is named and fails the test.
#
# Every daemon runs as the user running the test (root or not), which is all the jobs need.
# Exits 77 (CTest's SKIP_RETURN_CODE) after a SKIP line when the engine is not installed or
# cannot start here (a sandbox without sockets or /proc): skipped, never passed.
set -euo pipefail
mode=$1 source=$2 pmenc=$3
readonly skip_code=77

say() { echo "recipes/$mode [${SECONDS}s]: $*" >&2; }
failure=""
fail() {
  failure=$*
  say "FAIL: $*"
  exit 1
}
skip() {
  say "********************************************************************"
  say "SKIP: $*"
  say "********************************************************************"
  exit "$skip_code"
}

# A job or client would otherwise read the variables of a Slurm job this test may run in.
while read -r name; do unset "$name"; done < <(compgen -e | grep -E '^(SLURM|SBATCH|SQUEUE|SCANCEL|SINFO|SRUN|SALLOC)_' || true)
export PATH="$(cd "$(dirname "$pmenc")" && pwd):$PATH:/usr/sbin:/sbin"

need() {  # PACKAGE PROGRAM...
  local package=$1
  shift
  for program in "$@"; do
    command -v "$program" >/dev/null ||
      skip "$program is not installed (Debian package $package; bash .ci/deps --test installs it)"
  done
}
case $mode in
  slurm)
    need slurm-wlm slurmctld slurmd sbatch squeue scancel sinfo
    need munge munged munge unmunge ;;
  parallel) need parallel parallel ;;
  *) fail "usage: run.sh slurm|parallel SOURCE_DIR PMENC" ;;
esac

work=$(mktemp -d "${TMPDIR:-/tmp}/pm-recipes.XXXXXX")
chmod 711 "$work"  # munged wants its socket's directories searchable by all
assets=$work/assets
started=()  # pids of the daemons this test started, the last started first

# Processes whose working directory, executable or open files are in $work: job steps, pmenc.
processes_in_work() {
  find /proc/[0-9]*/cwd /proc/[0-9]*/exe /proc/[0-9]*/fd -maxdepth 1 \
    \( -lname "$work" -o -lname "$work/*" \) 2>/dev/null |
    cut -d/ -f3 | sort -u | grep -v -x -e "$$" -e "$BASHPID" || true
}

stop() {  # PID: TERM, then KILL after 10 s
  local pid=$1
  kill -TERM "$pid" 2>/dev/null || return 0
  for _ in $(seq 100); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  kill -KILL "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
}

cleanup() {
  local status=$? pid leftovers
  cd /
  if [[ -n ${slurmctld_pid:-} ]] && kill -0 "$slurmctld_pid" 2>/dev/null; then
    scancel --quiet --user="$(id -un)" 2>/dev/null || true
    for _ in $(seq 100); do
      [[ -z "$(squeue -h -o %i 2>/dev/null)" ]] && break
      sleep 0.1
    done
  fi
  for pid in "${started[@]}"; do stop "$pid"; done
  leftovers=$(processes_in_work)
  if [[ -n $leftovers ]]; then
    say "FAIL: processes of this test still running, now killed:"
    ps -o pid,args -p "$(echo $leftovers | tr ' ' ,)" >&2 || true
    kill -KILL $leftovers 2>/dev/null || true
    ((status == 0 || status == skip_code)) && status=1
  fi
  if ((status != 0 && status != skip_code)); then
    for log in "$work"/slurm/log/*.log "$work"/parallel.err; do
      [[ -s $log ]] && { say "--- last lines of $log:"; tail -n 10 "$log" >&2; }
    done
    [[ -n $failure ]] && say "FAIL: $failure"
  fi
  ((status != 0)) || say "PASS: no process of this test left running"
  rm -rf "$work"
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# The recipe NAME from README.md: its indented code block between the marks, unindented.
readme_recipe() {
  local text
  text=$(awk -v mark="<!-- recipe: $1 " '
    index($0, mark) == 1 { inside = 1; next }
    inside && index($0, "<!-- /recipe -->") == 1 { exit }
    inside { print }' "$source/README.md")
  [[ -n "${text//[[:space:]]/}" ]] || fail "README.md has no recipe marked '<!-- recipe: $1 ...'"
  if grep -v '^$' <<<"$text" | grep -qv '^    '; then
    fail "README.md's recipe '$1' is not one indented code block"
  fi
  sed -e '/^$/d' -e 's/^    //' <<<"$text"
}

# --- The corpus: the samples, an OFF mesh, four invalid inputs (and, for Slurm, a larger
# --- mesh in a shard with small ones, so that a task can be cancelled half done).

declare -A shard_of valid  # input path as pmenc lists it -> its shard; -> 1 when valid
shards=0

map_shards() {
  shard_of=()
  local i input
  for ((i = 1; i <= shards; i++)); do
    while IFS=$'\t' read -r input _; do shard_of[$input]=$i; done < <(
      cd "$assets" && pmenc -r corpus --out-dir out --dry-run --shard "$i/$shards")
  done
}

make_corpus() {
  mkdir -p "$assets/corpus/samples" "$assets/corpus/broken"
  local name
  for name in sphere terrain_holes block_features polygons nonmanifold textured; do
    cp "$source/samples/$name.obj" "$assets/corpus/samples/"
  done
  cp "$source/samples/textured.mtl" "$assets/corpus/samples/"
  printf '%s\n' OFF '6 8 0' '1 0 0' '-1 0 0' '0 1 0' '0 -1 0' '0 0 1' '0 0 -1' \
    '3 0 2 4' '3 2 1 4' '3 1 3 4' '3 3 0 4' '3 2 0 5' '3 1 2 5' '3 3 1 5' '3 0 3 5' \
    >"$assets/corpus/samples/octahedron.off"
  printf '%s\n' 'v 0 0 0' 'v 1 0 0' 'v 0 1 0' 'f 1 2 4' >"$assets/corpus/broken/face_out_of_range.obj"
  : >"$assets/corpus/broken/empty.obj"
  printf '%s\n' ply 'format ascii 1.0' 'element vertex 8' 'property float x' 'property float y' \
    'property float z' 'element face 12' 'property list uchar int vertex_indices' end_header \
    '0 0 0' '1 0 0' >"$assets/corpus/broken/truncated.ply"
  echo 'not a mesh' >"$assets/corpus/broken/not_a_mesh.stl"
}

# A 160 x 160 height field (50,562 faces: a second or two of pmenc, against a few hundredths
# for the samples), placed under a name whose shard holds some of the small inputs too.
add_large_mesh() {
  mkdir -p "$assets/corpus/large"
  local k chosen=""
  for k in $(seq 64); do : >"$assets/corpus/large/grid_$k.obj"; done
  map_shards
  for k in $(seq 64); do
    local shard=${shard_of[corpus/large/grid_$k.obj]}
    for input in "${!shard_of[@]}"; do
      if [[ $input == corpus/samples/* && ${shard_of[$input]} == "$shard" ]]; then
        chosen=$k
        break 2
      fi
    done
  done
  [[ -n $chosen ]] || fail "no shard name for the large mesh shares a shard with a sample"
  for k in $(seq 64); do [[ $k == "$chosen" ]] || rm "$assets/corpus/large/grid_$k.obj"; done
  large=corpus/large/grid_$chosen.obj
  awk -v n=160 'BEGIN {
    for (j = 0; j < n; j++) for (i = 0; i < n; i++)
      printf "v %d %d %.4f\n", i, j, 3 * sin(i * 0.21) * cos(j * 0.17) + sin(i * j * 0.003)
    for (j = 0; j < n - 1; j++) for (i = 0; i < n - 1; i++) {
      a = j * n + i + 1
      printf "f %d %d %d\nf %d %d %d\n", a, a + 1, a + n + 1, a, a + n + 1, a + n
    }
  }' >"$assets/$large"
}

# The local run the recipes must match, and which inputs are valid (those it converts).
convert_locally() {
  local code=0 input
  (cd "$assets" && pmenc -r corpus --out-dir "$work/ref" -q 2>/dev/null) || code=$?
  ((code == 8)) || fail "local pmenc over the corpus: exit code $code, 8 expected (some inputs invalid)"
  map_shards
  valid=()
  for input in "${!shard_of[@]}"; do
    [[ -f "$work/ref/${input%.*}.pm" ]] && valid[$input]=1
    if [[ $input == corpus/broken/* ]]; then
      [[ -z ${valid[$input]:-} ]] || fail "local pmenc converted the invalid $input"
    else
      [[ -n ${valid[$input]:-} ]] || fail "local pmenc did not convert the valid $input"
    fi
  done
}

# --- Checks after a round.

check_outputs() {  # ROUND: out/ holds ref/'s files, byte for byte, and nothing else
  local round=$1 temporaries file
  temporaries=$(cd "$assets" && find out -name '*.tmp.*' 2>/dev/null)
  [[ -z $temporaries ]] || fail "$round: temporaries left: $temporaries"
  diff <(cd "$work/ref" && find . -type f | sort) <(cd "$assets/out" && find . -type f | sort) >&2 ||
    fail "$round: out/ is not the local run's list of outputs (< missing, > extra)"
  while read -r file; do
    cmp -s "$work/ref/$file" "$assets/out/$file" || fail "$round: out/$file differs from the local run's"
  done < <(cd "$work/ref" && find . -type f)
}

check_logs() {  # ROUND LOG_DIR...: the runs' logs, the last one's in full
  local round=$1
  shift
  local final=${*: -1} i line input status file dir
  local -A lines_of=() converted=()
  local json='^\{"input":"([^"]*)",.*,"status":"([a-z]*)",'
  for ((i = 1; i <= shards; i++)); do
    [[ -f $final/shard$i.jsonl ]] || fail "$round: no log/shard$i.jsonl: array task or job $i did not run"
    while IFS= read -r line; do
      [[ $line =~ $json ]] || fail "$round: shard$i.jsonl: not a pmenc JSON line: $line"
      input=${BASH_REMATCH[1]} status=${BASH_REMATCH[2]}
      [[ ${shard_of[$input]:-} == "$i" ]] ||
        fail "$round: $input is in shard$i.jsonl, pmenc --dry-run puts it in shard ${shard_of[$input]:-none}"
      lines_of[$input]=$((${lines_of[$input]:-0} + 1))
      if [[ -n ${valid[$input]:-} ]]; then
        [[ $status == ok || $status == skipped ]] || fail "$round: the valid $input is $status: $line"
      else
        [[ $status == failed && $line != *'"error_code":null'* ]] ||
          fail "$round: the invalid $input is not reported as failed: $line"
      fi
    done <"$final/shard$i.jsonl"
  done
  for dir in "$@"; do
    for file in "$dir"/shard*.jsonl; do
      [[ -f $file ]] || continue
      while IFS= read -r line; do
        [[ $line =~ $json && ${BASH_REMATCH[2]} == ok ]] &&
          converted[${BASH_REMATCH[1]}]=$((${converted[${BASH_REMATCH[1]}]:-0} + 1))
      done <"$file"
    done
  done
  for input in "${!shard_of[@]}"; do
    [[ ${lines_of[$input]:-0} == 1 ]] ||
      fail "$round: $input has ${lines_of[$input]:-0} lines in the last run's logs, 1 expected"
    [[ -z ${valid[$input]:-} || ${converted[$input]:-0} == 1 ]] ||
      fail "$round: $input was converted ${converted[$input]:-0} times over the round's runs, once expected"
  done
  say "$round: ${#shard_of[@]} inputs (${#valid[@]} valid) in $shards shards: outputs identical to the local run, logs complete"
}

# --- GNU parallel.

run_parallel() {
  local recipe hosts slots expected_failures=0 code i input
  recipe=$(readme_recipe parallel)
  [[ $recipe == */data/assets* ]] || fail "the parallel recipe no longer works in /data/assets"
  hosts=$(grep -o -- '--sshlogin [^ ]*' <<<"$recipe" | cut -d' ' -f2)
  [[ -n $hosts ]] || fail "the parallel recipe has no --sshlogin HOSTS"
  slots=$(tr ',' '\n' <<<"$hosts" | grep -c .)
  recipe=${recipe//\/data\/assets/$assets}
  recipe=${recipe/--sshlogin $hosts/-j $slots}
  shards=$(grep -o -- '--shard [^ ]*' <<<"$recipe" | grep -o '/[0-9]*' | tr -d /)
  [[ -n $shards ]] || fail "the parallel recipe has no --shard I/N"
  [[ "$(sed -n 's/.* ::: //p' <<<"$recipe")" == "$(seq -s ' ' "$shards")" ]] ||
    fail "the parallel recipe's arguments are not 1 to $shards, one job per shard"
  make_corpus
  convert_locally
  # GNU parallel's exit code is its number of failed jobs: the shards with an invalid input.
  for ((i = 1; i <= shards; i++)); do
    for input in "${!shard_of[@]}"; do
      if [[ ${shard_of[$input]} == "$i" && -z ${valid[$input]:-} ]]; then
        expected_failures=$((expected_failures + 1))
        break
      fi
    done
  done
  say "running, in $work: $recipe"
  for round in clean rerun; do
    code=0
    (cd "$work" && bash -c "$recipe") 2>>"$work/parallel.err" || code=$?
    ((code == expected_failures)) ||
      fail "$round: parallel exited with $code, $expected_failures expected (the shards with an invalid input)"
    check_outputs "$round"
    mkdir -p "$work/logs"
    cp -r "$assets/log" "$work/logs/$round"
  done
  check_logs clean "$work/logs/clean"
  check_logs "clean + rerun" "$work/logs/clean" "$work/logs/rerun"
}

# --- Slurm.

free_port() {  # one nobody answers on, not $1
  local port
  while :; do
    port=$((20000 + RANDOM % 40000))
    [[ $port == "${1:-}" ]] && continue
    (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null || { echo "$port"; return; }
  done
}

start_slurm() {
  local dir=$work/slurm user host
  user=$(id -un)
  host=$(uname -n)
  host=${host%%.*}
  mkdir -p "$dir/state" "$dir/spool" "$dir/log"
  # munged with a key and a socket of its own.
  mkdir -m 711 "$dir/munge"
  head -c 1024 /dev/urandom >"$dir/munge/munge.key"
  chmod 400 "$dir/munge/munge.key"
  munged -F --key-file="$dir/munge/munge.key" --socket="$dir/munge/socket" \
    --pid-file="$dir/munge/munged.pid" --seed-file="$dir/munge/seed" \
    --log-file="$dir/log/munged.log" >"$dir/log/munged.out" 2>&1 &
  started=("$!" "${started[@]}")
  for _ in $(seq 100); do
    munge -n -S "$dir/munge/socket" 2>/dev/null | unmunge -S "$dir/munge/socket" >/dev/null 2>&1 && break
    kill -0 "${started[0]}" 2>/dev/null || skip "munged cannot start here: $(tail -n 2 "$dir/log/munged.out")"
    sleep 0.1
  done
  : >"$dir/plugstack.conf"
  export SLURM_CONF=$dir/slurm.conf
  cat >"$SLURM_CONF" <<EOF
ClusterName=pmrecipes
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
PlugStackConfig=$dir/plugstack.conf
MailProg=/bin/true
DebugFlags=NO_CONF_HASH
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SwitchType=switch/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
# The node claims the CPUs for all the array's tasks at once, however many this machine has.
SlurmdParameters=config_overrides
ReturnToService=2
KillWait=5
NodeName=pmnode NodeHostname=localhost NodeAddr=127.0.0.1 CPUs=$((shards * ${cpus_per_task:-1})) State=UNKNOWN
PartitionName=pm Nodes=pmnode Default=YES MaxTime=INFINITE State=UP
EOF
  slurmctld -D -i -f "$SLURM_CONF" >"$dir/log/slurmctld.out" 2>&1 &
  slurmctld_pid=$!
  started=("$!" "${started[@]}")
  slurmd -D -N pmnode -f "$SLURM_CONF" >"$dir/log/slurmd.out" 2>&1 &
  started=("$!" "${started[@]}")
  for _ in $(seq 300); do
    [[ "$(sinfo -h -o %T 2>/dev/null)" == idle ]] && return
    for pid in "${started[@]}"; do
      kill -0 "$pid" 2>/dev/null ||
        skip "Slurm cannot start here: $(ps -o args= -p "$pid" 2>/dev/null | cut -c1-20) ended: $(tail -n 3 "$dir"/log/*.out | tr '\n' ' ')"
    done
    sleep 0.1
  done
  skip "Slurm's node did not come up in 30 s: $(tail -n 3 "$dir"/log/*.out | tr '\n' ' ')"
}

submit() {  # prints the job id
  local out
  out=$(cd "$work/submit" && sbatch --parsable convert.sh) || fail "sbatch convert.sh failed"
  echo "${out%%;*}"
}

wait_for_queue() {  # until no job is left (5 minutes at most)
  for _ in $(seq 3000); do
    [[ -z "$(squeue -h -o %i)" ]] && return
    sleep 0.1
  done
  squeue >&2
  fail "the job array did not end in 5 minutes"
}

run_slurm() {
  local recipe job task i
  recipe=$(readme_recipe slurm)
  cpus_per_task=$(sed -n 's/^#SBATCH --cpus-per-task=\([0-9]*\).*/\1/p' <<<"$recipe")
  [[ $recipe == */data/assets* ]] || fail "the Slurm recipe no longer works in /data/assets"
  shards=$(grep -o -- '--shard [^ ]*' <<<"$recipe" | grep -o '/[0-9]*' | tr -d /)
  [[ -n $shards ]] || fail "the Slurm recipe has no --shard I/N"
  [[ "$(sed -n 's/^#SBATCH --array=//p' <<<"$recipe")" == "1-$shards" ]] ||
    fail "the Slurm recipe's --array is not 1-$shards, one task per shard"
  mkdir -p "$work/submit"
  echo "${recipe//\/data\/assets/$assets}" >"$work/submit/convert.sh"
  make_corpus
  add_large_mesh
  convert_locally
  task=${shard_of[$large]}
  start_slurm
  say "Slurm up (slurmctld, slurmd, munged: pids ${started[*]}); job array: $(grep -c . "$work/submit/convert.sh") lines of README.md"

  submit >/dev/null
  wait_for_queue
  check_outputs clean
  check_logs clean "$assets/log"

  rm -rf "$assets/out" "$assets/log" "$work/submit"/slurm-*.out
  job=$(submit)
  # Cancel task $task once it has converted a small input, while it converts the large one.
  for i in $(seq 3000); do
    [[ -s $assets/log/shard$task.jsonl ]] && break
    ((i % 20)) || [[ -n "$(squeue -h -o %i)" ]] || fail "the job array ended before task $task wrote its log"
    sleep 0.05
  done
  scancel "${job}_$task"
  wait_for_queue
  [[ ! -e $assets/out/${large%.*}.pm && -s $assets/log/shard$task.jsonl ]] ||
    fail "scancel did not cut array task $task half way (its large mesh was converted already)"
  mkdir -p "$work/logs"
  mv "$assets/log" "$work/logs/cancelled"
  submit >/dev/null
  wait_for_queue
  check_outputs resumed
  check_logs "cancelled + resumed" "$work/logs/cancelled" "$assets/log"
}

case $mode in
  slurm) run_slurm ;;
  parallel) run_parallel ;;
esac
