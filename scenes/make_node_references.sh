#!/bin/sh
# Render the Cycles references of the per-node parity test (blender_tests/test_node_parity.py).
#
#   scenes/make_node_references.sh [WORKDIR]
#
# 1. builds node_parity_emission.blend, node_parity_lit.blend and node_parity_geometry.blend with
#    scenes/node_parity.py
#    into WORKDIR (default /tmp/smis_node_reference_work),
# 2. renders each scene twice with Cycles (CPU, unbiased settings, BOX filter 1 px) with seeds
#    1 and 2 (scenes/make_cycles_references.py),
# 3. averages the two renders into blender_tests/references/node_parity_SCENE.exr and records
#    the measured noise in node_parity_SCENE.exr.json (scenes/combine_references.py, 8x8 blocks).
# Samples per render: see SPP below (the reference has 2x that many): the emission tiles need
# few (camera rays only: 2 x 128 = 256 spp), the geometry objects 2 x 1024 (per-face values: sharp edges in every block), the lit scene 2 x 2048 = 4096 spp.
# About 3 minutes on 2 cores.
set -e
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${1:-/tmp/smis_node_reference_work}
REFS="$ROOT/blender_tests/references"
BLENDER=${BLENDER:-blender}
mkdir -p "$WORK" "$REFS"

"$BLENDER" -b --factory-startup --python "$ROOT/scenes/node_parity.py" -- "$WORK"

for entry in node_parity_emission:128 node_parity_lit:2048 node_parity_geometry:1024; do
    scene=${entry%%:*}
    spp=${entry##*:}
    for seed in 1 2; do
        "$BLENDER" -b "$WORK/$scene.blend" \
            --python "$ROOT/scenes/make_cycles_references.py" -- \
            "$WORK/${scene}_seed$seed.exr" "$spp" "$seed"
    done
    "$BLENDER" -b --factory-startup --python "$ROOT/scenes/combine_references.py" -- \
        "$REFS/$scene.exr" "$WORK/${scene}_seed1.exr" "$WORK/${scene}_seed2.exr" 8
done
