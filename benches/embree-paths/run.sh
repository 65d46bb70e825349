#!/bin/bash
# Embree 3 on the rays of Penumbra's path tracer, one by one and in 16-wide packets in
# wavefront order (docs/performance.md, "Where Mitsuba's time goes"). Needs
# `../shared/anchors/run.sh setup` (Embree headers, the Python venv; ANCHORS_VENV as there).
# Built in a scratch worktree at commit 9c8f191 with raydump.patch applied: the patch
# instruments that commit's path-at-a-time tracer. Every later change to the path tracer
# kept its images bit-identical (docs/performance.md), so it casts the same rays; the BVH
# timed at the end (`bench accel` of that build) is also unchanged since.
# From the repository:
#   bash benches/embree-paths/run.sh [SPP]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
SPP=${1:-4}
WORK=${TMPDIR:-/tmp}/penumbra-embree-paths
PY=${ANCHORS_VENV:-$HOME/.cache/penumbra-anchors/venv}/bin/python
rm -rf "$WORK" && mkdir -p "$WORK"
git -C "$ROOT" worktree prune
git -C "$ROOT" worktree add -q --detach "$WORK/src" 9c8f191
trap 'git -C "$ROOT" worktree remove --force "$WORK/src"' EXIT
git -C "$WORK/src" apply "$ROOT/benches/embree-paths/raydump.patch"
(cd "$WORK/src" && cargo build --release -q)
PENUMBRA_RAYDUMP="$WORK/raydump.bin" "$WORK/src/target/release/penumbra" render "$ROOT/scenes/cbox-mitsuba.toml" \
    --spp "$SPP" --threads 1 -o "$WORK/cbox.exr" --quiet
"$PY" "$ROOT/benches/embree-paths/scene_ply.py" "$ROOT/scenes/cbox-mitsuba.toml" "$WORK/cbox.ply"
cc -O2 -o "$WORK/embree_paths" "$ROOT/benches/embree-paths/embree_paths.c" -lembree3 -lm
"$WORK/embree_paths" "$WORK/cbox.ply" "$WORK/raydump.bin"
# Penumbra's BVH on the same closest-hit rays, one by one in path order.
"$PY" - "$WORK" <<'PYEOF'
import sys, numpy as np
w = sys.argv[1]
d = np.fromfile(w + "/raydump.bin", dtype=np.dtype([("id", "<u4"), ("depth", "<u4"), ("kind", "<u4"), ("r", "<f4", 7)]))
d[d["kind"] == 0]["r"][:, :6].astype("<f4").tofile(w + "/rays_closest.f32")
PYEOF
"$WORK/src/target/release/penumbra" bench accel "$WORK/cbox.ply" --rays "$WORK/rays_closest.f32" --accel bvh --threads 1 --repeats 5
