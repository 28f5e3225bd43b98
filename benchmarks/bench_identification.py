"""Cost vs error of the numerical verification of Eq. (5.20): how many contact directions does it take?

The constrained minimisation (5.12) is solved over three families of direction sets and its E, nu are compared
with the closed form (5.20) (Kn/Kt = 2.5, Table 5.4):

- ``gauss``: the product Gauss rule ``abrakit.tensors.sphere_quadrature(degree)``, degree 2 ... 60;
  exact (round-off) from degree 4 on, because Eq. (5.18) needs fourth moments only;
- ``fibonacci``: a Fibonacci lattice of m equally weighted directions (a well-spread finite fabric);
- ``random``: m random directions in +/- pairs (a finite isotropic random fabric, median of 3 seeds).

The error is ``max(|E/E_5.20 - 1|, |nu/nu_5.20 - 1|, anisotropy)``; the runtime is the best of a few repeats
of :func:`abrakit.identification.numerical_elastic_constants`. Writes ``identification.{csv,json,png}``.

Run: ``python benchmarks/bench_identification.py [--quick] [--outdir DIR]``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from _common import command_line, save_figure

from abrakit import identification as I
from abrakit.io import CurveWriter, read_curve, write_json
from abrakit.tensors import sphere_quadrature

FAMILIES = {"gauss": 0, "fibonacci": 1, "random": 2}
KN, RATIO, RADIUS = 1.0e7, 1.0 / 2.5, 1.0e-3  # N/m, Kt/Kn, m
RHO_C = I.contact_density(6.0, 0.35, RADIUS)


def fibonacci_directions(m: int) -> np.ndarray:
    """m nearly uniform unit vectors on a Fibonacci (golden-angle) spiral."""
    k = np.arange(m)
    z = 1.0 - (2.0 * k + 1.0) / m
    phi = k * np.pi * (3.0 - np.sqrt(5.0))
    s = np.sqrt(1.0 - z**2)
    return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1)


def random_directions(m: int, seed: int) -> np.ndarray:
    """m random unit vectors in +/- pairs (each contact seen from both of its particles)."""
    d = np.random.default_rng(seed).normal(size=(m // 2, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return np.concatenate([d, -d])


def _timed(fn, repeats):
    best, result = np.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - start)
    return best, result


def _error(num, E, nu):
    return max(abs(num.E / E - 1.0), abs(num.nu / nu - 1.0), num.anisotropy)


def main(outdir: Path = Path(__file__).parent / "results", quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    kt = RATIO * KN
    E, nu = I.elastic_constants(KN, kt, RHO_C, RADIUS)
    t_closed, _ = _timed(lambda: I.elastic_constants(KN, kt, RHO_C, RADIUS), 200)
    degrees = [2, 3, 4, 6, 8, 12, 20] + ([] if quick else [30, 45, 60])
    sizes = [32, 100, 316, 1000, 3162] + ([] if quick else [10_000, 31_623, 100_000])
    columns = ["family", "parameter", "directions", "unknowns", "seconds", "error"]
    csv_path = outdir / "identification.csv"
    with CurveWriter(csv_path, columns) as out:
        for degree in degrees:
            n, w = sphere_quadrature(degree)
            seconds, num = _timed(lambda n=n, w=w: I.numerical_elastic_constants(
                KN, kt, RHO_C, RADIUS, directions=n, weights=w), 5)
            out.write(family=0, parameter=degree, directions=len(w), unknowns=3 * len(w) + 12,
                      seconds=seconds, error=_error(num, E, nu))
        for m in sizes:
            n = fibonacci_directions(m)
            seconds, num = _timed(lambda n=n: I.numerical_elastic_constants(
                KN, kt, RHO_C, RADIUS, directions=n), 3)
            out.write(family=1, parameter=m, directions=m, unknowns=3 * m + 12, seconds=seconds,
                      error=_error(num, E, nu))
            fabrics = [random_directions(m, seed) for seed in range(3)]
            runs = [_timed(lambda d=d: I.numerical_elastic_constants(
                KN, kt, RHO_C, RADIUS, directions=d), 1) for d in fabrics]
            out.write(family=2, parameter=m, directions=2 * (m // 2), unknowns=6 * (m // 2) + 12,
                      seconds=float(np.median([r[0] for r in runs])),
                      error=float(np.median([_error(r[1], E, nu) for r in runs])))
    data = read_curve(csv_path)

    exact = (data["family"] == 0) & (data["error"] < 1e-12)
    first_exact = int(data["parameter"][exact].min())
    fits = {}
    for name in ("fibonacci", "random"):
        sel = data["family"] == FAMILIES[name]
        fits[name] = float(np.polyfit(np.log(data["directions"][sel]), np.log(data["error"][sel]), 1)[0])
    summary = {
        "study": "numerical verification of Eq. (5.20): runtime vs error over direction sets",
        "family_codes": FAMILIES,
        "Kn_N_per_m": KN,
        "Kt_over_Kn": RATIO,
        "rho_c_per_m3": RHO_C,
        "radius_m": RADIUS,
        "E_closed_form_Pa": E,
        "nu_closed_form": nu,
        "closed_form_seconds": t_closed,
        "first_exact_gauss_degree": first_exact,
        "max_error_exact_gauss": float(data["error"][exact].max()),
        "error_slope_vs_directions": fits,
        "quick": quick,
    }
    write_json(outdir / "identification.json", summary)
    _plot(data, summary, outdir / "identification.png")
    return summary


def _plot(data, summary, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    floor = 1e-17
    for name, code in FAMILIES.items():
        sel = data["family"] == code
        err = np.maximum(data["error"][sel], floor)
        ax1.loglog(data["seconds"][sel], err, "o-", label=name)
        ax2.loglog(data["directions"][sel], err, "o-", label=name)
    gauss = data["family"] == 0
    points = zip(data["directions"][gauss], data["parameter"][gauss], data["error"][gauss], strict=True)
    for x, degree, err in points:
        ax2.annotate(f"{int(degree)}", (x, max(err, floor) * 8), fontsize=7, ha="center")
    ax1.axvline(summary["closed_form_seconds"], color="k", ls=":", label="closed form (5.20)")
    ax1.axhline(1e-10, color="grey", ls="--", lw=0.8)
    ax2.axhline(1e-10, color="grey", ls="--", lw=0.8, label="acceptance 1e-10")
    ax1.set(xlabel="runtime [s]", ylabel="relative error of E, nu, anisotropy", title="cost vs error")
    ax2.set(xlabel="number of contact directions m", title="error vs directions (gauss: degree annotated)")
    for ax in (ax1, ax2):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, report=lambda r: {k: v for k, v in r.items() if k != 'family_codes'})
