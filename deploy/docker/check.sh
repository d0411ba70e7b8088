#!/usr/bin/env bash
# Checks deploy/docker/Dockerfile where no image can be built (no container engine, or
# no registry to pull debian:12 from):
#
#   1. says which container tools are here and whether a Docker daemon answers;
#   2. the builder stage builds with deploy/setup.sh itself (no cmake line of its own),
#      takes setup.sh's PACKAGES with the same sed as the Dockerfile, and every one of
#      them is a Debian 12 package (apt-cache show);
#   3. every runtime package the Dockerfile installs is a Debian 12 package, and comes
#      from setup.sh's list (a dependency, at any depth, of one of its -dev packages);
#   4. every shared library the built binary needs (readelf NEEDED, found with dpkg -S)
#      belongs to a runtime package, to one of their dependencies, or to debian:12-slim
#      itself (libc6, libgcc-s1, libstdc++6, zlib1g);
#   5. the files the Dockerfile copies exist, and .dockerignore keeps build/ out;
#   6. with --chroot: emulates the runtime stage: debootstrap (minbase) a Debian 12 root
#      from the apt archive, apt-get install exactly the Dockerfile's runtime packages in
#      it, copy the binary and scenes as the Dockerfile does, and run `pathfarm --help`
#      and a tiny render inside it (chroot) as the image's user. Needs root, ~150 MB and
#      a few minutes; installs debootstrap with apt-get if missing.
#
# Usage: deploy/docker/check.sh [--chroot]   (PATHFARM_BIN: default build/bin/pathfarm)
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
dockerfile=$here/Dockerfile
setup=$root/deploy/setup.sh
binary=${PATHFARM_BIN:-$root/build/bin/pathfarm}
chroot_try=""
case ${1:-} in
  "") ;;
  --chroot) chroot_try=1 ;;
  *) echo "usage: $0 [--chroot]" >&2; exit 2 ;;
esac
fail() {
  echo "docker check: FAILED: $*" >&2
  exit 1
}
log() { echo "docker check: $*"; }
[ -f "$dockerfile" ] || fail "no $dockerfile"
[ -x "$binary" ] || fail "no pathfarm binary at $binary (build it, or set PATHFARM_BIN)"
grep -q '^VERSION_ID="12"' /etc/os-release || fail "this is not Debian 12: the package checks need Debian 12's apt lists"

# --- 1. container tools -------------------------------------------------------------------
tools=""
for tool in docker podman buildah; do
  if command -v "$tool" > /dev/null; then tools+=" $tool ($(command -v "$tool"))"; fi
done
log "container tools here:${tools:- none}"
if command -v docker > /dev/null; then
  if timeout 10 docker info > /dev/null 2>&1; then
    log "a Docker daemon answers: build for real with: docker build -f deploy/docker/Dockerfile -t pathfarm ."
  else
    log "no Docker daemon answers (docker info fails): the image cannot be built here"
  fi
fi

# --- 2. the builder stage and setup.sh -------------------------------------------------------
# The builder's RUN lines, continuation lines joined.
runs=$(sed -n '/^FROM .* AS builder/,/^FROM /p' "$dockerfile" | sed -e ':a' -e '/\\$/N; s/\\\n//; ta' | grep '^RUN ')
grep -q '\./deploy/setup\.sh' <<< "$runs" || fail "the builder stage does not run ./deploy/setup.sh"
! grep -Eq 'cmake|ninja' <<< "$runs" || fail "the builder stage has cmake/ninja commands of its own: build with setup.sh"
grep -q 'sed -n "/^PACKAGES=(/,/^)/p" /tmp/setup.sh' <<< "$runs" || fail "the builder does not take setup.sh's PACKAGES"
grep -q '^FROM debian:12 AS builder' "$dockerfile" || fail "the builder stage is not FROM debian:12"
# The same extraction as the Dockerfile's, on a copy of setup.sh.
eval "$(sed -n "/^PACKAGES=(/,/^)/p" "$setup")"
((${#PACKAGES[@]} > 10)) || fail "could not read PACKAGES from setup.sh"
for command in 'cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release' 'cmake --build "$BUILD_DIR"'; do
  grep -qF "$command" "$setup" || fail "setup.sh no longer runs '$command': see that the Dockerfile's build still copies build/bin/pathfarm"
done
grep -q 'COPY --from=builder /src/build/bin/pathfarm ' "$dockerfile" || fail "the runtime stage does not copy build/bin/pathfarm"
missing=()
for package in "${PACKAGES[@]}"; do apt-cache show "$package" > /dev/null 2>&1 || missing+=("$package"); done
((${#missing[@]} == 0)) || fail "setup.sh packages unknown to apt (run apt-get update?): ${missing[*]}"
log "builder: runs deploy/setup.sh; its ${#PACKAGES[@]} packages (taken by the Dockerfile's sed) are all in apt"

# --- 3. runtime packages ---------------------------------------------------------------------
runtime_run=$(sed -n '/^FROM debian:12-slim/,$p' "$dockerfile" | sed -e ':a' -e '/\\$/N; s/\\\n//; ta' |
  grep -m1 'apt-get install')
[ -n "$runtime_run" ] || fail "no apt-get install in the runtime stage (FROM debian:12-slim)"
read -r -a runtime <<< "$(sed -e 's/.*--no-install-recommends//' -e 's/&&.*//' <<< "$runtime_run")"
((${#runtime[@]} > 0)) || fail "could not read the runtime packages"
missing=()
for package in "${runtime[@]}"; do apt-cache show "$package" > /dev/null 2>&1 || missing+=("$package"); done
((${#missing[@]} == 0)) || fail "runtime packages unknown to apt: ${missing[*]}"
closure=$(apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts --no-breaks --no-replaces \
  --no-enhances "${PACKAGES[@]}" 2> /dev/null | grep -v '^ ' | sort -u)
strays=()
for package in "${runtime[@]}"; do grep -qx "$package" <<< "$closure" || strays+=("$package"); done
((${#strays[@]} == 0)) || fail "runtime packages that no package of setup.sh depends on: ${strays[*]}"
log "runtime: ${#runtime[@]} packages, all in apt, all dependencies of setup.sh's packages"

# --- 4. the binary's libraries ----------------------------------------------------------------
runtime_closure=$(apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts --no-breaks \
  --no-replaces --no-enhances "${runtime[@]}" 2> /dev/null | grep -v '^ ' | sort -u)
base=(libc6 libgcc-s1 libstdc++6 zlib1g)
uncovered=()
needed=$(readelf -d "$binary" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
for soname in $needed; do
  path=$(ldconfig -p | awk -v s="$soname" '$1 == s && /x86-64/ && !found { print $NF; found = 1 }')
  [ -n "$path" ] || fail "$soname (needed by the binary) is not in ldconfig's cache"
  owner=""
  for candidate in "$path" "$(readlink -f "$path")" "${path#/usr}" "/usr$path"; do
    owner=$(dpkg -S "$candidate" 2> /dev/null | head -1 | cut -d: -f1) && [ -n "$owner" ] && break
  done
  [ -n "$owner" ] || fail "no package owns $path ($soname)"
  if ! printf '%s\n' "${base[@]}" | grep -qx "$owner" && ! grep -qx "$owner" <<< "$runtime_closure"; then
    uncovered+=("$soname ($owner)")
  fi
done
((${#uncovered[@]} == 0)) || fail "libraries the binary needs that the runtime stage does not install: ${uncovered[*]}"
log "the binary's $(wc -w <<< "$needed") NEEDED libraries all come from the runtime packages, their dependencies or the base image"

# --- 5. the build context ------------------------------------------------------------------------
for path in deploy/setup.sh scenes CMakeLists.txt; do [ -e "$root/$path" ] || fail "the Dockerfile copies $path, which is missing"; done
grep -qx 'build/' "$root/.dockerignore" || fail ".dockerignore does not keep build/ out of the context"
log "the copied paths exist; .dockerignore keeps build/ out"

# --- 6. the runtime stage, emulated in a chroot --------------------------------------------------
if [ -n "$chroot_try" ]; then
  [ "$(id -u)" -eq 0 ] || fail "--chroot needs root"
  if ! command -v debootstrap > /dev/null; then
    log "installing Debian's debootstrap"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends debootstrap > /dev/null
  fi
  mirror=$(sed -n 's/^URIs: *\(http[^ ]*debian\/*\)$/\1/p' /etc/apt/sources.list.d/debian.sources 2> /dev/null | head -1)
  mirror=${mirror:-http://deb.debian.org/debian}
  work=$(mktemp -d /tmp/pathfarm-docker-chroot.XXXXXX)
  jail=$work/root
  mounted=""
  cleanup() {
    local status=$?
    set +e
    if [ -n "$mounted" ]; then umount "$jail/proc" "$jail/dev" 2> /dev/null; fi
    if mountpoint -q "$jail/dev" || mountpoint -q "$jail/proc"; then
      # Never rm -rf through a bind mount of the host's /dev.
      echo "docker check: $jail/dev or $jail/proc is still mounted: unmount them, then remove $work" >&2
    elif [ "${DOCKER_CHECK_KEEP:-}" = 1 ]; then
      echo "docker check: kept $work" >&2
    else
      rm -rf "$work"
    fi
    exit "$status"
  }
  trap cleanup EXIT
  trap 'exit 130' INT TERM
  log "debootstrap --variant=minbase bookworm from $mirror into $jail"
  debootstrap --variant=minbase bookworm "$jail" "$mirror" > "$work/debootstrap.log" 2>&1 ||
    fail "debootstrap failed: $(tail -n 5 "$work/debootstrap.log")"
  mount -t proc proc "$jail/proc" && mount --bind /dev "$jail/dev" && mounted=1
  # The runtime stage's RUN, as written in the Dockerfile (apt-get update .. useradd .. install -d).
  runtime_script=$(sed -n '/^FROM debian:12-slim/,$p' "$dockerfile" | sed -e ':a' -e '/\\$/N; s/\\\n//; ta' |
    grep -m1 '^RUN apt-get update' | sed 's/^RUN //')
  [ -n "$runtime_script" ] || fail "could not read the runtime stage's RUN apt-get update ... line"
  chroot "$jail" /usr/bin/env DEBIAN_FRONTEND=noninteractive PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    /bin/sh -c "$runtime_script" > "$work/runtime-stage.log" 2>&1 ||
    fail "the runtime stage's RUN failed in the chroot: $(tail -n 5 "$work/runtime-stage.log")"
  install -m 755 "$binary" "$jail/usr/local/bin/pathfarm"
  mkdir -p "$jail/usr/share/pathfarm" && cp -r "$root/scenes" "$jail/usr/share/pathfarm/scenes"
  as_image_user() {
    chroot --userspec=10001:10001 "$jail" /usr/bin/env -i HOME=/var/lib/pathfarm PATH=/usr/local/bin:/usr/bin:/bin \
      /bin/sh -c "cd /var/lib/pathfarm && $1"
  }
  as_image_user "pathfarm --help > /var/lib/pathfarm/help.log 2>&1" ||
    fail "pathfarm --help fails in the runtime root: $(tail -n 3 "$jail/var/lib/pathfarm/help.log" 2> /dev/null)"
  missing_libs=$(chroot "$jail" ldd /usr/local/bin/pathfarm | grep 'not found' || true)
  [ -z "$missing_libs" ] || fail "libraries missing in the runtime root: $missing_libs"
  as_image_user "pathfarm render /usr/share/pathfarm/scenes/cornell/scene.json --frames 0 --res 32x32 --spp 2 \
    --threads 1 --out /var/lib/pathfarm/out > /var/lib/pathfarm/render.log 2>&1" ||
    fail "a render as user 10001 fails in the runtime root: $(tail -n 3 "$jail/var/lib/pathfarm/render.log")"
  [ -s "$jail/var/lib/pathfarm/out/frame_0000.exr" ] || fail "the render in the runtime root wrote no frame"
  log "runtime stage emulated: Debian 12 minbase + the Dockerfile's RUN ($(du -shx "$jail" | cut -f1) in all);" \
    "pathfarm --help and a 32x32 render run as user 10001 with every library found"
fi
log "PASSED"
