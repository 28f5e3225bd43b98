"""Speed against error of the evolution-law update schemes of ``abrakit.evolution`` (seed Ch. 2.6, Eq. 4.53).

Two 1D models (hardening viscoplasticity, exponential damage) are driven along one smooth strain cycle
ε(t) = ε_a sin(2π t / T), T = 1 s, with every time discretisation listed after Eq. (2.110) (explicit, implicit,
the two operator splits) and with the numerical incremental variational update. The error is the largest
deviation of the internal variable from a DOP853 solution of the rate law at rtol 1e-12; runtime is the best of
three runs (one for the variational update). A second study times one step on a batch of material points.

    python benchmarks/bench_evolution.py [--quick] [--outdir DIR]

writes ``evolution.csv`` (one row per model, scheme and Δt, flushed as it goes), ``evolution.json`` (orders,
throughput, parameters) and ``evolution.png`` (error vs Δt and error vs runtime).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from _common import command_line, save_figure

from abrakit import evolution as ev
from abrakit.io import CurveWriter, write_json

NAME = "evolution"
CLOSED_FORM = tuple(ev.SCHEMES)


def cases():
    """Model, dissipation and strain amplitude of each study (MPa, s; E and K_H from Table 7.1)."""
    return {
        "plasticity": (ev.Plasticity1D(E=200_000.0, K=8_000.0), ev.elasto_viscoplastic(60.0, 10_000.0), 2e-3),
        "damage": (ev.Damage1D(E=200_000.0), ev.elasto_viscoplastic(0.05, 0.05), 1.5e-3),
    }


def throughput(model, dissipation, amp, n_points, scheme, repeats=3):
    """Material-point updates per second for one step on a batch of ``n_points`` points."""
    rng = np.random.default_rng(0)
    eps_m = rng.uniform(-amp, amp, n_points)
    eps_new = eps_m + 0.1 * amp
    state = model.initial_state((n_points,))
    best = np.inf
    for _ in range(repeats):
        tic = time.perf_counter()
        model.update(state, eps_m, eps_new, 0.01, dissipation, scheme)
        best = min(best, time.perf_counter() - tic)
    return n_points / best


def main(outdir: Path = Path(__file__).parent / "results", quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    n_closed = 2 ** np.arange(3, 9 if quick else 13)  # Δt = 1/8 … 1/4096 s
    n_variational = n_closed[:4] if quick else n_closed  # about 0.4 ms per numerical minimisation
    summary = {"quick": quick, "t_end": 1.0, "reference": "DOP853, rtol 1e-12, atol 1e-15",
               "error": "max over steps of |λ_m - λ_ref(t_m)| (εp for plasticity, d for damage)",
               "models": {}}
    studies = {}
    with CurveWriter(outdir / f"{NAME}.csv", ["model", "scheme", "n_steps", "dt", "runtime_s", "error"]) as csv:
        for name, (model, diss, amp) in cases().items():
            def strain(t, amp=amp):
                return amp * np.sin(2 * np.pi * t)

            def record(name=name, **row):
                csv.write(model=name, scheme=row["scheme"], n_steps=row["n_steps"], dt=row["dt"],
                          runtime_s=row["runtime"], error=row["error"])

            closed = ev.convergence_study(model, diss, strain, 1.0, n_closed, CLOSED_FORM, repeats=3,
                                          on_result=record)
            numeric = ev.convergence_study(model, diss, strain, 1.0, n_variational, ("variational",),
                                           on_result=record)
            study = {**{s: closed[s] for s in CLOSED_FORM}, "variational": numeric["variational"]}
            studies[name] = study
            orders = {**closed["orders"], **numeric["orders"]}
            points = 2_000 if quick else 20_000
            summary["models"][name] = {
                "model": repr(model), "dissipation": repr(diss), "strain_amplitude": amp,
                "observed_order": orders,
                "finest_dt": {s: float(study[s]["dt"][-1]) for s in study},
                "finest_error": {s: float(study[s]["error"][-1]) for s in study},
                "updates_per_second": {
                    **{s: throughput(model, diss, amp, points, s) for s in CLOSED_FORM},
                    "variational": throughput(model, diss, amp, 20, "variational", repeats=1),
                },
            }
            if name == "plasticity":
                summary["models"][name]["relaxation_time_s"] = diss.r2 / (model.E + model.K)
    lines = [f"{m}: orders " + ", ".join(f"{s} {o:.2f}" for s, o in d["observed_order"].items())
             for m, d in summary["models"].items()]
    summary["summary"] = "; ".join(lines)
    write_json(outdir / f"{NAME}.json", summary)
    plot(studies, outdir / f"{NAME}.png")
    return summary


def plot(studies, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    styles = {"explicit": "o-", "implicit": "s-", "split": "^-", "split_reverse": "v-", "variational": "x--"}
    fig, axes = plt.subplots(len(studies), 2, figsize=(10, 4 * len(studies)), squeeze=False)
    for row, (name, study) in zip(axes, studies.items(), strict=True):
        for scheme, data in study.items():
            row[0].loglog(data["dt"], data["error"], styles[scheme], label=scheme, ms=4)
            row[1].loglog(data["runtime"], data["error"], styles[scheme], label=scheme, ms=4)
        dt = study["implicit"]["dt"]
        ref = study["implicit"]["error"][-1] * dt / dt[-1]
        row[0].loglog(dt, ref, "k:", lw=1, label="slope 1")
        row[0].set(xlabel="Δt [s]", ylabel="max error of λ", title=f"{name}: error vs time step")
        row[1].set(xlabel="runtime [s] (one material point, one cycle)", ylabel="max error of λ",
                   title=f"{name}: error vs runtime")
        for ax in row:
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=8)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="fewer time steps (seconds instead of a minute)")
