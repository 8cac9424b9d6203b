# Shared set-up steps for the README's commands: install Debian packages when missing, build, and make
# the add-on visible to Blender. Sourced by demo.sh and test.sh; every step is idempotent.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${SMIS_BUILD_DIR:-$ROOT/build}"
PACKAGES=(blender libembree-dev libopenexr-dev libopencolorio-dev libtbb-dev pybind11-dev python3-dev
          python3-pytest python3-numpy python3-matplotlib libgtest-dev libpng-dev zlib1g-dev cmake g++ make
          openexr xvfb xauth)

install_packages() {
    local missing=()
    for p in "${PACKAGES[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    if [ ${#missing[@]} -gt 0 ]; then
        echo "== installing: ${missing[*]}"
        local sudo=""
        [ "$(id -u)" -eq 0 ] || sudo="sudo"
        $sudo apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
    fi
}

build_engine() {
    echo "== building into $BUILD_DIR"
    cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$BUILD_DIR" -j "$(nproc)"
}

# Blender finds add-ons in its user scripts folder; a symlink keeps the checkout the source of truth.
install_addon() {
    local addons="${BLENDER_USER_SCRIPTS:-$HOME/.config/blender/3.4/scripts}/addons"
    mkdir -p "$addons"
    ln -sfn "$ROOT/addon/smis_render" "$addons/smis_render"
    echo "== add-on linked: $addons/smis_render -> $ROOT/addon/smis_render"
}

build_scenes() {
    if [ ! -f "$ROOT/scenes/cornell.blend" ] || [ ! -f "$ROOT/scenes/spectral_glass.blend" ] ||
       [ "$ROOT/scenes/build_scenes.py" -nt "$ROOT/scenes/cornell.blend" ]; then
        echo "== building scenes"
        blender -b --factory-startup --python "$ROOT/scenes/build_scenes.py" -- "$ROOT/scenes" >/dev/null
    fi
}
