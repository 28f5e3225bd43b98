"""Explicit (seed, Eq. 6.59/6.61) vs implicit (radial return) plasticity update: error against runtime over step sizes.

A batch of material points (Table 7.1 steel: E = 200 GPa, nu = 0.33, r_p = 60 MPa, K_H = 8000 MPa) follows
strain paths to about ten times the yield strain, in N equal steps, with each integration:

- *radial* paths ``eps(t) = t eps_B`` (the implicit update is exact for any N here);
- *non-proportional* paths ``0 -> eps_A -> eps_B`` with random directions (both updates have a step error).

The error is the RMS over the points of the final stress error relative to a reference (the implicit update
with 16 times the finest N), divided by the uniaxial yield stress. The runtime is the wall time of the N batch
updates. Writes ``plasticity.csv`` (one row per run, as it goes), ``plasticity.json`` and ``plasticity.png``.

    python benchmarks/bench_plasticity.py [--quick] [--outdir DIR]
"""

from __future__ import annotations

import pathlib
import time

import numpy as np
from _common import command_line, save_figure

from abrakit.io import CurveWriter, write_json
from abrakit.materials import TABLE_7_1, VonMisesPlasticity, uniaxial_yield_stress

PARAMETERS = {key: TABLE_7_1[key] for key in ("E", "nu", "r_p", "K_H")}
COLUMNS = ["path", "scheme", "n_steps", "runtime_s", "point_updates_per_s", "stress_error", "alpha_error"]


def strain_paths(n_points: int, seed: int = 0) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Corner strains ``(eps_A, eps_B)`` of each path kind, Mandel ``(n_points, 6)``, |eps| ~ 10 yield strains."""
    rng = np.random.default_rng(seed)
    yield_strain = uniaxial_yield_stress(PARAMETERS["r_p"]) / PARAMETERS["E"]

    def directions():
        v = rng.normal(size=(n_points, 6))
        return v / np.linalg.norm(v, axis=1, keepdims=True)

    eps_B = 10.0 * yield_strain * directions()
    eps_A = 10.0 * yield_strain * directions()
    return {"radial": (0.5 * eps_B, eps_B), "non-proportional": (eps_A, eps_B)}


def strain_at(corners, t: float) -> np.ndarray:
    """Piecewise-linear path 0 -> eps_A (t = 1/2) -> eps_B (t = 1)."""
    eps_A, eps_B = corners
    return 2.0 * t * eps_A if t <= 0.5 else eps_A + (2.0 * t - 1.0) * (eps_B - eps_A)


def integrate(material, corners, n_steps: int):
    """Final stress and alpha_p after ``n_steps`` equal steps (``n_steps`` even, so the corner is hit)."""
    state = material.initial_state(corners[0].shape[:-1])
    for k in range(1, n_steps + 1):
        response = material.update(state, strain_at(corners, k / n_steps))
        state = response.state
    return response.stress, state["alpha_p"]


def main(outdir: pathlib.Path = pathlib.Path(__file__).parent / "results", quick: bool = False) -> dict:
    outdir = pathlib.Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    n_points = 256 if quick else 4096
    step_counts = [2**k for k in range(2, 9 if quick else 11)]
    sigma_0 = uniaxial_yield_stress(PARAMETERS["r_p"])
    paths = strain_paths(n_points)
    schemes = {s: VonMisesPlasticity(**PARAMETERS, integration=s) for s in ("explicit", "implicit")}

    rows = []
    with CurveWriter(outdir / "plasticity.csv", COLUMNS) as writer:
        for path_name, corners in paths.items():
            ref_stress, ref_alpha = integrate(schemes["implicit"], corners, 16 * step_counts[-1])
            for scheme, material in schemes.items():
                for n_steps in step_counts:
                    start = time.perf_counter()
                    stress, alpha = integrate(material, corners, n_steps)
                    runtime = time.perf_counter() - start
                    alpha_scale = np.sqrt(np.mean(ref_alpha**2))
                    row = {
                        "path": path_name,
                        "scheme": scheme,
                        "n_steps": n_steps,
                        "runtime_s": runtime,
                        "point_updates_per_s": n_points * n_steps / runtime,
                        "stress_error": float(np.sqrt(np.mean(np.sum((stress - ref_stress) ** 2, -1))) / sigma_0),
                        "alpha_error": float(np.sqrt(np.mean((alpha - ref_alpha) ** 2)) / alpha_scale),
                    }
                    writer.write(**row)
                    rows.append(row)

    summary = {
        "parameters": PARAMETERS,
        "n_points": n_points,
        "step_counts": step_counts,
        "error_measure": "RMS over points of |sigma - sigma_ref| / sigma_0 at the end of the path",
        "reference": f"implicit radial return with {16 * step_counts[-1]} steps",
        "rows": rows,
    }
    for path_name in paths:
        for scheme in schemes:
            sel = [r for r in rows if r["path"] == path_name and r["scheme"] == scheme]
            n = np.array([r["n_steps"] for r in sel], float)
            err = np.array([r["stress_error"] for r in sel])
            fine = err > 1e-10
            order = float(-np.polyfit(np.log(n[fine][-4:]), np.log(err[fine][-4:]), 1)[0]) if fine.sum() >= 2 else None
            reached = [r for r in sel if r["stress_error"] <= 0.01]
            summary[f"{path_name}/{scheme}"] = {
                "observed_order": order,
                "steps_for_1_percent": reached[0]["n_steps"] if reached else None,
                "runtime_for_1_percent_s": reached[0]["runtime_s"] if reached else None,
                "point_updates_per_s": float(np.median([r["point_updates_per_s"] for r in sel])),
            }
    write_json(outdir / "plasticity.json", summary)
    plot(rows, outdir / "plasticity.png")
    return summary


def plot(rows, path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_n, ax_t) = plt.subplots(1, 2, figsize=(10, 4))
    styles = {"explicit": "o-", "implicit": "s--"}
    for path_name in ("radial", "non-proportional"):
        for scheme in ("explicit", "implicit"):
            sel = [r for r in rows if r["path"] == path_name and r["scheme"] == scheme]
            err = np.maximum([r["stress_error"] for r in sel], 1e-16)
            label = f"{scheme}, {path_name}"
            ax_n.loglog([r["n_steps"] for r in sel], err, styles[scheme], label=label)
            ax_t.loglog([r["runtime_s"] for r in sel], err, styles[scheme], label=label)
    ax_n.set_xlabel("steps N")
    ax_t.set_xlabel("runtime [s]")
    for ax in (ax_n, ax_t):
        ax.set_ylabel(r"RMS final stress error / $\sigma_0$")
        ax.grid(True, which="both", alpha=0.3)
    ax_n.legend(fontsize=8)
    fig.suptitle("Plasticity update: explicit Euler (seed) vs radial return")
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, report=lambda r: '\n'.join(f'{k} {v}' for k, v in r.items() if '/' in k))
