"""Diagnostic: is the damage at the sharp notch's right edge physics or an artefact of the boundary condition?

Model II (α = 0.005, Table 7.2) on the upper half of the sharp-notch specimen, loaded two ways to 10 % of the peak:

- **grip**: the top edge moved uniformly in y (the Chapter 7 set-up: a grip that cannot rotate), displacement
  control (``abrakit.damage.runs.run_specimen``);
- **traction**: the same edge pulled by a uniform traction (free to rotate and deform), followed through the
  softening by the notch-mouth opening (:class:`abrakit.fem.PathFollowingSolver`, ``method="opening"``) with the
  rate limit on the external force's work.

on two meshes (1000 and 4000 elements). For each run: the damaged area (stiffness loss above 0.5) in three zones —
the ligament band (y < 2 mm, x > 25 mm), the top-right corner (x > 45, y > 15 mm) and the right edge below it
(x > 45, 5 < y < 15 mm) — and the peak force. A zone damaged in both meshes by a similar area is a property of the
loading, not of the discretisation; one damaged only under the grip is a consequence of the grip.

    python benchmarks/bench_sharp_notch_edge.py [--quick] [--outdir DIR]

writes ``sharp_notch_edge.csv``, ``sharp_notch_edge.json`` and ``sharp_notch_edge.png``.
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure

from abrakit.damage.metrics import element_areas
from abrakit.damage.model_two_fe import default_material, element_f_bar
from abrakit.damage.runs import run_specimen
from abrakit.damage.specimens import plot_field, sharp_notch
from abrakit.fem import NewtonOptions, PathControl, PathFollowingSolver
from abrakit.fem.boundary import surface_load
from abrakit.io import CurveWriter, write_json

NAME = "sharp_notch_edge"
ALPHA, STOP = 0.005, 0.1
LEVELS, QUICK_LEVELS = ("coarse", "medium"), ("coarse",)
ZONES = {
    "ligament": lambda x, y: (y < 2.0) & (x > 25.0),
    "corner": lambda x, y: (x > 45.0) & (y > 15.0),
    "right_edge": lambda x, y: (x > 45.0) & (y > 5.0) & (y < 15.0),
}
COLUMNS = ("load", "level", "elements", "peak_N", "seconds", "status",
           *(f"{z}_{q}" for z in ZONES for q in ("damaged_mm2", "max_loss")))


def grip(sp) -> dict:
    tic = time.perf_counter()
    run = run_specimen(sp, "II", ALPHA, step=0.002, stop_fraction=STOP)
    return {"loss": run.stiffness_loss, "peak_N": float(np.max(run.F)), "seconds": time.perf_counter() - tic,
            "status": run.status}


def traction(sp, stress: float) -> dict:
    """The top edge under a uniform traction ``stress`` × λ (MPa), followed by the notch-mouth opening."""
    material = default_material(ALPHA)
    f_hat = surface_load(sp.basis, "top", traction=(0.0, stress))
    p, y_dofs = sp.mesh.p, sp.basis.nodal_dofs[1]
    mouth = y_dofs[np.flatnonzero((p[0] < 1e-9) & (p[1] < 1e-9))]
    far_end = y_dofs[np.flatnonzero((p[0] > 50.0 - 1e-9) & (p[1] < 1e-9))]
    top = sp.basis.get_dofs("top").nodal["u^2"]
    solver = PathFollowingSolver(sp.basis, material, [d for d in sp.dirichlet if not d.name],
                                 external_force=lambda lam: lam * f_hat, method="opening", opening=(mouth, far_end),
                                 path=PathControl(initial=0.05, maximum=0.05, target_iterations=8, max_steps=1500),
                                 monitors={"top": top}, newton=NewtonOptions(max_iterations=20))
    scale = sp.force_scale

    def loading(ctx):           # the rate limit on the work of the applied force over the increment (magnitude)
        return {"external_work": abs(scale * (ctx.load_factor - ctx.delta) * float(f_hat @ (ctx.u - ctx.u_old)))}

    solver.loading = loading
    tic = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        result = solver.run(stop_force=STOP, progress=False)
    F = scale * result.curves["F_top"]
    return {"loss": 1.0 - element_f_bar(result.state, solver.kin.dx), "peak_N": float(np.max(F)),
            "seconds": time.perf_counter() - tic, "status": "fractured" if F[-1] <= STOP * F.max() else "end"}


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    rows, maps = [], {}
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for level in QUICK_LEVELS if quick else LEVELS:
            sp = sharp_notch(level)
            centres = sp.mesh.p[:, sp.mesh.t].mean(axis=1)
            area = element_areas(sp.mesh)
            held = grip(sp)
            pulled = traction(sp, 1.5 * held["peak_N"] / sp.force_scale / 50.0)
            for load, run in (("grip", held), ("traction", pulled)):
                row = {"load": load, "level": level, "elements": sp.mesh.nelements, "peak_N": run["peak_N"],
                       "seconds": run["seconds"], "status": run["status"]}
                for zone, inside in ZONES.items():
                    mask = inside(*centres)
                    row[f"{zone}_damaged_mm2"] = float(area[mask & (run["loss"] > 0.5)].sum())
                    row[f"{zone}_max_loss"] = float(run["loss"][mask].max())
                rows.append(row)
                writer.write(**row)
                maps[(load, level)] = (sp, run["loss"])
                print(f"[edge] {load:8s} {level:6s}: peak {row['peak_N']:.0f} N, damaged mm²: ligament "
                      f"{row['ligament_damaged_mm2']:.1f}, corner {row['corner_damaged_mm2']:.1f}, right edge "
                      f"{row['right_edge_damaged_mm2']:.2f} ({row['seconds']:.0f} s)", flush=True)
    data = {"rows": rows, "alpha": ALPHA, "stop_fraction": STOP, "quick": quick,
            "date": time.strftime("%Y-%m-%d %H:%M")}
    write_json(outdir / f"{NAME}.json", data)
    plot(maps, outdir / f"{NAME}.png")
    return data


def plot(maps, path):
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(maps), figsize=(4.2 * len(maps), 3.6))
    for ax, ((load, level), (sp, loss)) in zip(np.atleast_1d(axes), maps.items(), strict=True):
        plot_field(sp, loss, ax=ax, whole=False, colorbar=False)
        ax.set_title(f"{load}, {level}: stiffness loss", fontsize=9)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="the coarse mesh only")
