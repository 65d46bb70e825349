#!/usr/bin/env bash
# Equal-time comparisons of the light-transport integrators on scenes where path tracing
# struggles (docs/light-transport.md). For each scene: a long reference render (kept in
# $REF, made once), then each integrator with the same wall-clock budget (--time), scored
# by relative MSE against the reference; small PNGs of the equal-time renders go to
# docs/images/light-transport/.
#   bash docs/light-transport.sh [seconds per render, default 10]
#   INTEGRATORS="mlt" bash docs/light-transport.sh 10     (only those; default: path bdpt mlt sppm photon)
# (from the repository, after cargo build --release; ../shared beside it)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
S="$ROOT/../shared/scenes"
BIN="$ROOT/target/release/penumbra"
REF=${REF:-/tmp/penumbra-light-transport}
OUT="$ROOT/docs/images/light-transport"
SECS=${1:-10}
mkdir -p "$REF" "$OUT"
compare() { # name scene res ref-integrator ref-spp integrators...
  local name=$1 scene=$2 res=$3 refint=$4 refspp=$5; shift 5
  local ref="$REF/$name-ref.exr"
  if [ ! -f "$ref" ]; then
    "$BIN" render "$scene" --res "$res" --integrator "$refint" --spp "$refspp" --seed 999 -o "$ref" -q >/dev/null 2>&1
  fi
  for integrator in "$@"; do
    local out="$REF/$name-$integrator.exr"
    local line
    line=$("$BIN" render "$scene" --res "$res" --integrator "$integrator" --spp 1000000 --time "$SECS" -o "$out" 2>&1 | grep '^rendered')
    local spp=${line#*at }; spp=${spp%% spp*}
    local err
    err=$("$BIN" diff "$out" "$ref" | tail -1 | awk '{print $3}')
    "$BIN" render "$scene" --res "$res" --integrator "$integrator" --spp "$spp" -o "$OUT/$name-$integrator.png" -q >/dev/null 2>&1
    echo "| $name | $integrator | $spp | $err |"
  done
}
echo "| scene | integrator | spp in ${SECS} s | relMSE vs reference |"
echo "|---|---|---|---|"
read -r -a RUN <<< "${INTEGRATORS:-path bdpt mlt sppm photon}"
compare veach-bidir "$S/pbrt-veach-bidir/scene-v4.pbrt" 128x128 bdpt 2048 "${RUN[@]}"
compare caustic-glass "$S/pbrt-caustic-glass/caustic-glass-v4.pbrt" 140x200 bdpt 2048 "${RUN[@]}"
compare gap-room "$ROOT/scenes/gap-room.toml" 128x96 bdpt 2048 "${RUN[@]}"
