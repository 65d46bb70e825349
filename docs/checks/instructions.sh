#!/usr/bin/env bash
# Instructions and simulated branch mispredictions of one-thread renders of the suite's
# scenes at a small size (cachegrind), for changes too small for wall-clock time to show
# on a shared machine. Valgrind runs the AVX2 kernels (it has no AVX-512).
#
# usage: docs/checks/instructions.sh BIN [OUT_DIR]   (cachegrind files go to OUT_DIR)
set -euo pipefail
[ $# -ge 1 ] || { sed -n 2,7p "$0"; exit 2; }
bin=$(realpath "$1"); dir=${2:-$(mktemp -d)}; mkdir -p "$dir"
here=$(cd "$(dirname "$0")/../.." && pwd); shared="$here/../shared"
[ -d "$shared" ] || { echo "error: $shared not found" >&2; exit 1; }
measure() {
  local name=$1 scene=$2; shift 2
  (cd "$(dirname "$scene")" && valgrind --tool=cachegrind --cache-sim=no --branch-sim=yes \
    --cachegrind-out-file="$dir/$name.out" "$bin" render "$(basename "$scene")" "$@" \
    --threads 1 -q -o "$dir/$name.exr" 2>&1) |
    awk -v n="$name" '/I +refs/ {i=$NF} /Mispredicts:/ {m=$3} END {print n": instructions " i ", mispredicted branches " m}'
}
measure bitterli-box "$shared/scenes/mitsuba-cornell-box-bitterli/scene_v3.xml" -D resx=128 -D resy=128 --spp 2
measure env-materials "$shared/scenes/mitsuba-env-materials/scene.xml" --res 160x100 --spp 4
measure cbox "$shared/references/mitsuba-cbox/cbox.xml" --res 128x128 --spp 2
echo "cachegrind files in $dir (cg_annotate FILE)"
