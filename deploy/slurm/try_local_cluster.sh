#!/usr/bin/env bash
# Tries deploy/slurm/pathfarm-workers.sbatch on a one-node Slurm cluster made on this
# machine, end to end:
#
#   1. installs Debian's slurm-wlm and munge with apt-get (skipped when installed);
#   2. writes a minimal slurm.conf and a fresh munge key in a temporary folder (never
#      in /etc: an existing /etc/slurm or /etc/munge, and a munged or Slurm already
#      running, are left alone: this cluster has its own socket, ports and state);
#   3. starts munged, slurmctld and slurmd (as root, in the foreground, in background);
#   4. starts a pathfarm scheduler on 127.0.0.1 with a random token;
#   5. submits the sbatch script as a job array of 2 workers (1 CPU each);
#   6. submits a tiny pt shot (Cornell box, 4 frames of 64x64 at 4 spp), waits for it
#      (with a timeout), fetches the frames and checks them against `pathfarm render`;
#   7. checks the workers ran under Slurm: squeue shows the array tasks running, the
#      scheduler lists the workers by their Slurm names, the worker processes carry
#      the job's SLURM_ variables, and both workers' logs show tasks;
#   8. submits a one-tile shot of a few seconds, cancels the job while the tile renders,
#      and checks the worker delivered that tile after Slurm's SIGTERM, both workers
#      stopped and their batch scripts exited 0; then stops everything it started (also
#      on failure: trap).
#
# Run as root (slurmd runs jobs as their submitter, and apt-get installs):
#   deploy/slurm/try_local_cluster.sh
# Environment: PATHFARM_BIN (default build/bin/pathfarm, copied to the temporary
# folder first), TRY_TIMEOUT (seconds for each wait, default 300), TRY_KEEP=1 keeps the
# temporary folder (logs, slurm.conf, frames).
#
# The sandbox it was written on (no systemd, no cgroup delegation) is why slurm.conf
# tracks processes by parent pid (proctrack/linuxproc), binds no tasks (task/none) and
# keeps no accounting (so no sacct; squeue and the workers' names show the Slurm side).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
timeout_seconds=${TRY_TIMEOUT:-300}
started_at=$(date +%s)

log() { echo "try_local_cluster: $*"; }
die() {
  echo "try_local_cluster: FAILED: $*" >&2
  exit 1
}

[ "$(id -u)" -eq 0 ] || die "run as root: it installs packages with apt-get and starts slurmd, which runs jobs as their submitter"
source_bin=${PATHFARM_BIN:-$root/build/bin/pathfarm}
[ -x "$source_bin" ] || die "no pathfarm binary at $source_bin (build it with deploy/setup.sh, or set PATHFARM_BIN)"

# --- 1. packages ------------------------------------------------------------------
packages=(slurm-wlm munge)
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2> /dev/null | grep -q "install ok installed" || missing+=("$package")
done
if ((${#missing[@]})); then
  log "installing ${missing[*]} with apt-get"
  # Their maintainer scripts would start the system's munged, slurmctld and slurmd; a
  # policy-rc.d that says no keeps them down (only made, and removed, if there is none).
  policy_made=""
  if [ ! -e /usr/sbin/policy-rc.d ]; then
    printf '#!/bin/sh\nexit 101\n' > /usr/sbin/policy-rc.d
    chmod 755 /usr/sbin/policy-rc.d
    policy_made=1
  fi
  export DEBIAN_FRONTEND=noninteractive
  install_status=0
  { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}"; } || install_status=$?
  if [ -n "$policy_made" ]; then rm -f /usr/sbin/policy-rc.d; fi
  ((install_status == 0)) || die "apt-get install ${missing[*]} failed (status $install_status)"
fi
for tool in munged slurmctld slurmd sbatch squeue scancel scontrol sinfo; do
  command -v "$tool" > /dev/null || die "$tool is missing after installing ${packages[*]}"
done

# --- 2. the temporary cluster's files ------------------------------------------------
work=$(mktemp -d /tmp/pathfarm-slurm-try.XXXXXX)
chmod 755 "$work"  # slurmstepd and the job read the binary and scripts under it
mkdir -p "$work"/{munge,ctld,slurmd,jobs,farm,bin}
chmod 700 "$work/munge"
cp "$source_bin" "$work/bin/pathfarm"
pathfarm=$work/bin/pathfarm

# Processes running this run's copy of pathfarm, other than the scheduler.
worker_pids() {
  local exe pid
  for exe in /proc/[0-9]*/exe; do
    [ "$(readlink "$exe" 2> /dev/null)" = "$pathfarm" ] || continue
    pid=${exe#/proc/}
    pid=${pid%/exe}
    [ "$pid" = "$scheduler_pid" ] || echo "$pid"
  done
}

pids=()        # daemons started here, stopped in reverse order
job=""
scheduler_pid=""
cleanup() {
  local status=$?
  set +e
  if [ -n "$job" ] && squeue -h -j "$job" 2> /dev/null | grep -q .; then
    log "cleanup: cancelling job $job"
    scancel "$job"
    for _ in $(seq 1 60); do squeue -h -j "$job" 2> /dev/null | grep -q . || break; sleep 1; done
  fi
  if [ -n "$scheduler_pid" ] && kill -0 "$scheduler_pid" 2> /dev/null; then
    kill -TERM "$scheduler_pid"
    wait "$scheduler_pid" 2> /dev/null
  fi
  local i
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    if kill -0 "${pids[i]}" 2> /dev/null; then
      kill -TERM "${pids[i]}"
      for _ in $(seq 1 50); do kill -0 "${pids[i]}" 2> /dev/null || break; sleep 0.2; done
      kill -KILL "${pids[i]}" 2> /dev/null
    fi
    wait "${pids[i]}" 2> /dev/null
  done
  # Job processes that outlived slurmd (none expected): those running this run's copy
  # of the binary, found by their executable's path (unique to this temporary folder).
  for pid in $(worker_pids); do kill -TERM "$pid" 2> /dev/null; done
  if ((status != 0)); then
    for f in "$work"/slurmctld.log "$work"/slurmd.log "$work"/munged.log "$work"/scheduler.log "$work"/jobs/*.out; do
      [ -s "$f" ] || continue
      echo "---- last lines of $f" >&2
      tail -n 15 "$f" >&2
    done
  fi
  if [ "${TRY_KEEP:-}" = 1 ]; then
    log "kept $work"
  else
    rm -rf "$work"
  fi
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# Waits until "$@" succeeds, at most timeout_seconds.
wait_for() {
  local what=$1
  shift
  local deadline=$(($(date +%s) + timeout_seconds))
  until "$@" > /dev/null 2>&1; do
    (($(date +%s) < deadline)) || die "timed out after ${timeout_seconds} s waiting for $what"
    sleep 1
  done
}

port_free() { ! (exec 3<> "/dev/tcp/127.0.0.1/$1") 2> /dev/null; }
free_port() {
  local port=$1
  while ! port_free "$port"; do port=$((port + 1)); done
  echo "$port"
}

host=$(hostname -s)
cpus=$(nproc)
ctld_port=$(free_port 16817)
slurmd_port=$(free_port $((ctld_port + 1)))

# munge: a key of its own and a socket in the temporary folder.
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
socket=$work/munge/munge.socket

export SLURM_CONF=$work/slurm.conf
cat > "$SLURM_CONF" <<CONF
# A one-node cluster for trying pathfarm-workers.sbatch (written by try_local_cluster.sh).
ClusterName=pathfarmtry
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$work/ctld
SlurmdSpoolDir=$work/slurmd
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
# No systemd and no cgroup delegation here: track job processes by parent pid, bind nothing.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
# Several jobs share the node, one CPU each.
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
# SIGTERM, then SIGKILL this many seconds later: the time a worker has to deliver its task.
KillWait=30
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=try Nodes=$host Default=YES MaxTime=60 State=UP
CONF

# --- 3. daemons -----------------------------------------------------------------------
log "starting munged, slurmctld (port $ctld_port) and slurmd (port $slurmd_port) with $SLURM_CONF"
munged --foreground --force --socket="$socket" --key-file="$work/munge/munge.key" \
  --pid-file="$work/munge/munged.pid" --seed-file="$work/munge/munged.seed" \
  --log-file="$work/munged.log" > "$work/munged.out" 2>&1 &
pids+=($!)
wait_for "munged's socket" test -S "$socket"
munge --socket="$socket" -n | unmunge --socket="$socket" > /dev/null || die "munge cannot encode and decode a credential"

slurmctld -D -f "$SLURM_CONF" > "$work/slurmctld.out" 2>&1 &
pids+=($!)
wait_for "slurmctld to answer" scontrol ping
slurmd -D -f "$SLURM_CONF" -N "$host" > "$work/slurmd.out" 2>&1 &
pids+=($!)
node_idle() { sinfo -h -n "$host" -o %t | grep -Eq '^(idle|mix|alloc)'; }
wait_for "node $host to be idle" node_idle
log "slurm is up: $(sinfo -h -o '%P %D %t %C' | head -1) (partition nodes state cpus A/I/O/T)"

# --- 4. the pathfarm scheduler ---------------------------------------------------------
head -c 32 /dev/urandom | od -An -tx1 | tr -d ' \n' > "$work/token"
chmod 600 "$work/token"
export PATHFARM_TOKEN_FILE=$work/token
"$pathfarm" scheduler --listen 127.0.0.1:0 --port-file "$work/farm/port" --db "$work/farm/farm.db" \
  --store "$work/farm/chunks" --token-file "$work/token" > "$work/scheduler.log" 2>&1 &
scheduler_pid=$!
wait_for "the pathfarm scheduler's port file" test -s "$work/farm/port"
address=127.0.0.1:$(cat "$work/farm/port")
log "pathfarm scheduler on $address (token in $work/token)"

# --- 5. the workers, a Slurm job array -------------------------------------------------
job=$(sbatch --parsable --array=0-1 --cpus-per-task=1 --time=30 --chdir="$work/jobs" \
  --output="$work/jobs/worker-%A_%a.out" --export="ALL,PATHFARM_BIN=$pathfarm" \
  "$here/pathfarm-workers.sbatch" "$address" "$work/token")
job=${job%%;*}
log "submitted job array $job"
two_running() { [ "$(squeue -h -j "$job" -t RUNNING -o %i | wc -l)" -eq 2 ]; }
wait_for "both array tasks of job $job to run" two_running
squeue -j "$job" -o '%.12i %.16j %.8T %.10M %.6C %R'
two_registered() { [ "$("$pathfarm" workers --scheduler "$address" | grep -c "slurm-${job}_[01]@$host")" -eq 2 ]; }
wait_for "both Slurm workers to register with the scheduler" two_registered
"$pathfarm" workers --scheduler "$address"

# The worker processes are children of Slurm's job steps: their environment says so.
for pid in $(worker_pids); do
  tr '\0' '\n' < "/proc/$pid/environ" | grep -q "^SLURM_ARRAY_JOB_ID=$job$" ||
    die "worker process $pid does not carry SLURM_ARRAY_JOB_ID=$job"
done
log "worker processes: $(worker_pids | wc -l), each with SLURM_ARRAY_JOB_ID=$job in its environment"

# `pathfarm submit` prints the shot id on a line of its own (log lines may come too).
submit() {
  local id
  id=$("$pathfarm" submit --scheduler "$address" "$1" | grep -E '^[0-9]+$' | tail -n 1) || true
  [ -n "$id" ] || die "pathfarm submit $1 printed no shot id"
  echo "$id"
}

# --- 6. a tiny shot --------------------------------------------------------------------
cat > "$work/shot.json" <<JSON
{"name": "slurm-try", "scene": "$root/scenes/cornell/scene.json", "frames": {"start": 0, "end": 3},
 "resolution": [64, 64], "spp": 4, "max_depth": 4, "tile": 32, "pipeline": "pt"}
JSON
shot=$(submit "$work/shot.json")
log "submitted shot $shot (4 frames, 64x64, 4 spp, 16 tiles)"
timeout "$timeout_seconds" "$pathfarm" watch --scheduler "$address" "$shot" > "$work/watch.log" 2>&1 ||
  die "shot $shot did not finish within ${timeout_seconds} s: $(tail -n 3 "$work/watch.log")"
"$pathfarm" status --scheduler "$address" "$shot" | head -1
"$pathfarm" fetch --scheduler "$address" "$shot" --out "$work/frames"
"$pathfarm" render "$root/scenes/cornell/scene.json" --frames 0:3 --res 64x64 --spp 4 --max-depth 4 --threads 1 \
  --out "$work/render" > "$work/render.log" 2>&1 || die "pathfarm render failed: $(tail -n 3 "$work/render.log")"
for frame in 0 1 2 3; do
  f=$(printf 'frame_%04d.exr' "$frame")
  [ -s "$work/frames/$f" ] || die "frame $f was not written"
  cmp -s "$work/frames/$f" "$work/render/$f" || die "$f from the Slurm workers differs from pathfarm render"
done
log "4 frames fetched, byte-identical to pathfarm render"
for index in 0 1; do
  out=$work/jobs/worker-${job}_$index.out
  tasks=$(grep -c ': done' "$out" || true)
  ((tasks > 0)) || die "array task $index did no task: $(tail -n 5 "$out")"
  log "array task $index (worker slurm-${job}_$index@$host) did $tasks tasks"
done

# --- 7. cancel in the middle of a task: the worker delivers it, then stops -------------
cat > "$work/long.json" <<JSON
{"name": "slurm-cancel", "scene": "$root/scenes/cornell/scene.json", "frames": {"start": 0, "end": 0},
 "resolution": [64, 64], "spp": 1024, "max_depth": 4, "tile": 64, "pipeline": "pt"}
JSON
long=$(submit "$work/long.json")
one_running() { "$pathfarm" status --scheduler "$address" "$long" | head -1 | grep -q ' 1 running'; }
wait_for "shot $long's one tile to be leased" one_running
log "shot $long (one 64x64 tile at 1024 spp) is rendering; scancel $job"
scancel "$job"
gone() { ! squeue -h -j "$job" | grep -q .; }
wait_for "job $job to end after scancel" gone
for index in 0 1; do
  out=$work/jobs/worker-${job}_$index.out
  grep -q "worker [0-9]* stopped" "$out" || die "array task $index: the worker did not stop cleanly: $(tail -n 5 "$out")"
  grep -q "exited with status 0" "$out" || die "array task $index: the batch script did not exit 0: $(tail -n 5 "$out")"
done
"$pathfarm" status --scheduler "$address" "$long" | head -1
tile_done() { "$pathfarm" status --scheduler "$address" "$long" | head -1 | grep -q ': 1/2 tasks done'; }
tile_done || die "the tile in hand when the job was cancelled was not delivered"
# In the log of the worker that held it: Slurm's cancel notice, then the tile done, then stopped.
delivered_after_cancel() {
  awk '/CANCELLED AT/ { cancelled = 1 } cancelled && /task [0-9]+: done/ { done = 1 }
       done && /worker [0-9]+ stopped/ { ok = 1 } END { exit !ok }' "$1"
}
held=""
for index in 0 1; do
  if delivered_after_cancel "$work/jobs/worker-${job}_$index.out"; then held=$index; fi
done
[ -n "$held" ] || die "no worker log shows a task done between Slurm's cancel and the worker's stop"
sed -n '/CANCELLED AT/,$p' "$work/jobs/worker-${job}_$held.out" | sed "s/^/  array task $held: /"
log "scancel: the worker holding a tile finished and delivered it after SIGTERM; both workers stopped, batch scripts exited 0"
job=""
log "PASSED in $(($(date +%s) - started_at)) s"
