"""Element Laplacian of Model I (Eq. 6.65-6.75): error against h and cost per element.

For f = prod_k cos(pi x_k) on the unit square/cube (df/dn = 0 on every wall, so the mirrored ghosts are exact
boundary data) the exact Laplacian is -d pi^2 f. For each mesh family and refinement we record the max and rms
error at the element centres, the set-up time of the sparse operator (once per mesh), the time of one
application ``L @ f`` (every Newton step), the number of least-squares fallbacks and the exactness on a quadratic.

    python benchmarks/bench_laplacian.py [--quick] [--outdir DIR]
"""

from __future__ import annotations

import pathlib
import time

import numpy as np
from _common import command_line, save_figure

from abrakit.damage.laplacian import element_laplacian, face_neighbours, unit_cube_mesh
from abrakit.io import CurveWriter, write_json

NAME = "laplacian"
COLUMNS = ["family", "kind", "n", "elements", "h", "max_error", "rms_error", "quadratic_error", "roundoff_floor",
           "setup_s",
           "setup_us_per_element", "apply_us_per_element", "fallbacks", "max_condition"]

#: family -> (element kind, grading, perturbation as a fraction of h, refinements (quick), refinements (full))
FAMILIES = {
    "line structured": ("line", "none", 0.0, (16, 32, 64), (16, 32, 64, 128, 256, 512)),
    "quad structured": ("quad", "none", 0.0, (8, 16, 32), (8, 16, 32, 64, 128, 256)),
    "quad graded": ("quad", "corner", 0.0, (8, 16, 32), (8, 16, 32, 64, 128, 256)),
    "quad perturbed 25%": ("quad", "none", 0.25, (8, 16, 32), (8, 16, 32, 64, 128, 256)),
    "tri structured": ("tri", "none", 0.0, (8, 16, 32), (8, 16, 32, 64, 128)),
    "tri perturbed 20%": ("tri", "none", 0.2, (8, 16, 32), (8, 16, 32, 64, 128)),
    "hex structured": ("hex", "none", 0.0, (4, 8), (4, 8, 16, 32)),
    "hex perturbed 25%": ("hex", "none", 0.25, (4, 8), (4, 8, 16, 32)),
    "tet structured": ("tet", "none", 0.0, (4, 8), (4, 8, 16)),
}


def _best_time(func, repeats):
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        func()
        best = min(best, time.perf_counter() - start)
    return best


def measure(kind, grading, perturb, n, seed=0) -> dict:
    """Error and timings of the element Laplacian on one mesh."""
    mesh = unit_cube_mesh(kind, n, grading=grading, perturb=perturb, seed=seed)
    lap = element_laplacian(mesh)
    setup = _best_time(lambda: element_laplacian(mesh), repeats=2)
    x = lap.centres
    dim = x.shape[1]
    f = np.prod(np.cos(np.pi * x), axis=1)
    error = lap(f) + dim * np.pi**2 * f
    rng = np.random.default_rng(seed)
    Q = rng.normal(size=(dim, dim))
    Q = Q + Q.T
    quadratic = 0.5 + x @ rng.normal(size=dim) + np.einsum("ik,kl,il->i", x, Q, x)
    interior = np.all(face_neighbours(mesh) >= 0, axis=1)
    quadratic_error = np.abs(lap(quadratic) - 2.0 * np.trace(Q))[interior].max() / np.abs(Q).max()
    # Cancellation in f_j - f_i limits any difference formula to about eps |f| / h_min**2.
    h_min = np.ptp(mesh.p[:, mesh.t], axis=1).min()
    roundoff_floor = np.finfo(float).eps * np.abs(quadratic).max() / h_min**2 / np.abs(Q).max()
    nel = len(x)
    apply = _best_time(lambda: lap.matrix @ f, repeats=20)
    return {"kind": kind, "n": n, "elements": nel, "h": 1.0 / n, "max_error": np.abs(error).max(),
            "rms_error": np.sqrt(np.mean(error**2)), "quadratic_error": quadratic_error,
            "roundoff_floor": roundoff_floor, "setup_s": setup,
            "setup_us_per_element": 1e6 * setup / nel, "apply_us_per_element": 1e6 * apply / nel,
            "fallbacks": lap.n_fallback, "max_condition": lap.condition.max()}


def observed_rates(rows) -> dict:
    """Convergence rates log(e_coarse / e_fine) / log(h_coarse / h_fine) of the last two refinements."""
    h = np.array([r["h"] for r in rows])
    out = {}
    for key in ("max_error", "rms_error"):
        e = np.array([r[key] for r in rows])
        out[key] = float(np.log(e[-2] / e[-1]) / np.log(h[-2] / h[-1]))
    return out


def plot(results, path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_h, ax_cost) = plt.subplots(1, 2, figsize=(12, 4.8))
    for family, rows in results.items():
        h = np.array([r["h"] for r in rows])
        rms = np.array([r["rms_error"] for r in rows])
        style = "-o" if "structured" in family else ("--s" if "perturbed" in family else ":^")
        line, = ax_h.loglog(h, rms, style, label=family, ms=4)
        ax_cost.loglog([r["setup_s"] for r in rows], rms, style, color=line.get_color(), ms=4, label=family)
    h_ref = np.array([1 / 256, 1 / 8])
    ax_h.loglog(h_ref, 1.0 * h_ref / h_ref[-1], "k-", lw=0.8, label="slope 1")
    ax_h.loglog(h_ref, 0.05 * (h_ref / h_ref[-1]) ** 2, "k--", lw=0.8, label="slope 2")
    ax_h.set(xlabel="h = 1/n", ylabel=r"rms error of $\Lambda_f$ for $f=\prod\cos(\pi x_k)$",
             title="Taylor-stencil Laplacian: error vs h")
    ax_h.legend(fontsize=7)
    ax_cost.set(xlabel="set-up time of L [s] (once per mesh; L @ f costs ~5 ns per element)",
                ylabel=r"rms error of $\Lambda_f$", title="speed against error")
    ax_cost.legend(fontsize=7)
    save_figure(fig, path, dpi=130)


def main(outdir: pathlib.Path = pathlib.Path(__file__).parent / "results", quick: bool = False) -> dict:
    outdir = pathlib.Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    results: dict[str, list[dict]] = {}
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for family, (kind, grading, perturb, sizes_quick, sizes_full) in FAMILIES.items():
            results[family] = []
            for n in sizes_quick if quick else sizes_full:
                row = measure(kind, grading, perturb, n)
                results[family].append(row)
                writer.write(family=family, **row)
    summary = {
        "name": NAME,
        "quick": quick,
        "field": "f = prod cos(pi x_k) on the unit square/cube, exact Laplacian -d pi^2 f",
        "quadratic_error": "max |Lambda_f - 2 tr Q| / max |Q| over interior elements for f = a + b.x + x.Q.x; "
                           "roundoff_floor = eps max|f| / h_min**2 / max|Q|",
        "families": {
            family: {
                "rates": observed_rates(rows),
                "finest": rows[-1],
                "worst_quadratic_error": max(r["quadratic_error"] for r in rows),
                "worst_quadratic_error_over_roundoff_floor": max(r["quadratic_error"] / r["roundoff_floor"]
                                                                 for r in rows),
                "total_fallbacks": sum(r["fallbacks"] for r in rows),
            }
            for family, rows in results.items()
        },
    }
    write_json(outdir / f"{NAME}.json", summary)
    plot(results, outdir / f"{NAME}.png")
    return summary


def report(summary) -> str:
    lines = []
    for family, info in summary["families"].items():
        finest = info["finest"]
        lines.append(
            f"{family:20s} rate max {info['rates']['max_error']:.2f} rms {info['rates']['rms_error']:.2f}  "
            f"finest {finest['elements']:6d} el: rms {finest['rms_error']:.2e}, set-up "
            f"{finest['setup_us_per_element']:.1f} µs/el, L@f {finest['apply_us_per_element'] * 1e3:.1f} ns/el, "
            f"quadratic {info['worst_quadratic_error_over_roundoff_floor']:.1f} x roundoff, "
            f"fallbacks {info['total_fallbacks']}")
    return "\n".join(lines)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="coarse meshes only", report=report)
