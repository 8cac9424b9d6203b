#!/bin/sh
# Render the Cycles references of the hair parity test (blender_tests/test_hair.py).
#
#   scenes/make_hair_references.sh [WORKDIR] [SCENE ...]
#
# For each scene (default: all of test_hair.py's): builds hair_SCENE.blend with scenes/hair.py into
# WORKDIR (default /tmp/smis_hair_reference_work), renders it twice with Cycles (CPU, unbiased
# settings, BOX filter 1 px; scenes/make_cycles_references.py) with seeds 1 and 2, SPP samples each
# (default 512), and averages the two into blender_tests/references/hair_SCENE.exr with the measured
# noise in hair_SCENE.exr.json (scenes/combine_references.py, 8x8 blocks).
set -e
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=${1:-/tmp/smis_hair_reference_work}
[ $# -gt 0 ] && shift
SCENES=${*:-"diffuse diffuse_curves hair_bsdf_direct principled_color_direct principled_melanin_direct principled_absorption_direct principled_random_direct principled_random_curves_direct principled_color_sun principled_color info_intercept_direct info_geometry_direct info_intercept_curves_direct info_geometry_curves_direct emissive_sun uv_direct uv_curves_direct diffuse_ribbons_close diffuse_close_moving diffuse_curves_close_moving vcol_direct"}
SPP=${SPP:-256}
REFS="$ROOT/blender_tests/references"
BLENDER=${BLENDER:-blender}
mkdir -p "$WORK" "$REFS"

for scene in $SCENES; do
    "$BLENDER" -b --factory-startup --python "$ROOT/scenes/hair.py" -- "$WORK" "$scene"
    for seed in 1 2; do
        "$BLENDER" -b "$WORK/hair_$scene.blend" --python "$ROOT/scenes/make_cycles_references.py" -- \
            "$WORK/hair_${scene}_seed$seed.exr" "$SPP" "$seed"
    done
    "$BLENDER" -b --factory-startup --python "$ROOT/scenes/combine_references.py" -- \
        "$REFS/hair_$scene.exr" "$WORK/hair_${scene}_seed1.exr" "$WORK/hair_${scene}_seed2.exr" 8
done
