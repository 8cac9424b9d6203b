"""Display-referred PNG from a scene-linear EXR, through OpenColorIO with Blender's own config.

    /usr/bin/python3 scripts/exr_to_png.py IN.exr OUT.png [--view Filmic] [--look None] [--exposure 0]
"""
import argparse
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The native module directly: the add-on package itself needs bpy.
sys.path.insert(0, os.path.join(ROOT, "addon", "smis_render"))
import _smis  # noqa: E402

BLENDER_OCIO = "/usr/share/blender/datafiles/colormanagement/config.ocio"


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("exr")
    ap.add_argument("png")
    ap.add_argument("--layer", default="", help="channel prefix in a multilayer EXR, e.g. ViewLayer.Combined")
    ap.add_argument("--display", default="sRGB")
    ap.add_argument("--view", default="Filmic")
    ap.add_argument("--look", default="None")
    ap.add_argument("--exposure", type=float, default=0.0)
    ap.add_argument("--gamma", type=float, default=1.0)
    ap.add_argument("--config", default=BLENDER_OCIO)
    a = ap.parse_args()
    img = _smis.read_exr(a.exr, a.layer)
    _smis.write_png(a.png, img, a.config, a.display, a.view, a.look, a.exposure, a.gamma)
    print(f"wrote {a.png} ({img.shape[1]}x{img.shape[0]}, view {a.view})")


if __name__ == "__main__":
    main()
