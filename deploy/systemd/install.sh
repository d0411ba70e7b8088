#!/usr/bin/env bash
# Installs pathfarm's systemd units on this host (or into a folder, for packaging):
#
#   PREFIX/bin/pathfarm                                 the binary (default build/bin/pathfarm)
#   /etc/systemd/system/pathfarm-scheduler.service      the scheduler
#   /etc/systemd/system/pathfarm-worker@.service        workers: pathfarm-worker@1, @2, ...
#   /etc/sysusers.d/pathfarm.conf                       the system user and group `pathfarm`
#   /etc/pathfarm/pathfarm.env                          settings (from pathfarm.env.example; kept if present)
#   /etc/pathfarm/token                                 a random token, root:pathfarm 0640 (kept if present)
#
# Then, when systemd runs this host, `systemctl daemon-reload`. Nothing is enabled or
# started: that is yours to say (the script prints how).
#
# Usage: deploy/systemd/install.sh [--prefix DIR] [--root DIR] [--binary FILE] [--dry-run]
#   --prefix DIR   where the binary goes, DIR/bin (default /usr/local); the units' ExecStart follow
#   --root DIR     install below DIR instead of / (no user is made on the host, no reload)
#   --binary FILE  the pathfarm binary to install (default: build/bin/pathfarm of this tree)
#   --dry-run      print what would be done, change nothing
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
source_tree=$(cd "$here/../.." && pwd)
prefix=/usr/local
root=""
binary=$source_tree/build/bin/pathfarm
dry_run=""

die() {
  echo "install.sh: $*" >&2
  exit 2
}
while (($#)); do
  case $1 in
    --prefix) [ $# -ge 2 ] || die "--prefix needs a folder"; prefix=$2; shift 2 ;;
    --root) [ $# -ge 2 ] || die "--root needs a folder"; root=$2; shift 2 ;;
    --binary) [ $# -ge 2 ] || die "--binary needs a file"; binary=$2; shift 2 ;;
    --dry-run) dry_run=1; shift ;;
    -h | --help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown argument '$1' (see --help)" ;;
  esac
done
[[ "$prefix" = /* ]] || die "--prefix must be an absolute path, not '$prefix'"
[ -z "$root" ] || root=$(cd "$root" 2> /dev/null && pwd) || die "--root $root is not a folder"
[ -x "$binary" ] || die "no pathfarm binary at $binary (build it with deploy/setup.sh, or give --binary)"
if [ -z "$root" ] && [ -z "$dry_run" ] && [ "$(id -u)" -ne 0 ]; then
  die "installing into / needs root (or use --root DIR, or --dry-run)"
fi

# Runs a command, or prints it with --dry-run.
run() {
  if [ -n "$dry_run" ]; then
    printf '+'
    printf ' %q' "$@"
    printf '\n'
  else
    "$@"
  fi
}
# Writes stdin to a file (mode $2), or says it would.
write() {
  if [ -n "$dry_run" ]; then
    echo "+ write $1 (mode $2)"
    cat > /dev/null
  else
    cat > "$1"
    chmod "$2" "$1"
  fi
}

bin_dir=$root$prefix/bin
unit_dir=$root/etc/systemd/system
sysusers_dir=$root/etc/sysusers.d
config_dir=$root/etc/pathfarm

run install -d -m 755 "$bin_dir" "$unit_dir" "$sysusers_dir"
run install -d -m 750 "$config_dir"
run install -m 755 "$binary" "$bin_dir/pathfarm"

for unit in pathfarm-scheduler.service pathfarm-worker@.service; do
  sed "s|/usr/local/bin/pathfarm|$prefix/bin/pathfarm|g" "$here/$unit" | write "$unit_dir/$unit" 644
done

# The system user: systemd-sysusers where there is one (it honours --root), else useradd.
write "$sysusers_dir/pathfarm.conf" 644 <<'CONF'
# pathfarm's scheduler and workers run as this user (deploy/systemd/install.sh).
u pathfarm - "pathfarm render farm" /var/lib/pathfarm -
CONF
if command -v systemd-sysusers > /dev/null; then
  if [ -n "$root" ]; then
    run systemd-sysusers --root="$root" "$sysusers_dir/pathfarm.conf"
  else
    run systemd-sysusers "$sysusers_dir/pathfarm.conf"
  fi
elif [ -z "$root" ] && ! getent passwd pathfarm > /dev/null; then
  run useradd --system --user-group --home-dir /var/lib/pathfarm --no-create-home \
    --shell /usr/sbin/nologin --comment "pathfarm render farm" pathfarm
elif [ -n "$root" ]; then
  echo "install.sh: no systemd-sysusers: create the user 'pathfarm' in $root yourself" >&2
fi

if [ -e "$config_dir/pathfarm.env" ]; then
  echo "install.sh: keeping $config_dir/pathfarm.env"
else
  write "$config_dir/pathfarm.env" 640 < "$here/pathfarm.env.example"
fi
if [ -e "$config_dir/token" ]; then
  echo "install.sh: keeping $config_dir/token"
else
  head -c 32 /dev/urandom | od -An -tx1 | tr -d ' \n' | write "$config_dir/token" 640
fi
# Group pathfarm reads the settings and the token (the group exists once sysusers ran).
if [ -n "$dry_run" ] || getent group pathfarm > /dev/null || { [ -n "$root" ] && grep -q '^pathfarm:' "$root/etc/group" 2> /dev/null; }; then
  if [ -z "$root" ]; then
    run chown root:pathfarm "$config_dir" "$config_dir/pathfarm.env" "$config_dir/token"
  else
    gid=$(awk -F: '$1 == "pathfarm" { print $3 }' "$root/etc/group" 2> /dev/null || true)
    [ -z "$gid" ] || run chown "0:$gid" "$config_dir" "$config_dir/pathfarm.env" "$config_dir/token"
  fi
fi

if [ -z "$root" ] && [ -d /run/systemd/system ]; then
  run systemctl daemon-reload
elif [ -z "$root" ]; then
  echo "install.sh: systemd is not running this system: no daemon-reload"
fi

cat <<NEXT
install.sh: done${dry_run:+ (dry run: nothing changed)}. Next:
  edit $config_dir/pathfarm.env (scheduler address, slots, threads, tags; optional TLS and a workers' token)
  copy $config_dir/token to whoever submits, and to every worker host unless workers get their
    own token (PATHFARM_WORKER_TOKEN_FILE); same path, root:pathfarm 0640
  systemctl enable --now pathfarm-scheduler                     # on the scheduler's host
  systemctl enable --now pathfarm-worker@1 pathfarm-worker@2    # on each render host
  journalctl -u pathfarm-scheduler -u 'pathfarm-worker@*' -f
  PATHFARM_TOKEN_FILE=$config_dir/token $prefix/bin/pathfarm workers --scheduler HOST:7700
NEXT
