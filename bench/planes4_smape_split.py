"""Where two estimators' SMAPE differs: per-pixel SMAPE maps (mean over seeds) split by the volume's
share of the reference and by the reference's brightness, with a figure (docs/bench/planes4.md).

    OUT=/tmp/planes_smape_map /usr/bin/python3 bench/planes_smape_map.py volume_spot 5 1,2,3
    /usr/bin/python3 bench/planes4_smape_split.py volume_spot /tmp/planes_smape_map PATH,PLANES 1,2,3 [FIG.png]

Reads the images bench/planes_smape_map.py saved (DIR/<scene>_<name>_<seed>.npy and its volume-only
render DIR/<scene>_vol.npy) and bench/references/<scene>_512x384_ref.exr."""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import metrics as M


def smape_map(ref, est):
    num = np.abs(ref - est); den = np.abs(ref) + np.abs(est)
    return np.where(den > 0, num / np.where(den > 0, den, 1), 0).mean(-1)


def main():
    scene, d, names, seeds = sys.argv[1], sys.argv[2], sys.argv[3].split(","), [int(s) for s in sys.argv[4].split(",")]
    fig_path = sys.argv[5] if len(sys.argv) > 5 else os.path.join(d, "%s_split.png" % scene)
    ref = M.load_exr(os.path.join(HERE, "references", "%s_512x384_ref.exr" % scene)).astype(np.float64)[..., :3]
    vol = np.load(os.path.join(d, "%s_vol.npy" % scene))
    maps = {}
    for n in names:
        imgs = [np.load(os.path.join(d, "%s_%s_%d.npy" % (scene, n, s)))[..., :3].astype(np.float64) for s in seeds]
        maps[n] = np.mean([smape_map(ref, im) for im in imgs], 0)
        rel = np.mean([(((im - ref) ** 2) / (ref ** 2 + 0.01)).mean(-1) for im in imgs], 0)
        print("%s: SMAPE %.4f relMSE %.4g" % (n, maps[n].mean(), rel.mean()))
    frac = np.clip(vol.mean(-1) / np.maximum(ref.mean(-1), 1e-8), 0, 1)
    lum = ref.mean(-1)
    a, b = names[0], names[1]
    print("| volume share of the pixel | pixels | %s SMAPE | %s SMAPE | ratio |" % (a, b))
    print("|---|---|---|---|---|")
    for lo, hi in [(0, .2), (.2, .4), (.4, .6), (.6, .8), (.8, .95), (.95, 1.01)]:
        m = (frac >= lo) & (frac < hi)
        if m.any():
            print("| %.2f-%.2f | %.3f | %.4f | %.4f | %.2f |" % (lo, min(hi, 1), m.mean(), maps[a][m].mean(),
                                                              maps[b][m].mean(), maps[b][m].mean() / maps[a][m].mean()))
    qs = np.quantile(lum, [0, .1, .25, .5, .75, .9, 1.0])
    names_q = ["0-10%", "10-25%", "25-50%", "50-75%", "75-90%", "90-100%"]
    print("\n| reference brightness quantile | %s SMAPE | %s SMAPE | ratio | mean volume share |" % (a, b))
    print("|---|---|---|---|---|")
    for i in range(len(qs) - 1):
        m = (lum >= qs[i]) & (lum <= qs[i + 1])
        print("| %s | %.4f | %.4f | %.2f | %.2f |" % (names_q[i], maps[a][m].mean(), maps[b][m].mean(),
                                                     maps[b][m].mean() / maps[a][m].mean(), frac[m].mean()))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from scipy.ndimage import uniform_filter
    fig, ax = plt.subplots(2, 2, figsize=(12, 9))
    ax[0, 0].imshow(np.clip(ref / np.quantile(ref, .99), 0, 1)); ax[0, 0].set_title("reference")
    ax[0, 1].imshow(frac); ax[0, 1].set_title("volume share of the pixel")
    im = ax[1, 0].imshow(maps[a], vmin=0, vmax=.3); ax[1, 0].set_title(a + " SMAPE"); plt.colorbar(im, ax=ax[1, 0])
    im = ax[1, 1].imshow(uniform_filter(maps[b] - maps[a], 7), cmap="RdBu_r", vmin=-.08, vmax=.08)
    ax[1, 1].set_title("%s - %s SMAPE (7 px box)" % (b, a)); plt.colorbar(im, ax=ax[1, 1])
    plt.tight_layout(); plt.savefig(fig_path, dpi=60)


if __name__ == "__main__":
    main()
