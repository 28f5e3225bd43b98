"""Convergence of the fatigue beam's life in the steps per cycle and the cycle-jump size (seed 002, Sec. 5).

The small rocker beam (``BeamSpec(radius=5e-3, seed=3)``: 98 disks, 245 bonds), P_max from its monotonic test
(``monotonic_bending(speed=1e-3, drop=0.9)``), then force-controlled haversine cycles at 0.86 and 0.79 P_max with
the ratcheting extrapolated through each jump and one settling cycle after it (``plasticity="extrapolated"``,
``settle=1``), the jump schedule in stages resumed from the run's checkpoint: ΔD_jump = 0.003 for the first ten
simulated cycles, 0.01 for six more, then 0.02 ("standard"); the same schedule with every jump halved ("halved")
and ΔD_jump = 0.003 throughout ("0.003"). Each run at 2000, 4000, 8000 and 16000 steps per cycle (the jump
variants at 8000; at 0.86 also 32000 steps, and the jump variants at 16000), with the peak-deflection ratio
δ_peak/δ_static of its first cycle beside the life (the quasi-static measure of
:func:`~abrakit.experiments.cyclic.cyclic_bending`) and the life's deviation from the finest run of its level
and schedule. Beside the lives, the damage two cycles add to one mid-life state (from the 16000-steps run) at
2000 to 64000 steps per cycle: the per-cycle rate the life integrates.

Every case is a resumable sweep record (``fatigue_convergence_runs/``: a finished case is read back, not
recomputed) and every fatigue run checkpoints after each simulated cycle (``fatigue_convergence_checkpoints/``), so
an interrupted study loses at most one cycle of one run; cases are ordered cheapest and most informative first.

    python benchmarks/bench_fatigue_convergence.py [--quick] [--outdir DIR]

writes ``fatigue_convergence.csv`` (one row per run), ``fatigue_convergence.json`` and ``fatigue_convergence.png``.
"""

from __future__ import annotations

import json
import shutil
import time
import warnings
from pathlib import Path

import matplotlib.pyplot as plt
from _common import command_line, save_figure, study_dirs

from abrakit.experiments.bending import BeamSpec, four_point_beam, monotonic_bending
from abrakit.experiments.cyclic import cyclic_bending
from abrakit.experiments.sweeps import run_sweep
from abrakit.io import CurveWriter, load_state, write_json

NAME = "fatigue_convergence"
CHECKPOINT = ("checkpoint",)    # where a run keeps its state: not part of its key (records move between clones)
BEAM = {"radius": 5e-3, "seed": 3}
SCHEDULES = {"standard": [[0.003, 10], [0.01, 6], [0.02, None]],
             "halved": [[0.0015, 10], [0.005, 6], [0.01, None]],
             "0.003": [[0.003, None]]}
"""Jump schedules: [ΔD_jump, simulated cycles] stages, the last one open-ended."""
STEPS = (2000, 4000, 8000, 16000)
LEVELS = (0.86, 0.79)


def _spec(params: dict) -> BeamSpec:
    return BeamSpec(radius=params["radius"], seed=params["seed"])


def monotonic_case(params: dict) -> dict:
    r = monotonic_bending(four_point_beam(_spec(params)), speed=params["speed"], drop=params["drop"])
    return {"P_max": float(r["load"].max()), "FS_max": r["FS_max"], "steps": r["steps"], "seconds": r["seconds"]}


def _simulated(checkpoint: Path) -> int:
    """Simulated cycles a checkpoint holds (0 without one)."""
    saved = load_state(checkpoint) if checkpoint.exists() else None
    return 0 if saved is None else len(saved["record"]["cycles"])


def run_stages(beam, load: float, schedule: list, checkpoint: Path, time_limit: float | None = None, **settings):
    """The schedule's stages ([ΔD_jump, simulated cycles], the last count None: open-ended), each a
    :func:`cyclic_bending` call resumed from ``checkpoint``, at most ``time_limit`` seconds in all; yields each
    call's result and stops after a call that ended for another reason than its stage's cycle count."""
    clock, bound = time.perf_counter(), 0
    for jump, count in schedule:
        bound = None if count is None else bound + count
        done = _simulated(checkpoint)
        if bound is not None and done >= bound:
            continue
        left = None if time_limit is None else max(time_limit - (time.perf_counter() - clock), 1.0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)    # the ratio is recorded instead
            r = cyclic_bending(beam, load, jump=jump, checkpoint=checkpoint, time_limit=left,
                               max_simulated=None if bound is None else bound - done, **settings)
        yield r
        if r["stopped"] != "max_simulated":
            return


def fatigue_case(params: dict) -> dict:
    """One run: the schedule's stages (:func:`run_stages`), at most ``time_limit`` seconds in all (the first
    cycle's peak-deflection ratio kept beside the checkpoint)."""
    beam = four_point_beam(_spec(params), control="force")
    checkpoint = Path(params["checkpoint"])
    ratio_file = checkpoint.with_suffix(".ratio.json")
    r = None
    for r in run_stages(beam, params["level"] * params["P_max"], params["schedule"], checkpoint,
                        params["time_limit"], steps_per_cycle=params["steps_per_cycle"],
                        plasticity="extrapolated", settle=1, max_cycles=params["max_cycles"]):
        if r["amplification"] is not None:
            write_json(ratio_file, {"ratio": 1.0 + r["amplification"]})
    ratio = json.loads(ratio_file.read_text())["ratio"] if ratio_file.exists() else None
    return {"life": r["life"], "stopped": r["stopped"], "simulated_cycles": r["simulated_cycles"],
            "cycles": r["cycles"].tolist(), "measured_at": r["measured_at"].tolist(),
            "modulus_ratio": (r["modulus"] / r["modulus"][0]).tolist(), "broken": r["broken"].tolist(),
            "seconds": r["seconds"], "peak_ratio": ratio}


def rate_case(params: dict) -> dict:
    """The damage that two cycles add to one mid-life state, against the steps per cycle: the state is the
    ``state_steps`` run's after ``state_cycles`` simulated cycles (0.86 P_max, standard jumps), each resolution
    then resumes a copy of it for two cycles without a jump. It shows whether the per-cycle damage rate has
    converged where the life has not."""
    state = Path(params["checkpoint"])
    settings = {"plasticity": "extrapolated", "settle": 1, "quasi_static_check": False}
    load = params["level"] * params["P_max"]
    *first, (last_jump, _) = SCHEDULES["standard"]
    schedule = [*first, [last_jump, params["state_cycles"] - sum(count for _, count in first)]]
    for _ in run_stages(four_point_beam(_spec(params), control="force"), load, schedule, state,
                        steps_per_cycle=params["state_steps"], **settings):
        pass
    saved = load_state(state)
    start = saved["sim"]["fatigue_bonds"].damage.copy()
    rows = []
    for n in params["steps"]:
        copy = state.with_name(f"rate_{n}.pkl")
        shutil.copy(state, copy)
        clock = time.perf_counter()
        r = cyclic_bending(four_point_beam(_spec(params), control="force"), load, steps_per_cycle=n, jump=None,
                           checkpoint=copy, max_simulated=2, **settings)
        grown = load_state(copy)["sim"]["fatigue_bonds"].damage - start
        copy.unlink()
        rows.append({"steps_per_cycle": n, "damage_added": float(grown.sum()), "largest": float(grown.max()),
                     "bonds": int((grown > 1e-12).sum()), "deflection": float(r["deflection"][-1]),
                     "seconds": time.perf_counter() - clock})
    return {"cycles": int(saved["record"]["cycles"][-1]),
            "modulus_ratio": float(saved["record"]["modulus"][-1] / saved["record"]["modulus"][0]), "rows": rows}


def cases(p_max: float, checkpoints: Path, quick: bool) -> list[dict]:
    """The runs, cheapest and most informative first: 0.86 P_max at every resolution, then 0.79, then the jump
    variants at 8000 steps per cycle, then 0.86 at 32000 steps and its jump variants at 16000 (0.79 shakes down
    at 16000 steps with every schedule, so it has no finer life to compare)."""
    levels, steps = ((0.86,), (2000, 4000)) if quick else (LEVELS, STEPS)
    plan = [(level, n, "standard") for level in levels for n in steps]
    plan += [] if quick else [(level, 8000, s) for s in ("halved", "0.003") for level in levels]
    plan += [] if quick else [(0.86, 32000, "standard"), (0.86, 16000, "halved"), (0.86, 16000, "0.003")]
    return [{**BEAM, "P_max": p_max, "level": level, "steps_per_cycle": n, "schedule": SCHEDULES[schedule],
             "schedule_name": schedule, "max_cycles": 1_000_000, "time_limit": 600 if quick else 5400,
             "name": f"level{level:.2f}_steps{n}_{schedule}",
             "checkpoint": str(checkpoints / f"level{level:.2f}_steps{n}_{schedule}.pkl")}
            for level, n, schedule in plan]


def _deviations(runs: list[dict]) -> None:
    """Each run's life against the finest-resolution run of its level and schedule (in place)."""
    for run in runs:
        same = [r for r in runs if r["level"] == run["level"] and r["schedule_name"] == "standard" and r["life"]]
        finest = max(same, key=lambda r: r["steps_per_cycle"], default=None)
        run["converged_life"] = None if finest is None else finest["life"]
        run["life_error"] = (run["life"] / finest["life"] - 1.0) if finest and run["life"] else None


def plot(runs: list[dict], path: Path) -> None:
    fig, ax = plt.subplots(1, 3, figsize=(15, 4))
    for k, level in enumerate(sorted({r["level"] for r in runs}, reverse=True)):
        own = sorted((r for r in runs if r["level"] == level and r["schedule_name"] == "standard"),
                     key=lambda r: r["steps_per_cycle"])
        done = [r for r in own if r["life"]]
        ax[0].semilogx([r["steps_per_cycle"] for r in done], [r["life"] for r in done], "o-", color=f"C{k}",
                       label=f"{100 * level:.0f} % P_max")
        for r in runs:
            if r["level"] == level and r["schedule_name"] != "standard" and r["life"]:
                ax[0].semilogx(r["steps_per_cycle"], r["life"], "s^"[r["schedule_name"] == "0.003"], color=f"C{k}",
                               mfc="none", label=f"{100 * level:.0f} %, jumps {r['schedule_name']}")
        ratio = [r for r in own if r["peak_ratio"] is not None]
        ax[1].semilogx([r["steps_per_cycle"] for r in ratio], [r["peak_ratio"] for r in ratio], "o-",
                       color=f"C{k}", label=f"{100 * level:.0f} % P_max")
        for r in done:
            ax[2].plot(r["measured_at"], r["modulus_ratio"], "-", lw=0.8, color=f"C{k}",
                       alpha=0.4 + 0.6 * r["steps_per_cycle"] / max(x["steps_per_cycle"] for x in done))
    ax[0].set(xlabel="steps per cycle", ylabel="fatigue life N_f", title="life (standard jumps; open: other jumps)")
    ax[0].legend(fontsize=7)
    ax[1].axhspan(0.98, 1.02, color="grey", alpha=0.2)
    ax[1].set(xlabel="steps per cycle", ylabel="δ_peak / δ_static", title="peak deflection of the first cycle")
    ax[1].legend(fontsize=7)
    ax[2].axhline(0.5, color="grey", lw=0.5)
    ax[2].set(xlabel="cycle N", ylabel="E_f / E_f,0", title="modulus (darker: more steps per cycle)")
    save_figure(fig, path)


def main(outdir: Path, quick: bool = False) -> dict:
    outdir, checkpoints = study_dirs(outdir, NAME)
    monotonic = run_sweep(monotonic_case, [{**BEAM, "speed": 1e-3, "drop": 0.9, "name": "monotonic"}],
                          outdir / f"{NAME}_runs", backend="serial")[0]["result"]
    records = run_sweep(fatigue_case, cases(monotonic["P_max"], checkpoints, quick), outdir / f"{NAME}_runs",
                        backend="serial", paths=CHECKPOINT, errors="record")
    runs = [{**r["params"], **r["result"]} for r in records if r["result"] is not None]
    rate = None if quick else run_sweep(
        rate_case, [{**BEAM, "P_max": monotonic["P_max"], "level": 0.86, "state_steps": 16000, "state_cycles": 40,
                     "steps": [2000, 4000, 8000, 16000, 32000, 64000], "name": "rate_from_state",
                     "checkpoint": str(checkpoints / "rate_state.pkl")}],
        outdir / f"{NAME}_runs", backend="serial", paths=CHECKPOINT)[0]["result"]
    _deviations(runs)
    columns = ("level", "schedule", "steps_per_cycle", "life", "stopped", "life_error", "peak_ratio",
               "simulated_cycles", "seconds", "seconds_per_cycle")
    writer = CurveWriter(outdir / f"{NAME}.csv", columns)
    for r in runs:
        writer.write(level=r["level"], schedule=r["schedule_name"], steps_per_cycle=r["steps_per_cycle"],
                     life=r["life"] or 0, stopped=r["stopped"],
                     life_error=float("nan") if r["life_error"] is None else r["life_error"],
                     peak_ratio=float("nan") if r["peak_ratio"] is None else r["peak_ratio"],
                     simulated_cycles=r["simulated_cycles"], seconds=r["seconds"],
                     seconds_per_cycle=r["seconds"] / max(r["simulated_cycles"], 1))
    writer.close()
    plot(runs, outdir / f"{NAME}.png")
    table = [{k: r[k] for k in ("level", "schedule_name", "steps_per_cycle", "life", "stopped", "life_error",
                                 "peak_ratio", "simulated_cycles", "seconds")} for r in runs]
    result = {"monotonic": monotonic, "runs": table, "quick": quick, "rate_from_state": rate,
              "missing": [r["params"]["name"] for r in records if r["result"] is None]}
    write_json(outdir / f"{NAME}.json", result)
    lines = [f"P_max {monotonic['P_max']:.1f} N"]
    lines += [f"{100 * r['level']:.0f} % {r['schedule_name']:>8} {r['steps_per_cycle']:>5} steps/cycle: life "
              f"{r['life']} ({r['stopped']}), {'-' if r['life_error'] is None else format(r['life_error'], '+.1%')}"
              f" from the finest, δ_peak/δ_static {r['peak_ratio'] or float('nan'):.3f}, {r['simulated_cycles']} "
              f"simulated in {r['seconds']:.0f} s" for r in table]
    if rate is not None:
        finest = rate["rows"][-1]["damage_added"]
        lines.append(f"damage added in two cycles from cycle {rate['cycles']} (E_f/E_f,0 "
                     f"{rate['modulus_ratio']:.3f}):")
        lines += [f"  {r['steps_per_cycle']:>5} steps/cycle: {r['damage_added']:.4e} "
                  f"({r['damage_added'] / finest - 1:+.1%} from the finest), {r['bonds']} bonds"
                  for r in rate["rows"]]
    result["summary"] = "\n".join(lines)
    return result


if __name__ == "__main__":
    command_line(main, __doc__)
