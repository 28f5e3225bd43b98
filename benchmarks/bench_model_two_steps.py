"""Model II under displacement control, step by step: its force is continuous in u (no snap-back to follow), and
what each halving of the step costs and gains.

The rate limit of Eq. (6.96)-(6.98) lets a sub-domain's damage grow in one step by at most alpha times the
step's external work ``s sum_D du_D f*_D``, so the force of a Model II run is Lipschitz in the applied
displacement. Refining the step therefore shrinks the largest force drop of one step in proportion to the step
and leaves the steepest secant slope of a step converging; a snap-back or a vertical drop would keep the drop
(local Model I on a bar: about 50 % at every step size) and double the slope with every halving. Each
specimen, both regularisations of Table 7.2 and both formulations (plane strain times 3 mm, one element through
the 3 mm plate) run at load steps of 0.004 ... 0.00025 mm on about 250 elements until the force falls to 10 % of
its peak. Errors of peak force and work are taken against the finest step.

A diagnostic of Crisfield's arc length on the plate with a hole (250 elements, alpha = 0.05), which stalls at the
peak: once with the rate limit following the load factor through the Newton iterations (the default), once with
it frozen at the step's predictor (``rate_limit="predictor"``).

    python benchmarks/bench_model_two_steps.py [--quick] [--outdir DIR]

writes ``model_two_steps.csv``, ``model_two_steps.json`` and ``model_two_steps.png``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure

from abrakit.damage import metrics
from abrakit.damage.model_two_fe import RATE_LIMITS, run_model_two
from abrakit.damage.runs import REGULARISATION, run_specimen
from abrakit.damage.specimens import SPECIMENS, specimen
from abrakit.fem import PathControl
from abrakit.io import CurveWriter, write_json

NAME = "model_two_steps"
STEPS = (0.004, 0.002, 0.001, 0.0005, 0.00025)
QUICK_STEPS = (0.002, 0.001, 0.0005)
ELEMENTS, STOP = 250, 0.1
FORMULATIONS = ("plane_strain", "extruded")
COLUMNS = ("specimen", "strength", "alpha", "formulation", "step_mm", "elements", "peak_N", "work_Nmm",
           "largest_drop", "steepest_per_mm", "steps", "cutbacks", "seconds", "status", "peak_error", "work_error")


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    steps = QUICK_STEPS if quick else STEPS
    formulations = FORMULATIONS[:1] if quick else FORMULATIONS
    rows = []
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for formulation in formulations:
            for name in SPECIMENS:
                sp = specimen(name, ELEMENTS, formulation=formulation)
                for strength, alpha in REGULARISATION["II"].items():
                    case = []
                    for step in steps:
                        tic = time.perf_counter()
                        run = run_specimen(sp, "II", alpha, step=step, stop_fraction=STOP)
                        case.append({"specimen": name, "strength": strength, "alpha": alpha,
                                     "formulation": formulation, "step_mm": step, "elements": sp.elements,
                                     "peak_N": float(run.F.max()), "work_Nmm": metrics.work(run.u, run.F),
                                     "largest_drop": metrics.largest_drop(run.u, run.F),
                                     "steepest_per_mm": metrics.steepest_softening(run.u, run.F), "steps": run.steps,
                                     "cutbacks": run.cutbacks, "seconds": time.perf_counter() - tic,
                                     "status": run.status})
                    finest = case[-1]
                    for row in case:
                        row["peak_error"] = row["peak_N"] / finest["peak_N"] - 1.0
                        row["work_error"] = row["work_Nmm"] / finest["work_Nmm"] - 1.0
                        writer.write(**row)
                    rows += case
                    drops = ", ".join(f"{100 * r['largest_drop']:.1f}" for r in case)
                    slopes = ", ".join(f"{r['steepest_per_mm']:.0f}" for r in case)
                    print(f"[model II steps] {name} {strength} {formulation}: largest drop per step {drops} %, "
                          f"steepest slope {slopes} /mm at steps {', '.join(map(str, steps))} mm", flush=True)
    data = {"rows": rows, "steps_mm": list(steps), "elements": ELEMENTS, "stop_fraction": STOP, "quick": quick,
            "date": time.strftime("%Y-%m-%d %H:%M")}
    for key in ("largest_drop", "steepest_per_mm"):
        ratios = halving_ratios(rows, key)
        data[f"halving_ratio_{key}"] = {"min": min(ratios), "median": float(np.median(ratios)), "max": max(ratios)}
    data["arc_length"] = arc_length_diagnostic(max_steps=200 if quick else 600)
    drop, slope = data["halving_ratio_largest_drop"], data["halving_ratio_steepest_per_mm"]
    data["summary"] = (f"Model II, {len(rows)} runs: halving the step scales the largest force drop of a step by "
                       f"{drop['median']:.2f} (median; {drop['min']:.2f}-{drop['max']:.2f}) and the steepest slope by "
                       f"{slope['median']:.2f} ({slope['min']:.2f}-{slope['max']:.2f}): 0.5 and 1 for a force "
                       "continuous in u, 1 and 2 for a jump")
    write_json(outdir / f"{NAME}.json", data)
    plot(rows, outdir / f"{NAME}.png")
    return data


def arc_length_diagnostic(max_steps: int) -> list[dict]:
    """Arc length on the plate with a hole (250 elements, alpha = 0.05, steps of 2 x 0.002 mm in the load factor)
    with the rate limit of the current iterate and frozen at the step's predictor: status, steps, cutbacks and
    the force at the end over the peak."""
    sp = specimen("plate_with_hole", ELEMENTS)
    h = 0.002 / sp.displacement
    rows = []
    for rate_limit in RATE_LIMITS:
        tic = time.perf_counter()
        run = run_model_two(sp, REGULARISATION["II"]["weak"], stop_fraction=STOP, method="arc-length",
                            rate_limit=rate_limit,
                            path=PathControl(initial=2 * h, maximum=2 * h, target_iterations=8, max_steps=max_steps))
        F = run.curves["F"]
        rows.append({"rate_limit": rate_limit, "status": run.status, "steps": run.steps, "cutbacks": run.cutbacks,
                     "peak_N": float(F.max()), "end_over_peak": float(F[-1] / F.max()),
                     "seconds": time.perf_counter() - tic, "message": run.message})
        print(f"[model II steps] arc length, rate limit of the {rate_limit}: {run.status} after {run.steps} steps, "
              f"force at {F[-1] / F.max():.1%} of the peak", flush=True)
    return rows


def cases(rows):
    """The runs grouped by (specimen, strength, formulation), each sorted from the coarsest step."""
    groups = {}
    for row in rows:
        groups.setdefault((row["specimen"], row["strength"], row["formulation"]), []).append(row)
    return {key: sorted(group, key=lambda r: -r["step_mm"]) for key, group in groups.items()}


def halving_ratios(rows, key: str) -> list[float]:
    """``key`` at a step over ``key`` at the previous (twice as large) step, for every case and halving past the
    coarsest step (largest drop: 0.5 for a force continuous in u, 1 for a jump; steepest slope: 1 and 2)."""
    return [b[key] / a[key] for group in cases(rows).values() for a, b in zip(group[1:], group[2:], strict=False)]


def plot(rows, path):
    import matplotlib.pyplot as plt

    fig, (left, middle, right) = plt.subplots(1, 3, figsize=(16, 4.6))
    left.set_prop_cycle(color=plt.cm.tab20(np.linspace(0, 1, 20))[:12])
    middle.set_prop_cycle(color=plt.cm.tab20(np.linspace(0, 1, 20))[:12])
    right.set_prop_cycle(color=plt.cm.tab20(np.linspace(0, 1, 20))[:12])
    for (name, strength, formulation), group in cases(rows).items():
        style = "-" if formulation == "plane_strain" else "--"
        label = f"{name.replace('_', ' ')}, {strength}, {formulation.replace('_', ' ')}"
        step = np.array([r["step_mm"] for r in group])
        left.loglog(step, [100 * r["largest_drop"] for r in group], style, marker="o", ms=3, label=label)
        middle.loglog(step, [r["steepest_per_mm"] for r in group], style, marker="o", ms=3)
        error = [abs(r["peak_error"]) for r in group[:-1]]
        right.loglog([r["seconds"] for r in group[:-1]], np.maximum(error, 1e-5), style, marker="o", ms=3)
    step = np.array(sorted({r["step_mm"] for r in rows}))
    left.loglog(step, 5e3 * step, "k:", lw=1, label="slope 1")
    left.set(xlabel="load step [mm]", ylabel="largest force drop of one step [% of peak]",
             title="Model II: the drop per step shrinks with the step")
    left.legend(fontsize=6)
    middle.set(xlabel="load step [mm]", ylabel="steepest secant of a step [peak / mm]",
               title="... and its steepest slope converges")
    right.set(xlabel="run time [s]", ylabel="|peak error| against the finest step",
              title="speed against error")
    for ax in (left, middle):
        ax.xaxis.set_minor_formatter(plt.NullFormatter())
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="plane strain, three steps")
