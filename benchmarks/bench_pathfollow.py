"""Benchmark: path following through snap-back against displacement control, speed against error.

The scene is :class:`abrakit.fem.problems.SofteningBar`: a bar of n bilinear elements (length 100 mm, E = 1000 MPa,
ν = 0), its middle element weaker (peak strain 1e-3) and softening linearly to zero stress at strain 0.02, pulled
at one end. Its force–displacement path is known in closed form and snaps back for n > 20.

1. **Path following against displacement control** (n = 10, 50, 200, 1000): steps, Newton iterations, cutbacks,
   CPU time, the largest force error of the computed points against the closed form (per cent of the peak), and
   the dissipated energy at the end against G·A = ½ f_t ε_f h. Displacement control runs the same bar in 50 steps
   with the solver's cutbacks; where the bar snaps back it stops at the peak (or jumps), and its row says so.
2. **Speed against error** (n = 200). Every computed point lies on the closed form whatever the step, because the
   path is piecewise linear and each step is solved to the Newton tolerance; what the step size decides is how
   closely the points resolve the corner at the peak: the peak force captured and the energy budget along the path
   (external work by the trapezoidal rule − dissipation − ½ F v, per cent of G·A). Load-factor increments before
   the peak from 0.2 to 0.0025 (the dissipation target G/40 after it); error against CPU time.

    python benchmarks/bench_pathfollow.py [--quick] [--outdir DIR]

writes ``pathfollow.csv``, ``pathfollow.json`` and ``pathfollow.png``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure

from abrakit.fem import PathControl, StepControl, StepFailed
from abrakit.fem.problems import SofteningBar
from abrakit.io import CurveWriter, write_json

NAME = "pathfollow"
SIZES, QUICK_SIZES = (10, 50, 200, 1000), (10, 200)
INCREMENTS, QUICK_INCREMENTS = (0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.0025), (0.1, 0.01)
COLUMNS = ("study", "control", "n", "snaps_back", "steps", "iterations", "cutbacks", "cpu_seconds", "status",
           "max_force_error_pct", "energy_error_pct", "budget_error_pct", "peak_error_pct", "target")


def follow(bar: SofteningBar, divisions: int = 40, increment: float = 0.05) -> dict:
    solver = bar.solver(path=PathControl(dissipation=bar.fracture_energy / divisions, initial=increment,
                                         maximum=max(increment, 0.1)))
    dissipated = [0.0]
    tic = time.process_time()
    result = solver.run(stop_force=1e-3, progress=False, on_step=lambda r: dissipated.append(
        float(np.sum(solver.material.dissipation(r.state) * solver.kin.dx))))
    seconds = time.process_time() - tic
    v, F = result.curves["u_right"], result.curves["F_right"]
    work = np.concatenate(([0.0], np.cumsum(0.5 * (F[1:] + F[:-1]) * np.diff(v))))
    intact = bar.branch(v, F) != "broken"
    budget = (work - 0.5 * F * v - np.array(dissipated))[intact]
    return {"control": "path following", "steps": len(v) - 1, "iterations": int(result.iterations.sum()),
            "cutbacks": result.cutbacks, "cpu_seconds": seconds, "status": "completed",
            "max_force_error_pct": 100 * float(np.max(np.abs(F - bar.force(v, bar.branch(v, F))))) / bar.f_t,
            "energy_error_pct": 100 * (dissipated[-1] / bar.fracture_energy - 1.0),
            "budget_error_pct": 100 * float(np.max(np.abs(budget))) / bar.fracture_energy,
            "peak_error_pct": 100 * (1.0 - float(np.max(F)) / bar.f_t), "target": increment,
            "curve": (v, F, result.curves["constraint"])}


def displacement_control(bar: SofteningBar) -> dict:
    solver = bar.solver(follow=False, control=StepControl(initial=0.02, maximum=0.02))
    tic = time.process_time()
    try:
        result, status = solver.run(progress=False), "completed"
    except StepFailed as failure:
        result, status = failure.result, "stopped at the peak"
    seconds = time.process_time() - tic
    v, F = result.curves["u_right"], result.curves["F_right"]
    drop = float(np.max(-np.diff(F), initial=0.0)) / bar.f_t
    if status == "completed" and drop > 0.5:
        status = f"jumped ({100 * drop:.0f} % of the peak in one step)"
    return {"control": "displacement", "steps": len(v) - 1, "iterations": int(result.iterations.sum()),
            "cutbacks": result.cutbacks, "cpu_seconds": seconds, "status": status,
            "max_force_error_pct": 100 * float(np.max(np.abs(F - bar.force(v, bar.branch(v, F))))) / bar.f_t,
            "energy_error_pct": np.nan, "budget_error_pct": np.nan,
            "peak_error_pct": 100 * (1.0 - float(np.max(F)) / bar.f_t), "target": 0.02, "curve": (v, F, None)}


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    rows, curves = [], {}
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for n in QUICK_SIZES if quick else SIZES:
            bar = SofteningBar(n)
            for run in (follow(bar), displacement_control(bar)):
                curves[(n, run["control"])] = run.pop("curve")
                row = {"study": "controls", "n": n, "snaps_back": bar.snaps_back, **run}
                rows.append(row)
                writer.write(**row)
                print(f"[path] n = {n:5d} {row['control']:15s} {row['steps']:4d} steps {row['iterations']:4d} "
                      f"iterations {row['cutbacks']:3d} cutbacks {row['cpu_seconds']:.2f} s, {row['status']}; "
                      f"force error {row['max_force_error_pct']:.2g} %", flush=True)
        bar = SofteningBar(200)
        for increment in QUICK_INCREMENTS if quick else INCREMENTS:
            run = follow(bar, increment=increment)
            run.pop("curve")
            row = {"study": "increment", "n": 200, "snaps_back": True, **run}
            rows.append(row)
            writer.write(**row)
            print(f"[path] n = 200, Δλ = {increment:g} before the peak: {row['steps']} steps, "
                  f"{row['cpu_seconds']:.2f} s, peak {row['peak_error_pct']:.3g} % low, budget error "
                  f"{row['budget_error_pct']:.3g} %", flush=True)
    data = {"rows": rows, "quick": quick, "date": time.strftime("%Y-%m-%d %H:%M"),
            "summary": "path following: " + "; ".join(
                f"n = {r['n']}: {r['steps']} steps, force error {r['max_force_error_pct']:.1g} %"
                for r in rows if r["study"] == "controls" and r["control"] == "path following")}
    write_json(outdir / f"{NAME}.json", data)
    plot(rows, curves, outdir / f"{NAME}.png")
    return data


def plot(rows, curves, path):
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.5))
    for k, n in enumerate(sorted({n for n, _ in curves})):
        bar = SofteningBar(n)
        sigma = np.linspace(bar.f_t, 0.0, 50)
        v_exact = np.concatenate(([0.0], bar.softening_displacement(sigma)))
        ax.plot(v_exact, np.concatenate(([0.0], sigma)), color=f"C{k}", lw=4, alpha=0.25)
        v, F, constraint = curves[(n, "path following")]
        ax.plot(v, F, "o", color=f"C{k}", ms=3, label=f"n = {n}, path following")
        v, F, _ = curves[(n, "displacement")]
        ax.plot(v, F, "x", color=f"C{k}", ms=5)
    ax.set(xlabel="end displacement v (mm)", ylabel="force F (N)", xlim=(0.0, 0.23),
           title="closed form (bands), path following (o), displacement control (x)")
    ax.legend(fontsize=8)
    study = sorted((r for r in rows if r["study"] == "increment"), key=lambda r: r["cpu_seconds"])
    for key, label in (("peak_error_pct", "peak force missed"), ("budget_error_pct", "energy budget")):
        bx.loglog([r["cpu_seconds"] for r in study], [max(r[key], 1e-8) for r in study], "o-", label=label)
    for r in study:
        bx.annotate(f"Δλ={r['target']:g}", (r["cpu_seconds"], max(r["peak_error_pct"], 1e-8)), fontsize=7)
    bx.set(xlabel="CPU time (s)", ylabel="error (% of f_t, % of G·A)",
           title="n = 200: load increment before the peak against error")
    bx.legend(fontsize=8)
    bx.grid(True, which="both", alpha=0.3)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="n = 10 and 200, two targets")
