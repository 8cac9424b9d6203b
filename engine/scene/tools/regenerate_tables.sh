#!/bin/sh
# Rewrite the committed random-walk tables (engine/scene/tables/) with their generators, after a change to
# a walk (scene/ggx_walk.h), a layout or a generator (the WalkTables.* tests fail until then):
#
#   engine/scene/tools/regenerate_tables.sh [BUILD_DIR]     (default: build; about 150 s of CPU)
set -e
ROOT=$(cd "$(dirname "$0")/../../.." && pwd)
BUILD=${1:-$ROOT/build}
cmake --build "$BUILD" --target smis_ggx_multiple_gen smis_ggx_glass_gen smis_ggx_aniso_gen
for table in multiple glass aniso; do
    "$BUILD/engine/smis_ggx_${table}_gen" "$ROOT/engine/scene/tables/ggx_${table}_table.inc"
done
