#!/usr/bin/env bash
# A farm of hosts on one machine (issue 43), and the faults of a farm network played on it.
#
# Each host is a Linux network namespace with one interface, joined by a veth pair to a
# bridge in a namespace of its own (the switch), on a private /24 that exists only inside
# these namespaces: nothing is routed to or from the machine's own network. Hosts: a
# scheduler (TLS with a CA made here, a token, its database and store), --workers worker
# hosts (each with its own cache) and a client host that submits with uploads, follows the
# shot and fetches its frames. Everything is removed on exit, whatever happens.
#
# Each pipeline's shot runs once undisturbed, then once per fault:
#   worker-cut         a worker host's link goes down while it renders, for --cut seconds
#                      (longer than a lease), then comes back
#   scheduler-cut      the scheduler host's link goes down (every worker and the client lose
#                      it) for --cut seconds
#   worker-freeze      every process of a worker host is stopped (SIGSTOP: a paused VM, a
#                      swapping host) while it renders, for --cut seconds, then continued:
#                      its late result must be dropped by it or refused by the scheduler
#   power-loss         every process of a worker host is SIGKILLed while it renders and its
#                      cache is wiped; the host comes back a second later
#   scheduler-restart  every process of the scheduler host is SIGKILLed while tasks run; the
#                      scheduler starts again on its database and store
#   upload-cut         the client's link is slowed (tbf) and goes down for --cut seconds
#                      while `pathfarm submit` uploads; the stalled submit is killed and the
#                      client submits again with the same --submit-key, as a user would
# A run passes when its frames are byte-identical to the undisturbed run's, no task was
# charged an attempt (tasks.failures = 0: a lost lease is counted apart, in tasks.lost) and
# every chunk in the scheduler's store hashes to its name. One table row per run; time lost
# is the run's seconds less the undisturbed run's.
#
#   bench/netns_farm.sh [--build DIR] [--pipelines "pt d dui tgpt tmlt auto"] [--faults "..."]
#                       [--scene scenes/dolly/scene.json] [--frames 0:11] [--res 192x108] [--spp 64]
#                       [--workers 3] [--lease 3] [--cut 60] [--limit 900] [--quick] [--keep]
# --keep leaves the work folder (each host's log, the last run's database) and says where.
# --quick is CI's (ctest netns.farm): pt over frames 0:3 at 64x48, the faults worker-cut and
# scheduler-restart, a 2-second lease and a 7-second cut. Making namespaces needs root
# (CAP_SYS_ADMIN and CAP_NET_ADMIN); where it cannot, the script says so and exits 77
# (ctest: skipped). Every wait is bounded by --limit seconds.
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/frames_identical.sh
build=build pipelines="pt d dui tgpt tmlt auto" faults="worker-cut worker-freeze scheduler-cut power-loss scheduler-restart upload-cut"
scene=scenes/dolly/scene.json frames=0:11 res=192x108 spp=64 workers=3 lease=3 cut=60 limit=900 keep=0
while (($#)); do
  case "$1" in
    --quick) pipelines=pt faults="worker-cut scheduler-restart" frames=0:3 res=64x48 lease=2 cut=7 limit=240
             shift; continue ;;
    --keep) keep=1; shift; continue ;;
    --build) build=$2 ;;
    --pipelines) pipelines=$2 ;;
    --faults) faults=$2 ;;
    --scene) scene=$2 ;;
    --frames) frames=$2 ;;
    --res) res=$2 ;;
    --spp) spp=$2 ;;
    --workers) workers=$2 ;;
    --lease) lease=$2 ;;
    --cut) cut=$2 ;;
    --limit) limit=$2 ;;
    *) echo "netns_farm: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
for fault in $faults; do
  case $fault in worker-cut | worker-freeze | scheduler-cut | power-loss | scheduler-restart | upload-cut) ;;
    *) echo "netns_farm: unknown fault $fault" >&2; exit 2 ;;
  esac
done
case $build in /*) ;; *) build=$PWD/$build ;; esac
case $scene in /*) ;; *) scene=$PWD/$scene ;; esac
pathfarm="$build/bin/pathfarm"
[ -x "$pathfarm" ] || { echo "netns_farm: no $pathfarm (build first)" >&2; exit 2; }
for tool in ip tc openssl sqlite3 sha256sum; do
  command -v $tool > /dev/null || { echo "netns_farm: skipped: no $tool (deploy/setup.sh installs it)"; exit 77; }
done

tag="pf$$"              # namespace names: $tag-switch, $tag-scheduler, $tag-w1 ... $tag-client
net="10.$((RANDOM % 200 + 20)).$((RANDOM % 250)).0"  # the private /24; ${net%.0}.N are its hosts
work=$(mktemp -d "${TMPDIR:-/tmp}/pathfarm-netns-XXXXXX")
hosts=(scheduler client)
for i in $(seq 1 "$workers"); do hosts+=("w$i"); done

kill_host() {  # every process in host $1's namespace
  local pids
  pids=$(ip netns pids "$tag-$1" 2> /dev/null || true)
  [ -z "$pids" ] || kill -9 $pids 2> /dev/null || true
  for _ in $(seq 50); do [ -z "$(ip netns pids "$tag-$1" 2> /dev/null || true)" ] && return 0; sleep 0.1; done
}
signal_host() {  # $1: the host, $2: the signal
  local pids
  pids=$(ip netns pids "$tag-$1" 2> /dev/null || true)
  [ -z "$pids" ] || kill -"$2" $pids 2> /dev/null || true
}
cleanup() {
  for host in "${hosts[@]}"; do kill_host "$host"; done
  for ns in $(ip netns list 2> /dev/null | awk '{print $1}' | grep "^$tag-" || true); do ip netns del "$ns" || true; done
  if ((keep)); then echo "netns_farm: kept $work" >&2; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

if ! error=$(ip netns add "$tag-switch" 2>&1); then
  echo "netns_farm: skipped: cannot create network namespaces here (needs root): $error"
  exit 77
fi
ip -n "$tag-switch" link add br0 type bridge
ip -n "$tag-switch" link set br0 up
address_of() {  # host $1's address on the private network
  case $1 in scheduler) echo "${net%.0}.1" ;; client) echo "${net%.0}.2" ;; w*) echo "${net%.0}.$((10 + ${1#w}))" ;; esac
}
for host in "${hosts[@]}"; do
  ip netns add "$tag-$host"
  ip -n "$tag-switch" link add "to-$host" type veth peer name eth0 netns "$tag-$host"
  ip -n "$tag-switch" link set "to-$host" master br0 up
  ip -n "$tag-$host" addr add "$(address_of "$host")/24" dev eth0
  ip -n "$tag-$host" link set eth0 up
  ip -n "$tag-$host" link set lo up
done
on() { local host=$1; shift; ip netns exec "$tag-$host" "$@"; }
cut_link() { ip -n "$tag-switch" link set "to-$1" down; }
heal_link() { ip -n "$tag-switch" link set "to-$1" up; }

# TLS: a CA made for this run, the scheduler's certificate for its address on the private net.
scheduler_address="$(address_of scheduler):7700"
openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj "/CN=pathfarm netns test CA" \
  -keyout "$work/ca.key" -out "$work/ca.pem" 2> /dev/null
openssl req -newkey rsa:2048 -nodes -subj "/CN=scheduler" -keyout "$work/scheduler.key" -out "$work/scheduler.csr" 2> /dev/null
printf 'subjectAltName=IP:%s\nbasicConstraints=CA:FALSE\n' "$(address_of scheduler)" > "$work/san.ext"
openssl x509 -req -in "$work/scheduler.csr" -CA "$work/ca.pem" -CAkey "$work/ca.key" -CAcreateserial -days 1 \
  -extfile "$work/san.ext" -out "$work/scheduler.pem" 2> /dev/null
head -c 24 /dev/urandom | od -An -tx1 | tr -d ' \n' > "$work/token"
farm_options=(--scheduler "$scheduler_address" --tls-ca "$work/ca.pem" --token-file "$work/token")

start_scheduler() {
  on scheduler "$pathfarm" scheduler --listen "$scheduler_address" --db "$work/farm.db" --store "$work/store" \
    --token-file "$work/token" --tls-cert "$work/scheduler.pem" --tls-key "$work/scheduler.key" \
    --lease-seconds "$lease" --retry-backoff 0.2 >> "$work/scheduler.log" 2>&1 &
  for _ in $(seq 100); do
    on client "$pathfarm" status "${farm_options[@]}" > /dev/null 2>&1 && return 0
    sleep 0.2
  done
  echo "netns_farm: the scheduler does not answer on $scheduler_address; its log:" >&2
  tail -20 "$work/scheduler.log" >&2
  exit 1
}
start_worker() {  # $1: the worker host
  on "$1" "$pathfarm" worker "${farm_options[@]}" --threads 1 --name "$1" --cache "$work/cache-$1" \
    >> "$work/$1.log" 2>&1 &
}
state_of() {  # the state word of shot $1, seen from the client (empty while out of reach)
  on client timeout 20 "$pathfarm" status "$1" "${farm_options[@]}" 2> /dev/null | head -1 |
    grep -oE 'SHOT_[A-Z]+' | head -1 | sed 's/SHOT_//' || true
}
wait_for_log() {  # $1: a log file, $2: a pattern; true once it appears, false if the shot ends first (bounded)
  for _ in $(seq $((limit * 10))); do
    grep -q "$2" "$1" 2> /dev/null && return 0
    [ -e "$work/shot-over" ] && return 1
    sleep 0.1
  done
  return 1
}
submit() {  # prints the shot id; the same key each time, so a second submit is the first shot
  on client timeout "$limit" "$pathfarm" submit "$work/shot.json" "${farm_options[@]}" --submit-key "netns-$run" \
    2>> "$work/client.log" | grep -E '^[0-9]+$' || true
}

# The fault, played in the background while the shot runs; $work/fault-played says it was.
play_fault() {
  touch "$work/fault-played"
  case $1 in
    worker-cut)
      wait_for_log "$work/w1.log" "started" || { rm -f "$work/fault-played"; return 0; }
      cut_link w1; sleep "$cut"; heal_link w1 ;;
    worker-freeze)
      wait_for_log "$work/w1.log" "started" || { rm -f "$work/fault-played"; return 0; }
      signal_host w1 STOP; sleep "$cut"; signal_host w1 CONT ;;
    scheduler-cut)
      wait_for_log "$work/w1.log" "started" || { rm -f "$work/fault-played"; return 0; }
      cut_link scheduler; sleep "$cut"; heal_link scheduler ;;
    power-loss)
      wait_for_log "$work/w2.log" "started" || { rm -f "$work/fault-played"; return 0; }
      kill_host w2; rm -rf "$work/cache-w2"; sleep 1; start_worker w2 ;;
    scheduler-restart)
      wait_for_log "$work/w1.log" "started" || { rm -f "$work/fault-played"; return 0; }
      kill_host scheduler; start_scheduler ;;
  esac
}

# Every chunk in the scheduler's store hashes to its name: "N of M whole".
store_check() {
  local whole=0 total=0 file name
  while IFS= read -r file; do
    total=$((total + 1))
    name="$(basename "$(dirname "$file")")$(basename "$file")"
    [ "$(sha256sum "$file" | cut -d' ' -f1)" = "$name" ] && whole=$((whole + 1))
  done < <(find "$work/store/objects" -type f 2> /dev/null)
  echo "$whole $total"
}

echo "Hosts on ${net}/24: ${hosts[*]}; TLS and a token; lease ${lease} s, cuts of ${cut} s." >&2
echo "| pipeline | fault | seconds | time lost (s) | frames identical | attempts charged | leases lost | late results dropped by the worker / refused by the scheduler | store chunks whole |"
echo "| --- | --- | ---: | ---: | --- | ---: | ---: | ---: | --- |"
status=0 run=0
for pipeline in $pipelines; do
  baseline=""
  for fault in undisturbed $faults; do
    run=$((run + 1))
    kill_host scheduler
    for i in $(seq 1 "$workers"); do kill_host "w$i"; done
    rm -rf "$work/farm.db"* "$work/store" "$work"/cache-* "$work"/*.log "$work/out" "$work/shot-over" "$work/fault-played"
    for host in "${hosts[@]}"; do heal_link "$host"; done
    cat > "$work/shot.json" <<JSON
{"name": "netns-$pipeline-$fault", "scene": "$scene",
 "frames": {"start": ${frames%:*}, "end": ${frames#*:}}, "resolution": [${res%x*}, ${res#*x}],
 "spp": $spp, "tile": 32, "pipeline": "$pipeline", "max_attempts": 3}
JSON
    start_scheduler
    start_worker w1  # first, so that it leases the first task: the faults aim at it
    wait_for_log "$work/w1.log" "registered" || true
    for i in $(seq 2 "$workers"); do start_worker "w$i"; done
    started=$SECONDS fault_pid=""
    if [ "$fault" = upload-cut ]; then
      # The upload is slowed so that the cut finds it under way; the user gives up on the
      # stalled submit and runs it again.
      on client tc qdisc add dev eth0 root tbf rate 256kbit burst 16kbit latency 400ms
      submit > /dev/null &
      submit_pid=$!
      sleep 1; cut_link client; sleep "$cut"
      kill_host client; wait "$submit_pid" 2> /dev/null || true
      heal_link client
      on client tc qdisc del dev eth0 root
      id=$(submit)
    else
      id=$(submit)
      play_fault "$fault" &
      fault_pid=$!
    fi
    state=""
    while [ -n "$id" ] && ((SECONDS - started < limit)); do
      state=$(state_of "$id")
      [[ $state == DONE || $state == FAILED || $state == CANCELLED ]] && break
      sleep 1
    done
    seconds=$((SECONDS - started))
    touch "$work/shot-over"
    [ -z "$fault_pid" ] || wait "$fault_pid" 2> /dev/null || true  # the fault's end
    identical="no: shot ${state:-not submitted}"
    if [ "$fault" != undisturbed ] && [ "$fault" != upload-cut ] && [ ! -e "$work/fault-played" ]; then
      identical="no: the shot ended before the fault could be played (a longer shot: --frames, --spp)"
      status=1
    elif [[ $state == DONE ]]; then
      on client "$pathfarm" fetch "$id" --out "$work/out" "${farm_options[@]}" > /dev/null 2>> "$work/client.log"
      if [ "$fault" = undisturbed ]; then
        rm -rf "$work/undisturbed"; mv "$work/out" "$work/undisturbed"; baseline=$seconds
        identical="(the reference)"
      else
        identical=$(frames_identical "$work/undisturbed" "$work/out") || status=1
      fi
    else
      status=1
      on client "$pathfarm" status "$id" "${farm_options[@]}" 2> /dev/null | tail -5 >&2 || true
    fi
    kill_host scheduler
    for i in $(seq 1 "$workers"); do kill_host "w$i"; done
    charged=$(sqlite3 "$work/farm.db" "SELECT COALESCE(SUM(failures), 0) FROM tasks" 2> /dev/null || echo "?")
    lost=$(sqlite3 "$work/farm.db" "SELECT COALESCE(SUM(lost), 0) FROM tasks" 2> /dev/null || echo "?")
    dropped=$(cat "$work"/w*.log | grep -c "result dropped" || true)
    refused=$(cat "$work"/w*.log | grep -c "refused the report" || true)
    read -r whole chunks < <(store_check)
    [ "$charged" = 0 ] || status=1
    ((whole == chunks)) || status=1
    lostTime="–"
    [ -z "$baseline" ] || [ "$fault" = undisturbed ] || lostTime=$((seconds - baseline))
    echo "| $pipeline | $fault | $seconds | $lostTime | $identical | $charged | $lost | $dropped / $refused | $whole of $chunks |"
    if [[ $state != DONE ]] && [ "$fault" = undisturbed ]; then
      echo "netns_farm: the undisturbed $pipeline shot did not finish; the scheduler's log:" >&2
      tail -20 "$work/scheduler.log" >&2
      break
    fi
  done
done
exit $status
