"""One render of a volume scene against its cached reference, at a fixed amount of work: prints SMAPE
and relMSE and the integrator's statistics (docs/bench/planes3.md).

    /usr/bin/python3 bench/planes3_fixed_work.py SCENE ESTIMATOR SEED BUDGET SAMPLES ['{"key": value}']

e.g. `volume_spot PLANES_SMIS_EXACT 1 0 1 '{"plane_surface_samples": 16}'` (one plane set, 16 path samples
per pixel) or `volume_spot PATH 1 0 16`. KEEP=FILE.npy saves the image."""
import sys, os, json, time
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import single_scattering_equal_time as S
import metrics as M
from render import remove
scene, est, seed, budget, samples = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
extra = json.loads(sys.argv[6]) if len(sys.argv) > 6 else {}
settings = dict(S.ESTIMATORS.get(est) or dict(S.PLANES, volume_estimator=est), **extra)
ref, rec = S.reference(scene, False, S.REF_SECONDS, 0)
run = S.smis(S.scene_blend(scene), settings, seed, budget, samples)
m = M.metrics(ref, run.image, 0.01)
print("RESULT", scene, est, extra, "secs %.2f done %s smape %.4f relmse %.4g" % (run.seconds, run.samples_done, m["smape"], m["relmse"]))
for l in run.output.splitlines():
    if "stat" in l.lower() or "plane" in l.lower() or "seconds" in l: print("  ", l[:400])
if os.environ.get("KEEP"):
    import numpy as np; np.save(os.environ["KEEP"], run.image)
remove(run)
