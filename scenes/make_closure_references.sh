#!/bin/sh
# Render the Cycles reference of the closure parity test (blender_tests/test_closures.py).
#
#   scenes/make_closure_references.sh [WORKDIR]
#
# 1. builds closures.blend with scenes/closures.py into WORKDIR (default /tmp/smis_closure_reference_work),
# 2. renders it twice with Cycles (CPU, unbiased settings, BOX filter 1 px), seeds 1 and 2
#    (scenes/make_cycles_references.py), SPP samples each,
# 3. averages the two into blender_tests/references/closures.exr and records the measured noise in
#    closures.exr.json (scenes/combine_references.py, 8x8 blocks).
set -e
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${1:-/tmp/smis_closure_reference_work}
SPP=${SPP:-4096}
REFS="$ROOT/blender_tests/references"
BLENDER=${BLENDER:-blender}
mkdir -p "$WORK" "$REFS"

"$BLENDER" -b --factory-startup --python "$ROOT/scenes/closures.py" -- "$WORK"
for seed in 1 2; do
    "$BLENDER" -b "$WORK/closures.blend" --python "$ROOT/scenes/make_cycles_references.py" -- \
        "$WORK/closures_seed$seed.exr" "$SPP" "$seed"
done
"$BLENDER" -b --factory-startup --python "$ROOT/scenes/combine_references.py" -- \
    "$REFS/closures.exr" "$WORK/closures_seed1.exr" "$WORK/closures_seed2.exr" 8
