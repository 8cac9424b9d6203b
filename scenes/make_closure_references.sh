#!/bin/sh
# Render the Cycles reference of the closure parity test (blender_tests/test_closures.py).
#
#   scenes/make_closure_references.sh [WORKDIR] [SET]
#
# SET: closures (the default), closures_principled, closures_beckmann, closures_multiglass, closures_aniso,
# closures_msaniso or closures_multiglass_world
# (scenes/closures.py's sets); SET.blend, SET.exr.
# 1. builds SET.blend with scenes/closures.py into WORKDIR (default /tmp/smis_closure_reference_work),
# 2. renders it twice with Cycles (CPU, unbiased settings, BOX filter 1 px), seeds 1 and 2
#    (scenes/make_cycles_references.py), SPP samples each,
# 3. averages the two into blender_tests/references/closures.exr and records the measured noise in
#    closures.exr.json (scenes/combine_references.py, 8x8 blocks).
set -e
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${1:-/tmp/smis_closure_reference_work}
SET=${2:-closures}
SPP=${SPP:-4096}
REFS="$ROOT/blender_tests/references"
BLENDER=${BLENDER:-blender}
mkdir -p "$WORK" "$REFS"

"$BLENDER" -b --factory-startup --python "$ROOT/scenes/closures.py" -- "$WORK" "$SET"
for seed in 1 2; do
    "$BLENDER" -b "$WORK/$SET.blend" --python "$ROOT/scenes/make_cycles_references.py" -- \
        "$WORK/${SET}_seed$seed.exr" "$SPP" "$seed"
done
"$BLENDER" -b --factory-startup --python "$ROOT/scenes/combine_references.py" -- \
    "$REFS/$SET.exr" "$WORK/${SET}_seed1.exr" "$WORK/${SET}_seed2.exr" 8
