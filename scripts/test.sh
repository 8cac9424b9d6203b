#!/usr/bin/env bash
# README command 2: install, build from scratch, run every test (C++ unit tests, then the Blender suite).
source "$(dirname "$0")/common.sh"
install_packages
rm -rf "$BUILD_DIR"
build_engine
install_addon
build_scenes
echo "== C++ tests (ctest)"
# The stress suite and the fuzzer run verbosely so their counters (NaN caught, samples rejected,
# scenes rendered) reach the log; ctest's own summary line closes the step either way.
(cd "$BUILD_DIR" && ctest -R "^(Fuzz|Stress)\." -V > stress_fuzz.log 2>&1) || { cat "$BUILD_DIR/stress_fuzz.log"; exit 1; }
grep -hE "fuzz:|\[stress\]" "$BUILD_DIR/stress_fuzz.log" | sed -E 's/^[0-9]+: //' | sort -u
grep -hE "[0-9]+% tests passed" "$BUILD_DIR/stress_fuzz.log" | sed 's/^/stress and fuzz: /'
(cd "$BUILD_DIR" && ctest --output-on-failure -j "$(nproc)" -E "^(Fuzz|Stress)\.")
echo "== Blender tests (pytest inside blender --background)"
blender -b --factory-startup --addons smis_render --python "$ROOT/blender_tests/run.py" -- "$@"
