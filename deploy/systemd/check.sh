#!/usr/bin/env bash
# Checks deploy/systemd/ as far as a machine whose PID 1 is not systemd allows:
#
#   1. install.sh --dry-run changes nothing; install.sh --root TMP --prefix /opt/pathfarm
#      installs the binary, both units (ExecStart following --prefix), the sysusers file,
#      the user and group in TMP/etc, the settings and a token (0640);
#   2. `systemd-analyze verify --root TMP` of the scheduler and of worker instance 1
#      prints nothing (its warnings, such as an unknown key, fail this check too), and
#      `systemd-analyze security --offline` prints both units' exposure;
#   3. runs the units' ExecStart lines as systemd would expand them (expand_execstart.py:
#      specifiers, the environment files, ${VAR} and $VAR) in TMP: a scheduler on
#      127.0.0.1 and worker instances 1 and 2 (2 with its own worker-2.env giving it a
#      tag), submits a tiny shot and a shot requiring the tag, checks the frames and that
#      only worker 2 took the tagged shot, then stops them all with SIGTERM (as systemctl
#      stop does) and checks they exit 0.
#
# Not checked here (no systemd as PID 1): that systemd starts the units, the sandboxing
# itself (ProtectSystem= and friends), the `pathfarm` user's permissions (step 3 runs as
# the calling user), Restart=, StateDirectory=/CacheDirectory= creation. The TLS and
# worker-token settings stay empty, as in pathfarm.env.example (the units then pass empty
# --worker-token-file, --tls-cert, --tls-key and worker --token-file arguments); a farm
# with them is what tests/farm/farm_tls_test.cpp and farm_token_test.cpp run.
#
# Usage: deploy/systemd/check.sh   (PATHFARM_BIN: the binary, default build/bin/pathfarm,
# copied first; installs the `systemd` package with apt-get if systemd-analyze is missing)
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root_tree=$(cd "$here/../.." && pwd)
fail() {
  echo "systemd check: FAILED: $*" >&2
  exit 1
}
log() { echo "systemd check: $*"; }

source_bin=${PATHFARM_BIN:-$root_tree/build/bin/pathfarm}
[ -x "$source_bin" ] || fail "no pathfarm binary at $source_bin (build it, or set PATHFARM_BIN)"
if ! command -v systemd-analyze > /dev/null; then
  [ "$(id -u)" -eq 0 ] || fail "systemd-analyze is missing: apt-get install systemd (as root)"
  log "installing Debian's systemd package for systemd-analyze"
  DEBIAN_FRONTEND=noninteractive apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends systemd
fi
python=$(command -v python3) || fail "python3 is needed to expand the units' command lines"

tmp=$(mktemp -d /tmp/pathfarm-systemd-check.XXXXXX)
pids=()
cleanup() {
  local status=$? pid
  set +e
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2> /dev/null; done
  for pid in "${pids[@]}"; do wait "$pid" 2> /dev/null; done
  if ((status != 0)); then
    for f in "$tmp"/*.log; do [ -s "$f" ] && { echo "---- $f" >&2; tail -n 10 "$f" >&2; }; done
  fi
  rm -rf "$tmp"
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM
cp "$source_bin" "$tmp/pathfarm"

# --- 1. install.sh ----------------------------------------------------------------------
"$here/install.sh" --dry-run --binary "$tmp/pathfarm" > "$tmp/dry-run.out"
grep -q '^+ install -m 755 .* /usr/local/bin/pathfarm$' "$tmp/dry-run.out" || fail "dry run: $(cat "$tmp/dry-run.out")"
[ ! -e /etc/pathfarm ] || [ -n "$(ls -A /etc/pathfarm 2> /dev/null)" ] || fail "the dry run made /etc/pathfarm"

root=$tmp/root
mkdir -p "$root"
prefix=/opt/pathfarm
"$here/install.sh" --root "$root" --prefix "$prefix" --binary "$tmp/pathfarm" > "$tmp/install.log" 2>&1 ||
  fail "install.sh --root failed: $(cat "$tmp/install.log")"
for f in "$prefix/bin/pathfarm" /etc/systemd/system/pathfarm-scheduler.service /etc/systemd/system/pathfarm-worker@.service \
  /etc/sysusers.d/pathfarm.conf /etc/pathfarm/pathfarm.env /etc/pathfarm/token; do
  [ -s "$root$f" ] || fail "install.sh did not install $f"
done
[ "$(stat -c %a "$root/etc/pathfarm/token")" = 640 ] || fail "the token is not mode 0640"
[ "$(wc -c < "$root/etc/pathfarm/token")" -eq 64 ] || fail "the token is not 64 hex digits"
grep -q "^ExecStart=$prefix/bin/pathfarm scheduler " "$root/etc/systemd/system/pathfarm-scheduler.service" ||
  fail "ExecStart does not follow --prefix"
if command -v systemd-sysusers > /dev/null; then
  grep -q '^pathfarm:x:[0-9]*:[0-9]*:.*:/var/lib/pathfarm:' "$root/etc/passwd" || fail "no pathfarm user in $root/etc/passwd"
fi
token_before=$(cat "$root/etc/pathfarm/token")
"$here/install.sh" --root "$root" --prefix "$prefix" --binary "$tmp/pathfarm" > "$tmp/install2.log" 2>&1
[ "$(cat "$root/etc/pathfarm/token")" = "$token_before" ] || fail "a second install replaced the token"
grep -q "keeping .*/pathfarm.env" "$tmp/install2.log" || fail "a second install did not keep the settings"
log "install.sh: dry run, install into $root (prefix $prefix) and a second install keeping settings and token: ok"

# --- 2. systemd-analyze --------------------------------------------------------------------
# verify --root resolves the units' dependencies (sysinit.target, ...) inside the root:
# give it the host's unit folder. The binary is checked at its installed path there.
mkdir -p "$root/usr/lib/systemd"
cp -a /lib/systemd/system "$root/usr/lib/systemd/"
units=(pathfarm-scheduler.service pathfarm-worker@1.service)
(cd "$tmp" && systemd-analyze verify --man=no --root="$root" "${units[@]}") > "$tmp/verify.out" 2>&1 ||
  fail "systemd-analyze verify: $(cat "$tmp/verify.out")"
[ ! -s "$tmp/verify.out" ] || fail "systemd-analyze verify warned: $(cat "$tmp/verify.out")"
log "systemd-analyze verify --root: ${units[*]}: no errors, no warnings"
for unit in "${units[@]}"; do
  systemd-analyze security --offline=true --root="$root" "$unit" 2>&1 | grep 'Overall exposure' | sed 's/^→ /  /' || true
done

# --- 3. the command lines, run ---------------------------------------------------------------
port_free() { ! (exec 3<> "/dev/tcp/127.0.0.1/$1") 2> /dev/null; }
port=17700
while ! port_free "$port" || ! port_free $((port + 1)); do port=$((port + 2)); done
# The installed settings, pointed at this check's ports and token; threads 1 (2 cores).
sed -e "s|^PATHFARM_LISTEN=.*|PATHFARM_LISTEN=127.0.0.1:$port|" \
  -e "s|^PATHFARM_SCHEDULER=.*|PATHFARM_SCHEDULER=127.0.0.1:$port|" \
  -e "s|^PATHFARM_HTTP=.*|PATHFARM_HTTP=127.0.0.1:$((port + 1))|" \
  -e "s|^PATHFARM_TOKEN_FILE=.*|PATHFARM_TOKEN_FILE=$root/etc/pathfarm/token|" \
  -e "s|^PATHFARM_THREADS=.*|PATHFARM_THREADS=1|" "$root/etc/pathfarm/pathfarm.env" > "$tmp/pathfarm.env"
echo "PATHFARM_WORKER_OPTIONS=--tags=big" > "$tmp/worker-2.env"
host=$(hostname)
state=$tmp/var/lib
cache=$tmp/var/cache
mkdir -p "$state/pathfarm" "$cache/pathfarm/worker-1" "$cache/pathfarm/worker-2"  # StateDirectory=, CacheDirectory=

# The environment a unit's process gets: its EnvironmentFile= lines, nothing else of ours.
start_unit() {
  local unit=$1 instance=$2 log=$3
  shift 3
  local argv=()
  mapfile -d '' argv < <("$python" "$here/expand_execstart.py" "$root/etc/systemd/system/$unit" --instance "$instance" \
    --host "$host" --state "$state" --cache "$cache" --root "$root" "$@")
  ((${#argv[@]} > 1)) || fail "could not expand $unit's ExecStart"
  echo "${argv[*]}" > "$log"
  env -i PATH=/usr/bin:/bin PATHFARM_TOKEN_FILE="$(sed -n 's/^PATHFARM_TOKEN_FILE=//p' "$tmp/pathfarm.env")" \
    "${argv[@]}" >> "$log" 2>&1 &
  pids+=($!)
}
start_unit pathfarm-scheduler.service "" "$tmp/scheduler.log" --env "$tmp/pathfarm.env"
scheduler_pid=${pids[-1]}
log "scheduler: $(head -1 "$tmp/scheduler.log")"
start_unit pathfarm-worker@.service 1 "$tmp/worker-1.log" --env "$tmp/pathfarm.env"
start_unit pathfarm-worker@.service 2 "$tmp/worker-2.log" --env "$tmp/pathfarm.env" --env "$tmp/worker-2.env"
log "worker 2: $(head -1 "$tmp/worker-2.log")"

export PATHFARM_TOKEN_FILE=$root/etc/pathfarm/token
pathfarm=$root$prefix/bin/pathfarm
address=127.0.0.1:$port
deadline=$(($(date +%s) + 60))
until [ "$("$pathfarm" workers --scheduler "$address" 2> /dev/null | grep -Ec " $host-[12]: ")" -eq 2 ]; do
  (($(date +%s) < deadline)) || fail "the workers $host-1 and $host-2 did not register within 60 s"
  sleep 0.5
done
"$pathfarm" workers --scheduler "$address" | sed 's/^/  /'
! grep -q "no access token" "$tmp/scheduler.log" || fail "the scheduler ignored PATHFARM_TOKEN_FILE"
env -u PATHFARM_TOKEN_FILE PATHFARM_TOKEN=wrong "$pathfarm" workers --scheduler "$address" > "$tmp/refused.out" 2>&1 &&
  fail "the scheduler answered a call with a wrong token"
grep -q "requires its access token" "$tmp/refused.out" || fail "a wrong token was not refused as such: $(cat "$tmp/refused.out")"
if curl --version > /dev/null 2>&1; then
  # The token is sent too, for a scheduler that asks for it on HTTP as well.
  curl -fsS -H "Authorization: Bearer $(cat "$PATHFARM_TOKEN_FILE")" "http://127.0.0.1:$((port + 1))/metrics" | grep -q '^pathfarm_workers' || fail "no metrics on PATHFARM_HTTP"
  log "metrics served on 127.0.0.1:$((port + 1)) (PATHFARM_HTTP)"
fi

scene=$root_tree/scenes/cornell/scene.json
cat > "$tmp/shot.json" <<JSON
{"name": "systemd-check", "scene": "$scene", "frames": {"start": 0, "end": 1},
 "resolution": [48, 48], "spp": 2, "max_depth": 4, "tile": 24, "pipeline": "pt"}
JSON
cat > "$tmp/tagged.json" <<JSON
{"name": "systemd-check-big", "scene": "$scene", "frames": {"start": 0, "end": 0},
 "resolution": [48, 48], "spp": 2, "max_depth": 4, "tile": 24, "pipeline": "pt", "required_tags": ["big"]}
JSON
for shot_file in shot tagged; do
  # The shot id is the line that is a number (log lines may come too).
  id=$("$pathfarm" submit --scheduler "$address" "$tmp/$shot_file.json" | grep -E '^[0-9]+$' | tail -n 1) || true
  [ -n "$id" ] || fail "pathfarm submit $shot_file.json printed no shot id"
  timeout 120 "$pathfarm" watch --scheduler "$address" "$id" > "$tmp/watch-$id.log" 2>&1 ||
    fail "shot $id ($shot_file) did not finish: $(tail -n 3 "$tmp/watch-$id.log")"
  "$pathfarm" fetch --scheduler "$address" "$id" --out "$tmp/frames-$id" > /dev/null
  eval "shot_$shot_file=$id"
done
for f in frame_0000.exr frame_0001.exr; do [ -s "$tmp/frames-$shot_shot/$f" ] || fail "$f of shot $shot_shot missing"; done
[ -s "$tmp/frames-$shot_tagged/frame_0000.exr" ] || fail "the tagged shot's frame is missing"
grep -q "of shot $shot_tagged: started" "$tmp/worker-2.log" || fail "worker 2 (--tags=big) did not work on the tagged shot"
! grep -q "of shot $shot_tagged: started" "$tmp/worker-1.log" || fail "worker 1 (no tags) took a task of the tagged shot"
log "shots $shot_shot and $shot_tagged done and fetched; only worker 2, tagged by worker-2.env, took the tagged shot"

# systemctl stop: SIGTERM to the main process; each must exit 0.
for pid in "${pids[@]}"; do kill -TERM "$pid"; done
for pid in "${pids[@]}"; do
  status=0
  wait "$pid" || status=$?
  ((status == 0)) || fail "process $pid exited $status after SIGTERM"
done
pids=()
log "SIGTERM: the scheduler and both workers exited 0"
log "PASSED"
