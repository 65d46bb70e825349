#!/usr/bin/env bash
# The Mitsuba suite for several binaries in turn, round after round, so that each
# binary's figures meet the machine's slow and fast spells alike; prints each run's
# SUMMARY line (samples/s and equal-error efficiency against Mitsuba 3 llvm_ad_rgb).
# Report the min and median of the rounds per binary.
#
# usage: docs/checks/suite_alternating.sh ROUNDS BIN [BIN...]
#   (after `../shared/anchors/run.sh setup`; PENUMBRA_SIMD and other variables pass through)
set -euo pipefail
[ $# -ge 2 ] || { sed -n 2,9p "$0"; exit 2; }
rounds=$1; shift
here=$(cd "$(dirname "$0")/../.." && pwd)
run="$here/../shared/anchors/run.sh"
[ -f "$run" ] || { echo "error: $run not found (../shared is needed)" >&2; exit 1; }
for r in $(seq 1 "$rounds"); do
  for bin in "$@"; do
    echo "== round $r: $bin"
    bash "$run" suite "$(realpath "$bin")" --spp 64 --repeats 3 2>&1 | grep SUMMARY
  done
done
