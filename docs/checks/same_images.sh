#!/usr/bin/env bash
# Whether a change kept the images: renders a fixed list of scene/integrator pairs (small,
# 96x72 at 4 spp, seed fixed) with two binaries and compares the EXR files byte for byte.
# A change meant to be exact (a faster traversal, a new schedule) must print "different 0".
#
# usage: docs/checks/same_images.sh BASE_BIN NEW_BIN
#   (run from anywhere; the Mitsuba scenes of ../shared are skipped, with a note, when it is
#   absent)
set -euo pipefail
[ $# -eq 2 ] || { sed -n 2,8p "$0"; exit 2; }
base=$(realpath "$1"); new=$(realpath "$2")
here=$(cd "$(dirname "$0")/../.." && pwd)
scenes="$here/scenes"; shared="$here/../shared"
pairs=(
  "$scenes/cornell.toml path" "$scenes/cornell.toml bdpt" "$scenes/cornell.toml direct"
  "$scenes/cornell.toml whitted" "$scenes/materials.toml path" "$scenes/materials.toml bdpt"
  "$scenes/materials.toml direct" "$scenes/glossy-env.toml path" "$scenes/glossy-env.toml direct"
  "$scenes/glossy-env.toml bdpt" "$scenes/refraction.toml path" "$scenes/refraction.toml whitted"
  "$scenes/spheres.toml path" "$scenes/spheres.toml bdpt" "$scenes/veach-mis.toml direct"
  "$scenes/veach-mis.toml path" "$scenes/box-light.toml path" "$scenes/gap-room.toml path"
  "$scenes/whitted.toml whitted" "$scenes/cbox-mitsuba.toml path" "$scenes/cbox-mitsuba.toml mlt"
  "$scenes/bunny.toml path" "$scenes/teapot-stadium.toml path"
)
if [ -d "$shared" ]; then
  pairs+=(
    "$shared/scenes/mitsuba-env-materials/scene.xml path"
    "$shared/scenes/mitsuba-env-materials/scene.xml bdpt"
    "$shared/scenes/mitsuba-cornell-box-bitterli/scene_v3.xml path"
    "$shared/references/mitsuba-cbox/cbox.xml path"
  )
else
  echo "note: $shared is absent: its Mitsuba scenes are skipped"
fi
out=$(mktemp -d); trap 'rm -rf "$out"' EXIT
same=0; differ=0; failed=0; i=0
for pair in "${pairs[@]}"; do
  read -r scene integrator <<<"$pair"; i=$((i + 1))
  ok=1
  for side in base new; do
    bin=$base; [ $side = new ] && bin=$new
    (cd "$(dirname "$scene")" && "$bin" render "$(basename "$scene")" --integrator "$integrator" \
      --res 96x72 --spp 4 --seed 7 --threads 2 -q -o "$out/$side$i.exr") >/dev/null 2>&1 || ok=0
  done
  if [ $ok = 0 ]; then failed=$((failed + 1)); echo "failed to render: $pair"
  elif cmp -s "$out/base$i.exr" "$out/new$i.exr"; then same=$((same + 1))
  else differ=$((differ + 1)); echo "different: $pair"; fi
done
echo "identical $same, different $differ, failed $failed"
