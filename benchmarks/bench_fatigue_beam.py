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

Every case is a resumable sweep record (``fatigue_beam_resolution/``, ``fatigue_beam_jump/``, ``fatigue_beam_sn/``:
a finished case is read back, not recomputed), and the fatigue runs checkpoint every simulated cycle
(``fatigue_beam_checkpoints/``), so an interrupted study loses at most one cycle of each run.

    python benchmarks/bench_fatigue_beam.py [--quick] [--outdir DIR]

writes ``fatigue_beam.csv`` (one row per run), ``fatigue_beam.json`` and ``fatigue_beam.png``.
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from _common import command_line, save_figure

from abrakit.dem.fatigue_specimen import history_deviation
from abrakit.experiments.bending import (
    BeamSpec,
    cyclic_bending,
    flexural,
    four_point_beam,
    measured_cycles,
    monotonic_bending,
)
from abrakit.experiments.sweeps import run_sweep
from abrakit.io import CurveWriter, write_json

NAME = "fatigue_beam"
PAPER = {"FS_max_kPa": 1336.4, "levels": (0.95, 0.92, 0.84, 0.81, 0.77, 0.70), "jump": 0.003}


def _spec(params: dict) -> BeamSpec:
    return BeamSpec(radius=params["radius"], seed=params["seed"], grading=params.get("grading", "lattice"))


def monotonic_case(params: dict) -> dict:
    spec = _spec(params)
    beam = four_point_beam(spec)
    r = monotonic_bending(beam, record_every=200, drop=0.8)
    k = int(np.argmax(r["load"]))
    early = (np.arange(len(r["load"])) < k) & (r["load"] < 0.2 * r["load"][k]) & (r["deflection"] > 0)
    modulus = float(np.median(flexural(r["load"][early], r["deflection"][early], spec)["modulus"]))
    cyclic = four_point_beam(spec, control="force")
    tic = time.perf_counter()
    cyclic_bending(cyclic, 0.5 * float(r["load"][k]), steps_per_cycle=2000, max_simulated=2)
    return {"particles": len(beam.sim.particles), "bonds": len(beam.sim.fatigue_bonds), "FS_max": r["FS_max"],
            "P_max": float(r["load"][k]), "modulus": modulus, "seconds": r["seconds"], "steps": r["steps"],
            "ms_per_step": 1e3 * r["seconds"] / r["steps"], "seconds_per_cycle": (time.perf_counter() - tic) / 2,
            "time_step": beam.sim.dt, "curve": {"stress": r["stress"].tolist(), "strain": r["strain"].tolist()}}


def fatigue_case(params: dict) -> dict:
    beam = four_point_beam(_spec(params), control="force")
    checkpoint = params.get("checkpoint")
    r = cyclic_bending(beam, params["level"] * params["P_max"], jump=params["jump"],
                       plasticity=params.get("plasticity", "frozen"), settle=params.get("settle", 0),
                       steps_per_cycle=params["steps_per_cycle"],
                       max_cycles=params["max_cycles"], time_limit=params.get("time_limit"),
                       max_simulated=params.get("max_simulated"), checkpoint=checkpoint)
    return {"life": r["life"], "stopped": r["stopped"], "simulated_cycles": r["simulated_cycles"],
            "seconds": r["seconds"], "cycles": r["cycles"].tolist(), "measured_at": r["measured_at"].tolist(),
            "modulus_ratio": (r["modulus"] / r["modulus"][0]).tolist(), "damaged": r["damaged"].tolist(),
            "yielding": r["yielding"].tolist()}


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


def main(outdir: Path, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    checkpoints = outdir / f"{NAME}_checkpoints"
    checkpoints.mkdir(exist_ok=True)
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
        outdir / f"{NAME}_jump", backend="serial")]
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
          for r in run_sweep(fatigue_case, frozen + extrapolated, outdir / f"{NAME}_sn", backend="serial")]
    fits, lives = {}, {}
    for plasticity in ("frozen", "extrapolated"):
        failed = lives[plasticity] = [s for s in sn if s.get("plasticity", "frozen") == plasticity and s["life"]]
        if len(failed) >= 2:
            slope, intercept = np.polyfit(np.log10([s["life"] for s in failed]), [s["level"] for s in failed], 1)
            fits[plasticity] = {"intercept": float(intercept), "slope_per_decade": float(slope)}

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
    writer.close()
    strip = lambda rows, drop: [{k: v for k, v in r.items() if k not in drop} for r in rows]
    result = {"resolution": strip(resolution, ("curve",)), "jump": jump_runs, "sn": sn, "sn_fit": fits,
              "paper": PAPER, "quick": quick}
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
