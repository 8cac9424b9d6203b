#!/bin/sh
# Render the Cycles reference of the HDRI-lit scene (issue 18) into blender_tests/references/.
#
#   scenes/make_world_reference.sh [WORKDIR]
#
# As scenes/make_references.sh does for the .blend scenes: scenes/world_hdri.py builds the scene
# (no .blend: the HDRI is one of Blender's bundled studio lights) and renders it with Cycles (CPU,
# unbiased settings, BOX filter) with seeds 1 and 2; scenes/combine_references.py averages the two
# renders into blender_tests/references/world_hdri.exr and records the measured noise (8x8 blocks)
# in world_hdri.exr.json. About 2.5 min here (2 x 4096 spp at 96 x 72).
set -e
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${1:-/tmp/smis_reference_work}
REFS="$ROOT/blender_tests/references"
BLENDER=${BLENDER:-blender}
SPP=4096
mkdir -p "$WORK" "$REFS"
for seed in 1 2; do
    "$BLENDER" -b --factory-startup --python "$ROOT/scenes/world_hdri.py" -- "$WORK/world_hdri_seed$seed.exr" "$SPP" "$seed"
done
"$BLENDER" -b --factory-startup --python "$ROOT/scenes/combine_references.py" -- \
    "$REFS/world_hdri.exr" "$WORK/world_hdri_seed1.exr" "$WORK/world_hdri_seed2.exr" 8
