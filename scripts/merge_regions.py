"""Merge region renders (Blender render borders) into the full frame.

A farm splits one frame into regions by rendering the same .blend with different
render borders; each job writes an EXR (plain or multilayer, every pass kept). With
"Crop to Render Region" on, a file holds only its region; with it off, it is
full-frame and black outside the region. Either kind can be merged:

    /usr/bin/python3 scripts/merge_regions.py --resolution 1920 1080 -o frame.exr \\
        left.exr@0,0.5,0,1 right.exr@0.5,1,0,1

Each input is FILE@MIN_X,MAX_X,MIN_Y,MAX_Y with the border fractions given to
Blender (scene.render.border_min_x, border_max_x, border_min_y, border_max_y);
--resolution is the full output size after the resolution percentage. The pixel
windows are computed exactly as Blender computes them, so adjacent regions tile
without gaps or overlaps, and a merge of renders made with the same seed equals the
full render pixel for pixel.
"""
import argparse
import importlib.util
import os
import sys
from types import SimpleNamespace

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The native module directly: the add-on package itself needs bpy.
sys.path.insert(0, os.path.join(ROOT, "addon", "smis_render"))
import _smis  # noqa: E402


def _load_camera_module():
    """The add-on's border arithmetic (sync/camera.py needs only numpy), so there is one copy of it."""
    path = os.path.join(ROOT, "addon", "smis_render", "sync", "camera.py")
    spec = importlib.util.spec_from_file_location("smis_border", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


border_window_of = _load_camera_module().border_window


def region_window(border, width, height):
    """(x0, y0, x1, y1) of a border (min_x, max_x, min_y, max_y), y from the bottom, as Blender."""
    render = SimpleNamespace(use_border=True, border_min_x=border[0], border_max_x=border[1],
                             border_min_y=border[2], border_max_y=border[3])
    return border_window_of(render, width, height)


def merge(regions, width, height):
    """regions: [(channels dict from _smis.read_exr_channels, border)]. Returns the merged channels
    and the number of pixels no region covered."""
    names = set(regions[0][0])
    out = {name: np.zeros((height, width), np.float32) for name in names}
    covered = np.zeros((height, width), bool)
    for channels, border in regions:
        if set(channels) != names:
            raise ValueError("regions have different channels: %s vs %s" % (sorted(channels), sorted(names)))
        x0, y0, x1, y1 = region_window(border, width, height)
        shape = next(iter(channels.values())).shape
        if shape == (height, width):          # crop off: full frame, black outside the region
            crop = (slice(y0, y1), slice(x0, x1))
        elif shape == (y1 - y0, x1 - x0):     # crop on: the region only
            crop = (slice(None), slice(None))
        else:
            raise ValueError("a %dx%d image is neither the full frame %dx%d nor its region %dx%d"
                             % (shape[1], shape[0], width, height, x1 - x0, y1 - y0))
        for name, pixels in channels.items():
            out[name][y0:y1, x0:x1] = pixels[crop]
        covered[y0:y1, x0:x1] = True
    return out, int((~covered).sum())


def parse_region(arg):
    path, sep, fractions = arg.rpartition("@")
    values = [float(v) for v in fractions.split(",")] if sep else []
    if not sep or len(values) != 4:
        raise argparse.ArgumentTypeError("expected FILE@MIN_X,MAX_X,MIN_Y,MAX_Y, got %r" % arg)
    return path, values


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("regions", nargs="+", type=parse_region, metavar="FILE@MIN_X,MAX_X,MIN_Y,MAX_Y")
    ap.add_argument("--resolution", nargs=2, type=int, required=True, metavar=("WIDTH", "HEIGHT"))
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args(argv)
    width, height = args.resolution
    regions = [(_smis.read_exr_channels(path), border) for path, border in args.regions]
    merged, uncovered = merge(regions, width, height)
    _smis.write_exr_channels(args.output, merged)
    if uncovered:
        print("merge_regions: warning: %d pixels are in no region (left black)" % uncovered, file=sys.stderr)
    print("merge_regions: %d regions -> %s (%dx%d, %d channels)"
          % (len(regions), args.output, width, height, len(merged)))


if __name__ == "__main__":
    main()
