#!/usr/bin/env bash
# Renders every scene of ../shared/scenes that Penumbra reads into docs/images/gallery/
# (small PNGs) and prints a Markdown table row per scene with its render time.
#   bash docs/gallery.sh            (from the repository, after cargo build --release)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
S="$ROOT/../shared/scenes"
OUT="$ROOT/docs/images/gallery"
BIN="$ROOT/target/release/penumbra"
mkdir -p "$OUT"
row() { # name file spp res [extra args]
  local name=$1 file=$2 spp=$3 res=$4; shift 4
  local line
  line=$("$BIN" render "$S/$file" -o "$OUT/$name.png" --spp "$spp" --res "$res" "$@" 2>&1 | grep '^rendered')
  local secs=${line#*spp in }; secs=${secs%% s:*}
  echo "| ![$name](images/gallery/$name.png) | \`$file\` | $res, $spp spp | $secs s |"
}
echo "| image | scene | resolution, samples | time (2 threads) |"
echo "|---|---|---|---|"
row mitsuba-cbox mitsuba-cbox/cbox.xml 256 256x256
row mitsuba-cbox-rgb mitsuba-cbox/cbox-rgb.xml 256 256x256
row mitsuba-bitterli mitsuba-cornell-box-bitterli/scene_v3.xml 256 256x256
row mitsuba-veach-mis mitsuba-veach-mis/integrator_direct_both.xml 64 384x256
row pbrt-cornell-box pbrt-cornell-box/scene-v4.pbrt 256 256x256
row pbrt-veach-mis pbrt-veach-mis/scene-v4.pbrt 64 384x216
row pbrt-veach-bidir pbrt-veach-bidir/scene-v4.pbrt 64 256x256
row pbrt-caustic-glass pbrt-caustic-glass/caustic-glass-v4.pbrt 64 210x300
row pbrt-killeroo-simple pbrt-killeroos/killeroo-simple.pbrt 64 342x256
row mesh-bunny mesh-stanford-bunny/bun_zipper.ply 64 320x240
row mesh-teapot mesh-utah-teapot/teapot.obj 64 320x240
row mesh-suzanne mesh-suzanne/suzanne.obj 64 320x240
row gltf-2CylinderEngine gltf-2CylinderEngine/glTF-Binary/2CylinderEngine.glb 64 256x256
row gltf-BoxTextured gltf-BoxTextured/glTF-Binary/BoxTextured.glb 64 320x240
row gltf-Cameras gltf-Cameras/Cameras.gltf 64 256x256
row gltf-DamagedHelmet gltf-DamagedHelmet/glTF/DamagedHelmet.gltf 64 320x240
