#!/usr/bin/env bash
# `pathfarm render --integrator gpt|tgpt` and `pathfarm poisson` as a user runs them:
# gradient layers out, reconstructed frames back, bad input refused with exit status 2.
source "$(dirname "$0")/cli_test_support.sh"
scene="$source_dir/scenes/cornell/scene.json"
quiet() { "$@" > "$work/log" 2>&1 || fail "$* failed: $(cat "$work/log")"; }
channels() { python3 - "$1" <<'PY'
import sys
# EXR header: the channel names are NUL-terminated strings after "chlist".
data = open(sys.argv[1], 'rb').read(200000)
start = data.index(b'chlist\0') + len(b'chlist\0') + 4
names = []
while data[start] != 0:
    end = data.index(b'\0', start)
    names.append(data[start:end].decode())
    start = end + 1 + 16
print(' '.join(names))
PY
}

quiet "$pathfarm" render "$scene" --frames 3:6 --res 32x32 --spp 4 --integrator tgpt --batches 2 --out "$work/tgpt"
for layer in primal.R gradient_x.G gradient_y.B direct_emission.R temporal.R temporal.valid.Y temporal.target.X \
             mixed_x.G mixed_y.B; do
  channels "$work/tgpt/frame_0003.exr" | grep -qw "$layer" || fail "tgpt frame lacks $layer"
done
for norm in l2 l1; do
  quiet "$pathfarm" poisson "$work/tgpt" --window 4 --overlap 2 --norm "$norm" --out "$work/$norm"
  for f in 3 4 5 6; do [ -s "$work/$norm/frame_000$f.exr" ] || fail "poisson --norm $norm wrote no frame $f"; done
done
# The L1 reconstruction is closer to a converged render than the primal images it started
# from (summed over the frames; L2 keeps more of the caustics' outliers at 4 spp).
quiet "$pathfarm" render "$scene" --frames 3:6 --res 32x32 --spp 512 --out "$work/reference"
relmse() { "$pathfarm" compare "$1" "$2" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["relmse"])'; }
before=0
after=0
for f in 3 4 5 6; do
  before="$before + $(relmse "$work/tgpt/frame_000$f.exr" "$work/reference/frame_000$f.exr")"
  after="$after + $(relmse "$work/l1/frame_000$f.exr" "$work/reference/frame_000$f.exr")"
done
python3 -c "import sys; sys.exit(0 if ($after) < 0.8 * ($before) else 1)" \
  || fail "reconstruction did not lower relMSE ($before -> $after)"

# pt stays the default, bit for bit.
quiet "$pathfarm" render "$scene" --frames 4:4 --res 24x16 --spp 2 --out "$work/default"
quiet "$pathfarm" render "$scene" --frames 4:4 --res 24x16 --spp 2 --integrator pt --out "$work/pt"
cmp -s "$work/default/frame_0004.exr" "$work/pt/frame_0004.exr" || fail "--integrator pt differs from the default"

# Bad input: a missing folder, frames without gradient layers, unknown norm, windows that
# do not advance, options that do not fit the integrator.
expect_refused poisson "$work/missing" --out "$work/x"
expect_refused poisson "$work/default" --out "$work/x"
grep -q 'missing channel "primal.R"' "$work/log" || fail "no clear message for a frame without gradients: $(cat "$work/log")"
expect_refused poisson "$work/tgpt" --norm l3 --out "$work/x"
expect_refused poisson "$work/tgpt" --window 4 --overlap 4 --out "$work/x"
mkdir -p "$work/gap" && cp "$work/tgpt/frame_0003.exr" "$work/tgpt/frame_0005.exr" "$work/gap/"
expect_refused poisson "$work/gap" --out "$work/x"
grep -q "not consecutive" "$work/log" || fail "no clear message for a gap in the frames: $(cat "$work/log")"
expect_refused render "$scene" --frames 4:4 --res 8x8 --integrator gpt --decompose default --out "$work/x"
expect_refused render "$scene" --frames 4:4 --res 8x8 --batches 3 --out "$work/x"
expect_refused render "$scene" --frames 4:4 --res 8x8 --integrator vcm --out "$work/x"
[ -e "$work/x" ] && fail "a refused command wrote its output"

finish "gradient CLI"
