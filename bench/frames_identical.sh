# Sourced by the fault benchmarks (chaos.sh, netns_farm.sh).
# frames_identical REFERENCE_DIR DIR: prints "N of M", the frames of REFERENCE_DIR
# (frame_*.exr) that DIR holds byte for byte; succeeds when all do and there is one.
frames_identical() {
  local same=0 total=0 reference
  for reference in "$1"/frame_*.exr; do
    [ -e "$reference" ] || continue
    total=$((total + 1))
    cmp -s "$reference" "$2/$(basename "$reference")" && same=$((same + 1))
  done
  echo "$same of $total"
  ((same == total && total > 0))
}
