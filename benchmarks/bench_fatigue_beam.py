"""Four-point bending fatigue of the cemented DEM beam (seed 002, Sec. 5): strength and cost against resolution and
grading, the cycle jump's accuracy against a cycle-by-cycle run, and the S–N curve.

1. *Resolution*: monotonic tests on the lattice at largest radii 5, 3.5 and 2.5 mm and on the Fuller-graded
   packing at 6 and 4 mm (two seeds each): FS_max, the initial flexural modulus, particle and bond counts, wall time
   per step, and the wall time of one simulated cycle.
2. *Cycle jump*: the 5 mm lattice beam at 77 % of its FS_max, cycle by cycle (the reference) and with
   ΔD_jump = 0.01, 0.003, 0.001 (and 0.0003), yielding bonds frozen through a jump (the paper) or their ratcheting
   extrapolated (with one settling cycle after each jump, and without it at 0.003 and 0.001): fatigue life (cycles
   to E_f/E_f,0 = 0.5) and its deviation from the reference, the largest deviation of E_f/E_f,0 from the
   reference's at the same cycle, simulated cycles, wall time.
3. *S–N*: the 5 mm lattice beam at 95, 92, 84, 81, 77 and 70 % of FS_max with ΔD_jump = 0.003 (the paper's), with
   yielding bonds frozen (the paper) and extrapolated with one settling cycle; a log-linear fit S = a + b log₁₀ N
   over the levels that reached their life.

4. *Rockers* (issue 37): both tests on the rocker fixture (one specimen for the monotonic and the cyclic test, at
   the exact spans), per specimen (the Fuller-graded 6 mm packing with seeds 0 and 1, and the 5 mm lattice): the
   monotonic test, then S–N at the paper's levels of that specimen's own P_max with ΔD_jump = 0.003, the
   ratcheting extrapolated and one settling cycle (8000 steps per cycle, seating load 10 %), a log-linear fit per
   specimen and over both graded seeds with its residuals in decades (``fatigue_beam_rockers.png``), the slopes of
   the three stages of E_f/E_f,0 against N/N_f of every run that reached its life
   (:func:`~abrakit.experiments.cyclic.stage_slopes`); and each
   graded specimen calibrated to the paper's FS_max by similarity (:func:`~abrakit.experiments.bending.
   scaled_strengths`: strengths, softening displacements and loading speed × FS_paper / FS_max), its monotonic test
   rerun to show the calibrated FS_max and the unchanged E_f, and its S–N runs at the same levels of its own P_max
   (after every uncalibrated run).

Every case is a resumable sweep record (``fatigue_beam_resolution/``, ``fatigue_beam_jump/``, ``fatigue_beam_sn/``,
``fatigue_beam_rockers_*/``: a finished case is read back, not recomputed), and the fatigue runs checkpoint every
simulated cycle (``fatigue_beam_checkpoints/``), so an interrupted study loses at most one cycle of each run.

    python benchmarks/bench_fatigue_beam.py [--quick] [--outdir DIR]

writes ``fatigue_beam.csv`` (one row per run), ``fatigue_beam.json`` and ``fatigue_beam.png``.
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from _common import command_line, save_figure, study_dirs

from abrakit.dem.fatigue_specimen import history_deviation
from abrakit.experiments.bending import (
    SEATING,
    BeamSpec,
    flexural,
    four_point_beam,
    monotonic_bending,
    scaled_strengths,
    table_two,
)
from abrakit.experiments.cyclic import cyclic_bending, measured_cycles, stage_slopes
from abrakit.experiments.sweeps import run_sweep
from abrakit.io import CurveWriter, write_json

NAME = "fatigue_beam"
CHECKPOINT = ("checkpoint",)    # where a run keeps its state: not part of its key (records move between clones)
PAPER = {"FS_max_kPa": 1336.4, "levels": (0.95, 0.92, 0.84, 0.81, 0.77, 0.70), "jump": 0.003}


def _spec(params: dict) -> BeamSpec:
    return BeamSpec(radius=params["radius"], seed=params["seed"], grading=params.get("grading", "lattice"))


def _beam(params: dict, control: str = "displacement"):
    """The case's beam: the pads (the stored studies) unless ``fixture`` says "rockers"; Table 2's bonds, their
    strengths and softening displacements scaled by ``strength_scale`` if given (the calibration)."""
    bonds = scaled_strengths(table_two(), params.get("strength_scale", 1.0))
    return four_point_beam(_spec(params), bonds, control=control, fixture=params.get("fixture", "pads"))


def _cycles(params: dict) -> dict:
    """The cyclic test's settings of a case: 2000 steps per cycle from zero load on the pads; the rockers' studies
    give their own steps and the seating load one-sided supports need."""
    return {"steps_per_cycle": params.get("steps_per_cycle", 2000),
            "load_min_ratio": params.get("load_min_ratio", 0.0)}


def monotonic_case(params: dict) -> dict:
    spec = _spec(params)
    beam = _beam(params)
    r = monotonic_bending(beam, speed=5e-4 * params.get("strength_scale", 1.0), record_every=200, drop=0.8)
    k = int(np.argmax(r["load"]))
    early = (np.arange(len(r["load"])) < k) & (r["load"] < 0.2 * r["load"][k]) & (r["deflection"] > 0)
    modulus = float(np.median(flexural(r["load"][early], r["deflection"][early], spec)["modulus"]))
    cyclic = _beam(params, control="force")
    tic = time.perf_counter()
    cyclic_bending(cyclic, 0.5 * float(r["load"][k]), max_simulated=2, **_cycles(params))
    return {"particles": len(beam.sim.particles), "bonds": len(beam.sim.fatigue_bonds), "FS_max": r["FS_max"],
            "P_max": float(r["load"][k]), "modulus": modulus, "seconds": r["seconds"], "steps": r["steps"],
            "ms_per_step": 1e3 * r["seconds"] / r["steps"], "seconds_per_cycle": (time.perf_counter() - tic) / 2,
            "time_step": beam.sim.dt, "curve": {"stress": r["stress"].tolist(), "strain": r["strain"].tolist()}}


def fatigue_case(params: dict) -> dict:
    beam = _beam(params, control="force")
    checkpoint = params.get("checkpoint")
    r = cyclic_bending(beam, params["level"] * params["P_max"], jump=params["jump"],
                       plasticity=params.get("plasticity", "frozen"), settle=params.get("settle", 0),
                       **_cycles(params), max_cycles=params["max_cycles"], time_limit=params.get("time_limit"),
                       max_simulated=params.get("max_simulated"), checkpoint=checkpoint)
    return {"life": r["life"], "stopped": r["stopped"], "simulated_cycles": r["simulated_cycles"],
            "seconds": r["seconds"], "cycles": r["cycles"].tolist(), "measured_at": r["measured_at"].tolist(),
            "modulus_ratio": (r["modulus"] / r["modulus"][0]).tolist(), "damaged": r["damaged"].tolist(),
            "yielding": r["yielding"].tolist(), "amplification": r["amplification"]}


def _measured(run: dict) -> dict:
    """``run`` with E_f filed under the cycle it was measured in (``measured_at``) and the life read there: runs
    recorded before issue 37 filed it under the count after the cycle's jump (their life was the count after the
    last jump)."""
    if "measured_at" not in run:
        run["measured_at"] = measured_cycles(run["cycles"]).tolist()
        if run["life"]:
            run["life"] = run["measured_at"][-1]
    return run


def _life_error(run: dict, reference: dict) -> float | None:
    if not (run["life"] and reference["life"]):
        return None
    return run["life"] / reference["life"] - 1.0


def _curve_error(run: dict, reference: dict) -> float:
    """Largest relative deviation of E_f/E_f,0 from the reference's at the run's cycles, up to the first cycle where
    either has fallen to 0.75 (before the final collapse, whose timing the life compares)."""
    n, ratio = np.asarray(reference["measured_at"]), np.asarray(reference["modulus_ratio"])
    end = min(n[np.argmax(ratio < 0.75)] if np.any(ratio < 0.75) else n[-1],
              next((c for c, m in zip(run["measured_at"], run["modulus_ratio"], strict=True) if m < 0.75), n[-1]))
    keep = np.asarray(run["measured_at"]) <= end
    early = {"cycles": np.asarray(run["measured_at"])[keep], "modulus_ratio": np.asarray(run["modulus_ratio"])[keep]}
    return history_deviation(early, {"cycles": reference["measured_at"], "modulus_ratio": ratio},
                             key="modulus_ratio")


ROCKERS = {"fixture": "rockers", "steps_per_cycle": 8000, "load_min_ratio": SEATING}
"""The rocker fixture's cyclic settings: 8000 steps per cycle (the coarse beam's dynamic amplification within 2 % up
to 77 % of P_max) and a seating load of 10 % of the peak, which one-sided supports need."""


def _log_linear(runs: list[dict]) -> dict | None:
    """S = a + b log₁₀ N over the runs that reached their life, with the residuals in decades of N."""
    failed = [r for r in runs if r["life"]]
    if len(failed) < 2:
        return None
    lives, levels = np.log10([r["life"] for r in failed]), np.array([r["level"] for r in failed])
    slope, intercept = np.polyfit(lives, levels, 1)
    return {"intercept": float(intercept), "slope_per_decade": float(slope), "points": len(failed),
            "residual_decades": ((levels - intercept) / slope - lives).tolist()}


def _runs_of(specimen: dict, runs: list[dict]) -> list[dict]:
    """The rocker study's runs of one specimen (named after its monotonic test)."""
    return [r for r in runs if r["name"].startswith(specimen["name"] + "_level")]


def rocker_specimens(outdir: Path, quick: bool) -> list[dict]:
    """The rocker study's specimens (the Fuller-graded 6 mm packing, two seeds, and the 5 mm lattice), each with its
    monotonic test on the rockers."""
    specimens = [("lattice", 5e-3, 0)] if quick else [("fuller", 6e-3, 0), ("fuller", 6e-3, 1), ("lattice", 5e-3, 0)]
    return [{**r["params"], **r["result"]} for r in run_sweep(
        monotonic_case, [{"grading": g, "radius": radius, "seed": seed,
                          "name": f"rockers_{g}{radius * 1e3:.1f}mm_seed{seed}", **ROCKERS}
                         for g, radius, seed in specimens], outdir / f"{NAME}_rockers_monotonic", backend="serial")]


def calibrated_specimen(specimen: dict, outdir: Path, tolerance: float = 0.01, max_steps: int = 4) -> dict:
    """The similarity search for the paper's FS_max from a specimen's monotonic test: factor ← factor FS_paper /
    FS_max(factor), each step one monotonic test with σ_t, c, ū and the loading speed scaled (decision "calibrating
    the beam's strength by similarity"), until FS_max is within ``tolerance`` of the paper's. The graded packings'
    settling forces do not scale, so the first step can miss by a few per cent."""
    target = PAPER["FS_max_kPa"] * 1e3
    record, factor = specimen, 1.0
    for _ in range(max_steps):
        if factor != 1.0 and abs(record["FS_max"] / target - 1.0) <= tolerance:
            break
        factor *= target / record["FS_max"]
        run = run_sweep(monotonic_case, [
            {"grading": specimen["grading"], "radius": specimen["radius"], "seed": specimen["seed"],
             "name": f"{specimen['name']}_calibrated", "strength_scale": factor, **ROCKERS}],
            outdir / f"{NAME}_rockers_monotonic", backend="serial")[0]
        record = {**run["params"], **run["result"]}
    return record


def rocker_case(specimen: dict, level: float, checkpoints: Path, quick: bool) -> dict:
    """The S–N case of a specimen at ``level`` × its own P_max: ΔD_jump = 0.003, the ratcheting extrapolated, one
    settling cycle, at most an hour (five minutes in the quick run)."""
    return {"grading": specimen["grading"], "radius": specimen["radius"], "seed": specimen["seed"],
            "P_max": specimen["P_max"], **ROCKERS, "max_cycles": 1_000_000, "time_limit": 300 if quick else 3600,
            "level": level, "jump": 0.003, "plasticity": "extrapolated", "settle": 1,
            "name": f"{specimen['name']}_level{level:.2f}",
            "checkpoint": str(checkpoints / f"{specimen['name']}_{level:.2f}.pkl"),
            **({"strength_scale": specimen["strength_scale"]} if "strength_scale" in specimen else {})}


def rocker_study(outdir: Path, checkpoints: Path, quick: bool) -> dict:
    """Issue 37: both tests on the rocker fixture, per specimen (the Fuller-graded 6 mm packing, two seeds, and the
    5 mm lattice): the monotonic test, then the S–N levels as fractions of that specimen's own P_max, ΔD_jump =
    0.003 with the ratcheting extrapolated and one settling cycle, each run at most an hour (20 minutes before the
    compiled beam step, which stopped four graded runs without a life)."""
    monotonic = rocker_specimens(outdir, quick)
    calibrated = [calibrated_specimen(m, outdir) for m in monotonic if m["grading"] == "fuller"]
    levels = (0.95, 0.77) if quick else PAPER["levels"]
    cases = [rocker_case(m, level, checkpoints, quick) for level in levels for m in monotonic]
    cases += [rocker_case(m, level, checkpoints, quick) for level in levels for m in calibrated]  # after the others
    sn = [_measured({**r["params"], **r["result"]})
          for r in run_sweep(fatigue_case, cases, outdir / f"{NAME}_rockers_sn", backend="serial", paths=CHECKPOINT)]
    for run in sn:                          # the three stages of each run that reached its life
        run["stages"] = stage_slopes(run["measured_at"], run["modulus_ratio"], run["life"]) if run["life"] else None
    fits = {m["name"]: _log_linear(_runs_of(m, sn)) for m in monotonic + calibrated}
    graded = [r for r in sn if r["grading"] == "fuller" and "strength_scale" not in r]
    fits["graded, both seeds"] = _log_linear(graded)
    fits["graded, both seeds, calibrated"] = _log_linear([r for r in sn if "strength_scale" in r])
    return {"monotonic": [{k: v for k, v in m.items() if k != "curve"} for m in monotonic], "sn": sn, "fits": fits,
            "calibrated": [{k: v for k, v in m.items() if k != "curve"} for m in calibrated]}


def plot_rockers(rockers: dict, path: Path) -> None:
    """S–N per specimen on the rockers, and E_f/E_f,0 against N/N_f of the runs that reached their life."""
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for k, m in enumerate(rockers["monotonic"] + rockers["calibrated"]):
        failed = [r for r in _runs_of(m, rockers["sn"]) if r["life"]]
        calibrated = ", calibrated" if "strength_scale" in m else ""
        ax[0].semilogx([r["life"] for r in failed], [100 * r["level"] for r in failed], "os^D"[k % 4], color=f"C{k}",
                       label=f"{m['grading']} {m['radius'] * 1e3:.0f} mm, seed {m['seed']}{calibrated} "
                             f"(FS_max {m['FS_max'] / 1e3:.0f} kPa)")
        for r in failed:
            n = np.asarray(r["measured_at"], float)
            ax[1].plot(n / r["life"], r["modulus_ratio"], "-", lw=0.8, color=f"C{k}")
    ax[0].set(xlabel="fatigue life N_f", ylabel="stress level [% of the specimen's FS_max]",
              title="S–N on rockers (ΔD_jump 0.003, ratcheting extrapolated)")
    ax[0].legend(fontsize=7)
    ax[1].axhline(0.5, color="grey", lw=0.5)
    ax[1].set(xlabel="N / N_f", ylabel="E_f / E_f,0", title="modulus degradation, every run that failed")
    save_figure(fig, path)


def main(outdir: Path, quick: bool = False) -> dict:
    outdir, checkpoints = study_dirs(outdir, NAME)
    seeds = (0,) if quick else (0, 1)
    samples = [("lattice", 5e-3)] if quick else [("lattice", 5e-3), ("lattice", 3.5e-3), ("lattice", 2.5e-3),
                                                  ("fuller", 6e-3), ("fuller", 4e-3)]
    resolution = [{**r["params"], **r["result"]} for r in run_sweep(
        monotonic_case, [{"grading": g, "radius": radius, "seed": seed, "name": f"{g}{radius * 1e3:.1f}mm_seed{seed}"}
                         for g, radius in samples for seed in seeds],
        outdir / f"{NAME}_resolution", backend="serial")]
    coarse = next(r for r in resolution if r["grading"] == "lattice" and r["radius"] == 5e-3 and r["seed"] == 0)
    base = {"radius": 5e-3, "seed": 0, "P_max": coarse["P_max"], "steps_per_cycle": 2000, "max_cycles": 1_000_000}

    jumps = (0.01,) if quick else (0.01, 0.003, 0.001)
    variants = ([(f"frozen_{j}", j, "frozen", 0) for j in jumps]
                + [(f"extrapolated_nosettle_{j}", j, "extrapolated", 0) for j in jumps[1:]]
                + [(f"extrapolated_{j}", j, "extrapolated", 1) for j in jumps + (() if quick else (0.0003,))]
                + [("reference", None, "frozen", 0)])
    jump_runs = [_measured({**r["params"], **r["result"]}) for r in run_sweep(
        fatigue_case, [{**base, "level": 0.77, "jump": jump, "plasticity": plasticity, "name": name,
                        "checkpoint": str(checkpoints / f"jump_{name}.pkl"), **({"settle": 1} if settle else {}),
                        **({"max_simulated": 200} if quick and jump is None else {})}
                       for name, jump, plasticity, settle in variants],
        outdir / f"{NAME}_jump", backend="serial", paths=CHECKPOINT)]
    reference = jump_runs[-1]
    for run in jump_runs:
        run["life_error"] = _life_error(run, reference)
        run["curve_error"] = _curve_error(run, reference)

    levels = (0.95, 0.77) if quick else PAPER["levels"]
    frozen = [{**base, "time_limit": 300 if quick else 900, "level": level, "jump": 0.003, "name": f"level{level:.2f}"}
              for level in levels]
    extrapolated = [{**base, "level": level, "jump": 0.003, "plasticity": "extrapolated", "settle": 1,
                     "name": f"extrapolated_level{level:.2f}",
                     "checkpoint": str(checkpoints / f"sn_extrapolated_{level:.2f}.pkl")} for level in levels]
    sn = [_measured({**r["params"], **r["result"]})
          for r in run_sweep(fatigue_case, frozen + extrapolated, outdir / f"{NAME}_sn", backend="serial",
                             paths=CHECKPOINT)]
    lives = {plasticity: [s for s in sn if s.get("plasticity", "frozen") == plasticity and s["life"]]
             for plasticity in ("frozen", "extrapolated")}
    fits = {plasticity: fit for plasticity, failed in lives.items() if (fit := _log_linear(failed))}

    rockers = rocker_study(outdir, checkpoints, quick)

    columns = ("study", "grading", "radius", "seed", "level", "jump", "plasticity", "particles", "FS_max", "life",
               "life_error", "simulated_cycles", "seconds", "per_unit")
    writer = CurveWriter(outdir / f"{NAME}.csv", columns)
    for r in resolution:
        writer.write(study="monotonic", grading=r["grading"], radius=r["radius"], seed=r["seed"], level=1.0, jump=0.0,
                     plasticity="", particles=r["particles"], FS_max=r["FS_max"], life=0, life_error=0.0,
                     simulated_cycles=0, seconds=r["seconds"], per_unit=r["seconds_per_cycle"])
    for study, runs in (("jump", jump_runs), ("S-N", sn)):
        for r in runs:
            writer.write(study=study, grading="lattice", radius=5e-3, seed=0, level=r["level"], jump=r["jump"] or 0.0,
                         plasticity=r.get("plasticity", "frozen"), particles=coarse["particles"],
                         FS_max=coarse["FS_max"], life=r["life"] or 0,
                         life_error=r.get("life_error") if r.get("life_error") is not None else float("nan"),
                         simulated_cycles=r["simulated_cycles"], seconds=r["seconds"],
                         per_unit=r["seconds"] / max(r["simulated_cycles"], 1))
    for r in rockers["monotonic"]:
        writer.write(study="rockers monotonic", grading=r["grading"], radius=r["radius"], seed=r["seed"], level=1.0,
                     jump=0.0, plasticity="", particles=r["particles"], FS_max=r["FS_max"], life=0, life_error=0.0,
                     simulated_cycles=0, seconds=r["seconds"], per_unit=r["seconds_per_cycle"])
    for own in rockers["monotonic"] + rockers["calibrated"]:
        for r in _runs_of(own, rockers["sn"]):
            writer.write(study="rockers S-N", grading=r["grading"], radius=r["radius"], seed=r["seed"],
                         level=r["level"], jump=r["jump"], plasticity=r["plasticity"], particles=own["particles"],
                         FS_max=own["FS_max"], life=r["life"] or 0, life_error=float("nan"),
                         simulated_cycles=r["simulated_cycles"], seconds=r["seconds"],
                         per_unit=r["seconds"] / max(r["simulated_cycles"], 1))
    writer.close()
    plot_rockers(rockers, outdir / f"{NAME}_rockers.png")
    strip = lambda rows, drop: [{k: v for k, v in r.items() if k not in drop} for r in rows]
    result = {"resolution": strip(resolution, ("curve",)), "jump": jump_runs, "sn": sn, "sn_fit": fits,
              "rockers": rockers, "paper": PAPER, "quick": quick}
    write_json(outdir / f"{NAME}.json", result)

    fig, ax = plt.subplots(1, 3, figsize=(15, 4))
    for r in resolution:
        curve = r["curve"]
        ax[0].plot(np.asarray(curve["strain"]) * 1e3, np.asarray(curve["stress"]) / 1e3,
                   "-" if r["grading"] == "lattice" else "--",
                   label=f"{r['grading']} {r['radius'] * 1e3:.1f} mm, seed {r['seed']}")
    ax[0].set(xlabel="flexural strain [10⁻³]", ylabel="flexural stress [kPa]", title="monotonic (Eqs. 42, 43)")
    ax[0].legend(fontsize=6)
    for r in jump_runs:
        settle = " + settling" if r.get("settle") else ""
        label = "cycle by cycle" if r["jump"] is None else f"{r['plasticity']}{settle}, ΔD_jump = {r['jump']}"
        ax[1].plot(r["measured_at"], r["modulus_ratio"], "-" if r["jump"] is None else ".-", ms=3,
                   lw=2 if r["jump"] is None else 1, label=f"{label} (life {r['life']})")
    ax[1].axhline(0.5, color="grey", lw=0.5)
    ax[1].set(xlabel="cycle N in which E_f was measured", ylabel="E_f / E_f,0",
              title="77 % of FS_max: modulus degradation")
    ax[1].legend(fontsize=6)
    for plasticity, marker in (("frozen", "o"), ("extrapolated", "s")):
        failed = lives[plasticity]
        if not failed:
            continue
        ax[2].semilogx([s["life"] for s in failed], [100 * s["level"] for s in failed], marker,
                       label=f"ours, {plasticity}")
        if plasticity in fits:
            fit = fits[plasticity]
            n = np.logspace(np.log10(min(s["life"] for s in failed)), np.log10(max(s["life"] for s in failed)), 20)
            ax[2].semilogx(n, 100 * (fit["intercept"] + fit["slope_per_decade"] * np.log10(n)), "--", lw=0.8)
    ax[2].set(xlabel="fatigue life N_f", ylabel="stress level [% FS_max]", title="S–N (5 mm lattice, ΔD_jump 0.003)")
    ax[2].legend(fontsize=7)
    save_figure(fig, outdir / f"{NAME}.png")
    lines = [f"{r['grading']} {r['radius'] * 1e3:.1f} mm seed {r['seed']}: {r['particles']} particles, FS_max "
             f"{r['FS_max'] / 1e3:.1f} kPa, E_f0 {r['modulus'] / 1e9:.2f} GPa, {r['ms_per_step']:.2f} ms/step, "
             f"{r['seconds_per_cycle']:.2f} s/cycle" for r in resolution]
    lines += [f"77 %, {r['name']}: life {r['life']} ({r['stopped']}), deviation "
              f"{'-' if r['life_error'] is None else format(r['life_error'], '+.1%')}, E_f/E_f,0 within "
              f"{r['curve_error']:.1%}, {r['simulated_cycles']} simulated cycles" for r in jump_runs]
    lines += [f"S–N {r.get('plasticity', 'frozen')} {100 * r['level']:.0f} %: life {r['life']} ({r['stopped']}, "
              f"{r['simulated_cycles']} simulated)" for r in sn]
    result["summary"] = "\n".join(lines)
    return result


if __name__ == "__main__":
    command_line(main, __doc__)
