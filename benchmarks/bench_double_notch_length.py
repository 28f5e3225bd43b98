"""Diagnostic: what makes Model I's two cracks in the double-notched strip join -- the regularisation length
against the notch offset.

The dissertation (Sec. 7.3) reports two separate cracks for β = 0.1 and one S-shaped band joining the notch tips
for β = 1 MPa mm². Its figure with the specimen's dimensions is missing, so the notch offset (±10 mm from
mid-height) is our reconstruction. Model I (Table 7.1, displacement steps of 0.002 mm with the solver's cutbacks,
stopped at 10 % of the peak) is run over β on the coarse mesh, at the β where the band first joins on the medium
mesh (the shape must not depend on the mesh) and in the one-element-through-3-mm model, and with β = 1 at smaller
offsets. For each: the peak force and whether the band joins, i.e. the damaged elements (loss ≥ 0.9) connect the
element at one notch tip with the element at the other through shared faces.

    python benchmarks/bench_double_notch_length.py [--quick] [--outdir DIR]

writes ``double_notch_length.csv``, ``double_notch_length.json`` and ``double_notch_length.png``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure

from abrakit.damage import face_neighbours
from abrakit.damage.runs import run_specimen
from abrakit.damage.specimens import double_notched, plot_field
from abrakit.io import CurveWriter, write_json

NAME = "double_notch_length"
STEP, STOP = 0.002, 0.1
#: (beta MPa mm^2, notch offset mm, mesh, formulation)
CASES = ((0.1, 10.0, "coarse", "plane_strain"), (1.0, 10.0, "coarse", "plane_strain"),
         (2.0, 10.0, "coarse", "plane_strain"), (4.0, 10.0, "coarse", "plane_strain"),
         (16.0, 10.0, "coarse", "plane_strain"), (4.0, 10.0, "medium", "plane_strain"),
         (4.0, 10.0, "coarse", "extruded"), (1.0, 5.0, "coarse", "plane_strain"),
         (1.0, 2.5, "coarse", "plane_strain"))
QUICK_CASES = ((1.0, 10.0, "coarse", "plane_strain"), (4.0, 10.0, "coarse", "plane_strain"))
COLUMNS = ("beta", "offset_mm", "level", "formulation", "elements", "peak_N", "steps", "cutbacks", "seconds",
           "joined", "damaged_elements")


def tip_elements(specimen) -> tuple[int, int]:
    """The elements just ahead of the two notch tips: (10 mm, 50 + offset) and (40 mm, 50 - offset)."""
    mesh = specimen.plane_mesh
    centres = mesh.p[:, mesh.t].mean(axis=1).T
    offset = specimen.dimensions["offset"]
    tips = ((10.0, 50.0 + offset), (40.0, 50.0 - offset))
    return tuple(int(np.argmin(np.linalg.norm(centres - np.array(t), axis=1))) for t in tips)


def joined(specimen, loss, threshold: float = 0.9) -> bool:
    """Whether the elements with ``loss >= threshold`` connect the two notch tips through shared faces."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    neighbours = face_neighbours(specimen.plane_mesh)
    damaged = loss >= threshold
    own = np.repeat(np.arange(len(loss)), neighbours.shape[1])
    other = neighbours.ravel()
    keep = (other >= 0) & damaged[own] & damaged[np.maximum(other, 0)]
    graph = sp.coo_matrix((np.ones(keep.sum()), (own[keep], other[keep])), shape=(len(loss),) * 2)
    _, label = connected_components(graph, directed=False)
    upper, lower = tip_elements(specimen)
    return bool(damaged[upper] and damaged[lower] and label[upper] == label[lower])


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    rows, maps = [], []
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for beta, offset, level, formulation in QUICK_CASES if quick else CASES:
            specimen = double_notched(level, formulation=formulation, offset=offset)
            tic = time.perf_counter()
            run = run_specimen(specimen, "I", beta, step=STEP, stop_fraction=STOP)
            row = {"beta": beta, "offset_mm": offset, "level": level, "formulation": formulation,
                   "elements": specimen.elements, "peak_N": float(np.max(run.F)), "steps": run.steps,
                   "cutbacks": run.cutbacks, "seconds": time.perf_counter() - tic,
                   "joined": joined(specimen, run.stiffness_loss),
                   "damaged_elements": int(np.sum(run.stiffness_loss >= 0.9))}
            rows.append(row)
            writer.write(**row)
            maps.append((f"β = {beta:g}, ±{offset:g} mm\n{level}, {formulation.replace('_', ' ')}", specimen,
                         run.stiffness_loss))
            print(f"[double notch length] beta {beta:5g} offset {offset:4g} {level:6s} {formulation:12s}: peak "
                  f"{row['peak_N']:.0f} N, joined: {row['joined']}", flush=True)
    data = {"rows": rows, "step_mm": STEP, "stop_fraction": STOP, "quick": quick,
            "date": time.strftime("%Y-%m-%d %H:%M")}
    write_json(outdir / f"{NAME}.json", data)
    plot(maps, outdir / f"{NAME}.png")
    return data


def plot(maps, path):
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(maps), figsize=(2.4 * len(maps), 4.8))
    for ax, (label, specimen, loss) in zip(np.atleast_1d(axes), maps, strict=True):
        plot_field(specimen, loss, ax=ax, colorbar=False)
        ax.set_title(label, fontsize=7)
        ax.set_xticks([])
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="beta = 1 and 4 on the coarse mesh")
