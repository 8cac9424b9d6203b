"""A quick probe of a volume scene before its benchmark: a reference of our PATH alone (REF_SPP
samples, cached beside the .blend as .ref<N>.npy), then PATH, photon planes (PLANES_SMIS_EXACT, 512
planes, the integrator's own path samples) and planes with plane_path_pixel_samples 0 (AUTO) at the
given budgets and seeds, one after the other; prints SMAPE and relMSE against that reference. The
reference's own noise is in every number (a floor shared by all rows), so this is for choosing a
scene's set-up, not for a result: bench/single_scattering_equal_time.py measures.

    BLENDER_USER_SCRIPTS=.bl_scripts /usr/bin/python3 bench/volume_probe.py SCENE.blend REF_SPP 5,15 [1,2]
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import metrics as M  # noqa: E402
from render import remove  # noqa: E402
# The benchmark's render settings, so that the probe renders what the benchmark will.
from single_scattering_equal_time import ESTIMATORS as BENCH_ESTIMATORS, smis  # noqa: E402

PLANES = BENCH_ESTIMATORS["PLANES_SMIS_EXACT"]
ESTIMATORS = [("PATH", BENCH_ESTIMATORS["PATH"]), ("PLANES", PLANES),
              ("AUTO", dict(PLANES, plane_path_pixel_samples=0))]


def main():
    blend, ref_spp = sys.argv[1], int(sys.argv[2])
    budgets = [float(b) for b in sys.argv[3].split(",")]
    seeds = [int(s) for s in sys.argv[4].split(",")] if len(sys.argv) > 4 else [1]
    cached = "%s.ref%d.npy" % (blend, ref_spp)
    if os.path.exists(cached):
        ref = np.load(cached)
    else:
        run = smis(blend, BENCH_ESTIMATORS["PATH"], 1001, samples=ref_spp)
        ref = run.image.astype(np.float64)
        np.save(cached, ref)
        print("reference: %d spp in %.1f s" % (ref_spp, run.seconds), flush=True)
        remove(run)
    for budget in budgets:
        for seed in seeds:
            for name, settings in ESTIMATORS:
                run = smis(blend, settings, seed, budget)
                img = run.image.astype(np.float64)
                print("%-6s %5.0f s seed %d: SMAPE %.4f relMSE %.5f, %s path samples per pixel"
                      % (name, budget, seed, M.smape(ref, img), M.relmse(ref, img), run.samples_done), flush=True)
                remove(run)


if __name__ == "__main__":
    main()
