#!/bin/sh
# Render the Cycles reference images in blender_tests/references/.
#
#   scenes/make_references.sh [WORKDIR]
#
# 1. rebuilds scenes/*.blend with scenes/build_scenes.py,
# 2. renders each scene twice with Cycles (CPU, unbiased settings, BOX filter)
#    with seeds 1 and 2 (scenes/make_cycles_references.py) into WORKDIR
#    (default /tmp/smis_reference_work),
# 3. averages the two renders into blender_tests/references/SCENE.exr and
#    records the measured noise in SCENE.exr.json (scenes/combine_references.py).
# Sample counts per render: see SPP below (the reference has 2x that many).
set -e
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${1:-/tmp/smis_reference_work}
REFS="$ROOT/blender_tests/references"
BLENDER=${BLENDER:-blender}
mkdir -p "$WORK" "$REFS"

"$BLENDER" -b --factory-startup --python "$ROOT/scenes/build_scenes.py" -- "$ROOT/scenes"

for entry in cornell:20480 cornell_diffuse:8192 volume_planes:32768 principled_coat:8192; do
    scene=${entry%%:*}
    spp=${entry##*:}
    for seed in 1 2; do
        "$BLENDER" -b "$ROOT/scenes/$scene.blend" \
            --python "$ROOT/scenes/make_cycles_references.py" -- \
            "$WORK/${scene}_seed$seed.exr" "$spp" "$seed"
    done
    "$BLENDER" -b --factory-startup --python "$ROOT/scenes/combine_references.py" -- \
        "$REFS/$scene.exr" "$WORK/${scene}_seed1.exr" "$WORK/${scene}_seed2.exr" 4
done
