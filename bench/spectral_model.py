"""Spectral variance of one path on the Fig. 8 scene, without rendering: for a path that reflects an
F10 light off measured gold (normal-incidence Fresnel of the Au table), the variance of the per-path
RGB estimate sum_i f(l_i) rgb(l_i) / (n p(l_i)) over the wavelength sets alone, relative to the squared
exact value (sum over channels). This is the part of SMIS's error that BRUTE_FORCE (512 strata) does
not have, for each candidate importance density p and each pattern of n wavelengths:

    /usr/bin/python3 bench/spectral_model.py

Densities: observer response x F10 (the light mixture of the scene), with 5% uniform mixed in as the
engine does (spectral_scene.cpp); the observer response is ybar, xbar + ybar + zbar, sum |rgb|, the
length |rgb| of the RGB matching functions (the engine's choice), or |rgb| x R_Au (a material-aware
density the engine does not build, as a bound on what knowing the material would bring).
Patterns: "jittered" l_i = P^-1((i + u_i) / n) with n independent u_i, "shared" one u for all
strata (the engine's SMIS), "independent" (SMIS_INDEPENDENT).
"""
import os

import numpy as np

DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "engine", "spectral", "data")
XYZ_TO_RGB = np.array([[3.2404542, -1.5371385, -0.4985314], [-0.9692660, 1.8760108, 0.0415560],
                       [0.0556434, -0.2040259, 1.0572252]])
Y_INTEGRAL = 106.856895


def _table(name, col, lam):
    a = np.genfromtxt(os.path.join(DATA, name), delimiter=",", skip_header=1)
    return np.interp(lam, a[:, 0], a[:, col], left=0.0, right=0.0)


def model(trials=200000, seed=1):
    """Rows (density, n, pattern, relative per-path variance)."""
    lam = np.arange(360, 830) + 0.5  # the engine's 1 nm bins
    xyz = np.stack([_table("cie1931_2deg_xyz.csv", c, lam) for c in (1, 2, 3)], 1)
    rgb = xyz @ XYZ_TO_RGB.T / Y_INTEGRAL
    light = _table("illuminant_F10_1nm.csv", 1, lam)
    n_au, k_au = _table("metal_Au.csv", 1, lam), _table("metal_Au.csv", 2, lam)
    reflectance = ((n_au - 1) ** 2 + k_au ** 2) / ((n_au + 1) ** 2 + k_au ** 2)
    f = (reflectance * light)[:, None] * rgb
    exact = f.sum(0)
    norm = np.linalg.norm(rgb, axis=1)
    densities = [("ybar x F10", xyz[:, 1] * light), ("(xbar+ybar+zbar) x F10", xyz.sum(1) * light),
                 ("sum|rgb| x F10", np.abs(rgb).sum(1) * light), ("|rgb| x F10 (engine)", norm * light),
                 ("|rgb| x R_Au x F10", norm * reflectance * light)]
    rng = np.random.default_rng(seed)
    rows = []
    for name, w in densities:
        p = 0.95 * w / w.sum() + 0.05 / len(w)
        cdf = np.concatenate([[0.0], np.cumsum(p)])
        for n, pattern in ((1, "-"), (4, "jittered"), (4, "shared"), (4, "independent"), (8, "shared"),
                           (16, "shared")):
            strata = np.arange(n)[None, :]
            if pattern == "independent":
                u = rng.random((trials, n))
            elif pattern == "shared":
                u = (strata + rng.random((trials, 1))) / n
            else:
                u = (strata + rng.random((trials, n))) / n
            b = np.clip(np.searchsorted(cdf, u, side="right") - 1, 0, len(p) - 1)
            est = (f[b] / p[b][..., None]).mean(1)
            rows.append((name, n, pattern, float(est.var(0).sum() / (exact ** 2).sum())))
    return rows


if __name__ == "__main__":
    for name, n, pattern, v in model():
        print("%-26s n=%2d %-12s relative variance per path %.4f" % (name, n, pattern, v))
