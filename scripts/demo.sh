#!/usr/bin/env bash
# README command 1: install, build, link the add-on, render the demo scene through Blender.
source "$(dirname "$0")/common.sh"
install_packages
build_engine
install_addon
build_scenes
mkdir -p "$ROOT/out"
echo "== rendering scenes/demo.blend with the SMIS engine"
blender -b --factory-startup --addons smis_render "$ROOT/scenes/demo.blend" -E SMIS \
    --python-expr "import bpy; bpy.context.scene.smis.samples = ${SMIS_DEMO_SAMPLES:-256}" \
    -o "$ROOT/out/demo_####" -F OPEN_EXR -f 1
# The PNG preview goes through OpenColorIO with Blender's config and the scene's view transform.
/usr/bin/python3 "$ROOT/scripts/exr_to_png.py" "$ROOT/out/demo_0001.exr" "$ROOT/out/demo_0001.png" --view Filmic
echo "== wrote $ROOT/out/demo_0001.exr and $ROOT/out/demo_0001.png"
