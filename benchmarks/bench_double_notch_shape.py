"""Diagnostic: do Model I's two cracks in the double-notched strip (β = 1) merge, and does the formulation decide it?

The dissertation (Sec. 7.3) reports one S-shaped band joining the two notch tips for Model I. Our Model I, with the
Chapter 7 set-up (Table 7.1, β = 1 MPa mm², displacement steps of 0.002 mm with the solver's cutbacks, stopped at
10 % of the peak), is run in plane strain and with the seed's own model of the specimen, one element through the
3 mm plate (``formulation="extruded"``: plane stress in effect), on two meshes (1000 and 4000 elements). For each:
the peak force, the steps and cutbacks, and whether the two bands meet: the damage (loss ≥ 0.9) along the vertical
line through the middle of the strip, between the notch heights, is continuous from one band to the other.

    python benchmarks/bench_double_notch_shape.py [--quick] [--outdir DIR]

writes ``double_notch_shape.csv``, ``double_notch_shape.json`` and ``double_notch_shape.png``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure

from abrakit.damage.runs import run_specimen
from abrakit.damage.specimens import double_notched, plot_field
from abrakit.io import CurveWriter, write_json

NAME = "double_notch_shape"
BETA, STEP, STOP = 1.0, 0.002, 0.1
CASES = (("plane_strain", "coarse"), ("plane_strain", "medium"), ("extruded", "coarse"), ("extruded", "medium"))
QUICK_CASES = (("plane_strain", "coarse"), ("extruded", "coarse"))
COLUMNS = ("formulation", "level", "elements", "peak_N", "steps", "cutbacks", "seconds", "status", "bands_meet",
           "largest_gap_mm")


def bands_meet(specimen, loss, threshold: float = 0.9) -> tuple[bool, float]:
    """Whether the damage along x = 25 mm is continuous between the two notch heights (40 and 60 mm), and the
    largest undamaged gap (mm) there."""
    mesh = specimen.plane_mesh
    centres = mesh.p[:, mesh.t].mean(axis=1)
    column = np.abs(centres[0] - 25.0) < 1.5
    between = column & (centres[1] > 40.0) & (centres[1] < 60.0)
    ys = np.sort(centres[1][between & (loss >= threshold)])
    if ys.size == 0:
        return False, 20.0
    edges = np.concatenate(([40.0], ys, [60.0]))
    gap = float(np.max(np.diff(edges)))
    spacing = float(np.max(np.diff(np.sort(centres[1][between]))))
    return gap <= 1.5 * spacing, gap


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    rows, maps = [], []
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for formulation, level in QUICK_CASES if quick else CASES:
            specimen = double_notched(level, formulation=formulation)
            tic = time.perf_counter()
            run = run_specimen(specimen, "I", BETA, step=STEP, stop_fraction=STOP)
            meet, gap = bands_meet(specimen, run.stiffness_loss)
            row = {"formulation": formulation, "level": level, "elements": specimen.plane_mesh.nelements,
                   "peak_N": float(np.max(run.F)), "steps": run.steps, "cutbacks": run.cutbacks,
                   "seconds": time.perf_counter() - tic, "status": run.status, "bands_meet": meet,
                   "largest_gap_mm": gap}
            rows.append(row)
            writer.write(**row)
            maps.append((f"{formulation}, {level}", specimen, run.stiffness_loss))
            print(f"[double notch] {formulation:12s} {level:6s}: peak {row['peak_N']:.0f} N, {row['steps']} steps, "
                  f"{row['cutbacks']} cutbacks, bands meet: {meet} (largest gap {gap:.1f} mm)", flush=True)
    data = {"rows": rows, "beta": BETA, "step_mm": STEP, "stop_fraction": STOP, "quick": quick,
            "date": time.strftime("%Y-%m-%d %H:%M")}
    write_json(outdir / f"{NAME}.json", data)
    plot(maps, outdir / f"{NAME}.png")
    return data


def plot(maps, path):
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(maps), figsize=(3.2 * len(maps), 5.5))
    for ax, (label, specimen, loss) in zip(np.atleast_1d(axes), maps, strict=True):
        plot_field(specimen, loss, ax=ax, colorbar=False)
        ax.set_title(label, fontsize=9)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="the coarse mesh in both formulations")
