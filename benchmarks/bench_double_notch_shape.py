"""Diagnostic: do Model I's two cracks in the double-notched strip (β = 1) merge, and does the formulation decide it?

The dissertation (Sec. 7.3) reports one S-shaped band joining the two notch tips for Model I. Our Model I, with the
Chapter 7 set-up (Table 7.1, β = 1 MPa mm², displacement steps of 0.002 mm with the solver's cutbacks, stopped at
10 % of the peak), is run in plane strain and with the seed's own model of the specimen, one element through the
3 mm plate (``formulation="extruded"``: plane stress in effect), on two meshes (1000 and 4000 elements). For each:
the peak force, the steps and cutbacks, and whether the two bands meet: the damage (loss ≥ 0.9) along the vertical
line through the middle of the strip, between the notch heights, is continuous from one band to the other.

Every case is repeated under path following (``bench_damage.follow_specimen``: the damage dissipation of each
step prescribed, displacements, damage and load factor in one Newton system). The followed runs decide whether the
staggered update's jumps through the snap-back are the cause: the followed path computes the snap-back instead of
jumping over it. (An extensometer opening from y = 29 to 71 mm with converged staggered sweeps, used before,
stopped on the 3 mm plate at 22 % of its peak, where the sweeps no longer settled.)

    python benchmarks/bench_double_notch_shape.py [--quick] [--outdir DIR]

writes ``double_notch_shape.csv``, ``double_notch_shape.json`` and ``double_notch_shape.png``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure
from bench_damage import DAMAGE_STEP, STOP_FRACTION, follow_specimen

from abrakit.damage.runs import run_specimen
from abrakit.damage.specimens import double_notched, plot_field
from abrakit.io import CurveWriter, read_json, write_json

NAME = "double_notch_shape"
BETA, STEP, STOP = 1.0, 0.002, STOP_FRACTION
CASES = (("plane_strain", "coarse"), ("extruded", "coarse"), ("plane_strain", "medium"), ("extruded", "medium"))
QUICK_CASES = (("plane_strain", "coarse"), ("extruded", "coarse"))
COLUMNS = ("control", "formulation", "level", "elements", "peak_N", "u_at_peak_mm", "smallest_u_after_peak_mm",
           "steps", "cutbacks", "seconds", "status", "bands_meet", "largest_gap_mm", "dissipated_Nmm")


def bands_meet(specimen, loss, threshold: float = 0.9) -> tuple[bool, float]:
    """Whether the damage along x = 25 mm is continuous between the two notch heights (50 mm -/+ the offset), and
    the largest undamaged gap (mm) there."""
    mesh = specimen.plane_mesh
    offset = specimen.dimensions.get("offset", 10.0)
    low, high = 50.0 - offset, 50.0 + offset
    centres = mesh.p[:, mesh.t].mean(axis=1)
    column = np.abs(centres[0] - 25.0) < 1.5
    between = column & (centres[1] > low) & (centres[1] < high)
    ys = np.sort(centres[1][between & (loss >= threshold)])
    if ys.size == 0:
        return False, high - low
    edges = np.concatenate(([low], ys, [high]))
    gap = float(np.max(np.diff(edges)))
    spacing = float(np.max(np.diff(np.sort(centres[1][between]))))
    return gap <= 1.5 * spacing, gap


def main(outdir: Path = RESULTS, quick: bool = False, controls=("displacement", "path")) -> dict:
    """Run the cases under ``controls``; the stored rows and curves of the other control are kept (e.g.
    ``main(controls=("path",))`` after a change of the path follower; the figure then maps the new runs only)."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    rows, maps, curves = [], [], []
    stored = outdir / f"{NAME}.json"
    if stored.exists() and set(controls) != {"displacement", "path"}:
        old = read_json(stored)
        rows = [r for r in old["rows"] if r.get("control", "displacement") not in controls]
        curves = [(label, np.asarray(c["u"]), np.asarray(c["F"])) for label, c in old["curves"].items()
                  if not any(label.endswith(f", {control}") for control in controls)]
    cases = [(control, *c) for control in controls for c in (QUICK_CASES if quick else CASES)]
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for row in rows:
            writer.write(**row)
        for control, formulation, level in cases:
            specimen = double_notched(level, formulation=formulation)
            tic = time.perf_counter()
            run = (follow_specimen(specimen, "I", BETA, STEP) if control == "path"
                   else run_specimen(specimen, "I", BETA, step=STEP, stop_fraction=STOP))
            meet, gap = bands_meet(specimen, run.stiffness_loss)
            top = int(np.argmax(run.F))
            result = run.result
            dissipated = (result.dissipated_energy if control == "path"
                          else float(result.curves["dissipated_energy"][-1]))
            row = {"control": control, "formulation": formulation, "level": level,
                   "elements": specimen.plane_mesh.nelements, "peak_N": float(run.F[top]),
                   "u_at_peak_mm": float(run.u[top]), "smallest_u_after_peak_mm": float(np.min(run.u[top:])),
                   "steps": run.steps, "cutbacks": run.cutbacks, "seconds": time.perf_counter() - tic,
                   "status": run.status, "bands_meet": meet, "largest_gap_mm": gap,
                   "dissipated_Nmm": dissipated * specimen.force_scale}
            rows.append(row)
            writer.write(**row)
            maps.append((f"{formulation}, {level}, {control}", specimen, run.stiffness_loss))
            curves.append((f"{formulation}, {level}, {control}", run.u, run.F))
            print(f"[double notch] {control:12s} {formulation:12s} {level:6s}: peak {row['peak_N']:.0f} N, "
                  f"{row['steps']} steps, {row['cutbacks']} cutbacks, bands meet: {meet} (largest gap {gap:.1f} mm)",
                  flush=True)
            data = save(outdir, rows, maps, curves, quick)      # after every run: a stopped study keeps its runs
    return data


def save(outdir: Path, rows, maps, curves, quick: bool) -> dict:
    """``double_notch_shape.json`` and ``.png`` of the runs so far."""
    data = {"rows": rows, "beta": BETA, "step_mm": STEP, "stop_fraction": STOP, "damage_step": DAMAGE_STEP,
            "quick": quick, "curves": {label: {"u": np.asarray(u).tolist(), "F": np.asarray(F).tolist()}
                                       for label, u, F in curves},
            "date": time.strftime("%Y-%m-%d %H:%M")}
    write_json(outdir / f"{NAME}.json", data)
    plot(maps, curves, outdir / f"{NAME}.png")
    return data


def plot(maps, curves, path):
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(maps) + 1, figsize=(3.2 * (len(maps) + 1), 5.5), squeeze=False)
    axes = axes[0]
    for ax, (label, specimen, loss) in zip(axes[1:], maps, strict=True):
        plot_field(specimen, loss, ax=ax, colorbar=False)
        ax.set_title(label, fontsize=8)
    for label, u, F in curves:
        axes[0].plot(u, np.asarray(F) / 1e3, lw=1, label=label)
    axes[0].set(xlabel="top displacement [mm]", ylabel="force [kN]")
    axes[0].legend(fontsize=6)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="the coarse mesh in both formulations")
