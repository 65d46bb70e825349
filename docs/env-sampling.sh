#!/usr/bin/env bash
# Equal-time comparison of the environment-sampling strategies of the `env` integrator on
# scenes/glossy-env.toml (a glossy and a rough metal ball under a synthetic HDR sky that
# turns 2 degrees per frame): a 512-spp `mis` reference per frame (kept in $REF), then
# each strategy with the same time per frame, scored by relative MSE per frame.
#   bash docs/env-sampling.sh [seconds per frame, default 1] [frames, default 0..8]
# (from the repository, after cargo build --release)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN="$ROOT/target/release/penumbra"
SCENE="$ROOT/scenes/glossy-env.toml"
REF=${REF:-/tmp/penumbra-env-sampling}
OUT="$ROOT/docs/images/env-sampling"
SECS=${1:-1}
FRAMES=${2:-0..8}
mkdir -p "$REF" "$OUT"
if [ ! -f "$REF/ref-$FRAMES.done" ]; then
  "$BIN" render "$SCENE" --env-sampling mis --spp 512 --frames "$FRAMES" -o "$REF/ref.exr" -q >/dev/null
  touch "$REF/ref-$FRAMES.done"
fi
echo "| strategy | spp per frame (min-max) | relMSE per frame | mean relMSE |"
echo "|---|---|---|---|"
for s in light bsdf mis sir smc; do
  log=$("$BIN" render "$SCENE" --env-sampling "$s" --spp 1000000 --time "$SECS" --frames "$FRAMES" -o "$REF/$s.exr" 2>&1)
  spp=$(echo "$log" | sed -n 's/^frame [0-9]*: \([0-9]*\) spp.*/\1/p' | sort -n | sed -n '1p;$p' | paste -sd-)
  errs=""
  for f in "$REF"/"$s"_*.exr; do
    n=${f##*_}
    errs="$errs $("$BIN" diff "$f" "$REF/ref_$n" | tail -1 | awk '{print $3}')"
  done
  mean=$(echo "$errs" | tr ' ' '\n' | grep . | awk '{s+=$1; n++} END {printf "%.3e", s/n}')
  echo "| $s | $spp | $(echo $errs | tr ' ' ',') | $mean |"
  last=$(ls "$REF"/"$s"_*.exr | tail -1)
  "$BIN" diff "$last" "$REF/ref_${last##*_}" >/dev/null
  python3 - "$last" "$OUT/$s.png" <<'PY'
import sys, numpy as np, OpenEXR, Imath
from PIL import Image
f = OpenEXR.InputFile(sys.argv[1]); dw = f.header()['dataWindow']
w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
px = np.stack([np.frombuffer(f.channel(c, Imath.PixelType(Imath.PixelType.FLOAT)), dtype=np.float32).reshape(h, w) for c in 'RGB'], -1)
srgb = np.where(px <= 0.0031308, 12.92 * px, 1.055 * np.power(np.clip(px, 0, None), 1 / 2.4) - 0.055)
Image.fromarray((np.clip(srgb, 0, 1) * 255 + 0.5).astype(np.uint8)).save(sys.argv[2])
PY
done
