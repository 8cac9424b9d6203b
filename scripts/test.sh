#!/usr/bin/env bash
# README command 2: install, build from scratch, run every test (C++ unit tests, then the Blender suite).
source "$(dirname "$0")/common.sh"
install_packages
rm -rf "$BUILD_DIR"
build_engine
install_addon
build_scenes
echo "== C++ tests (ctest)"
(cd "$BUILD_DIR" && ctest --output-on-failure -j "$(nproc)")
echo "== Blender tests (pytest inside blender --background)"
blender -b --factory-startup --addons smis_render --python "$ROOT/blender_tests/run.py" -- "$@"
