# Sourced by the bench scripts that run one shot on the local farm. parse_local_shot_args
# USAGE ARGS... reads [--build DIR] [--workers N] [--label TEXT] SHOT [-- LOCAL-ARGS...]
# into build, workers, label, shot and the array local_args (what `pathfarm local` gets
# besides), and exits with USAGE when no shot is named.
parse_local_shot_args() {
  local usage=$1
  shift
  build=build workers=2 label="" shot="" local_args=()
  while (($#)); do
    case "$1" in
      --build) build=$2; shift 2 ;;
      --workers) workers=$2; shift 2 ;;
      --label) label=$2; shift 2 ;;
      --) shift; local_args=("$@"); break ;;
      *) shot=$1; shift ;;
    esac
  done
  [ -n "$shot" ] || { echo "usage: $usage" >&2; exit 2; }
}
