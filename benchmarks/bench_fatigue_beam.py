"""Four-point bending fatigue of the cemented DEM beam (seed 002, Sec. 5): strength and cost against resolution,
the cycle jump's effect on the fatigue life, and the S–N curve.

1. *Resolution*: monotonic tests at particle radii 5, 3.5 and 2.5 mm (two lattice seeds each): FS_max, the initial
   flexural modulus, particle and bond counts, wall time per step; and the wall time of one simulated cycle.
2. *Cycle jump*: the 5 mm beam at 77 % of its FS_max with ΔD_jump = 0.01, 0.003, 0.001: fatigue life (cycles to
   E_f/E_f,0 = 0.5), simulated cycles and wall time.
3. *S–N*: the 5 mm beam at 95, 92, 84, 81, 77 and 70 % of FS_max with ΔD_jump = 0.003 (the paper's), as a
   resumable sweep (``fatigue_beam_sn/``: a finished level is read back, not recomputed); a log-linear fit
   S = a + b log₁₀ N over the levels that reached their life.

    python benchmarks/bench_fatigue_beam.py [--quick] [--outdir DIR]

writes ``fatigue_beam.csv`` (one row per run, flushed as it goes), ``fatigue_beam.json`` and ``fatigue_beam.png``.
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from _common import command_line, save_figure

from abrakit.experiments.bending import BeamSpec, cyclic_bending, four_point_beam, monotonic_bending
from abrakit.experiments.sweeps import run_sweep
from abrakit.io import CurveWriter, write_json

NAME = "fatigue_beam"
PAPER = {"FS_max_kPa": 1336.4, "levels": (0.95, 0.92, 0.84, 0.81, 0.77, 0.70), "jump": 0.003}


def monotonic_case(params: dict) -> dict:
    spec = BeamSpec(radius=params["radius"], seed=params["seed"])
    beam = four_point_beam(spec)
    r = monotonic_bending(beam, record_every=200)
    k = int(np.argmax(r["load"]))
    early = r["load"] < 0.2 * r["load"][k]
    modulus = float(np.median(23 * r["load"][early] * spec.span**3
                              / (108 * r["deflection"][early] * spec.width * spec.height**3)))
    return {"particles": len(beam.sim.particles), "bonds": len(beam.sim.fatigue_bonds), "FS_max": r["FS_max"],
            "P_max": float(r["load"][k]), "modulus": modulus, "seconds": r["seconds"], "steps": r["steps"],
            "ms_per_step": 1e3 * r["seconds"] / r["steps"], "curve": {"stress": r["stress"], "strain": r["strain"]}}


def fatigue_case(params: dict) -> dict:
    spec = BeamSpec(radius=params["radius"], seed=params["seed"])
    beam = four_point_beam(spec, control="force")
    r = cyclic_bending(beam, params["level"] * params["P_max"], jump=params["jump"],
                       steps_per_cycle=params["steps_per_cycle"], max_cycles=params["max_cycles"],
                       time_limit=params.get("time_limit"), max_simulated=params.get("max_simulated"))
    return {"life": r["life"], "stopped": r["stopped"], "simulated_cycles": r["simulated_cycles"],
            "seconds": r["seconds"], "cycles": r["cycles"], "modulus_ratio": r["modulus"] / r["modulus"][0],
            "damaged": r["damaged"]}


def main(outdir: Path, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    radii = (5e-3,) if quick else (5e-3, 3.5e-3, 2.5e-3)
    seeds = (0,) if quick else (0, 1)
    columns = ("study", "radius", "seed", "level", "jump", "particles", "FS_max", "life", "simulated_cycles",
               "seconds", "per_unit")
    writer = CurveWriter(outdir / f"{NAME}.csv", columns)
    resolution = []
    for radius in radii:
        for seed in seeds:
            m = monotonic_case({"radius": radius, "seed": seed})
            beam = four_point_beam(BeamSpec(radius=radius, seed=seed), control="force")
            tic = time.perf_counter()
            cyclic_bending(beam, 0.5 * m["P_max"], steps_per_cycle=2000, max_simulated=2)
            m["seconds_per_cycle"] = (time.perf_counter() - tic) / 2
            resolution.append({"radius": radius, "seed": seed, **m})
            writer.write(study="monotonic", radius=radius, seed=seed, level=1.0, jump=0.0, particles=m["particles"],
                         FS_max=m["FS_max"], life=0, simulated_cycles=0, seconds=m["seconds"],
                         per_unit=m["seconds_per_cycle"])
    coarse = next(r for r in resolution if r["radius"] == 5e-3 and r["seed"] == 0)
    base = {"radius": 5e-3, "seed": 0, "P_max": coarse["P_max"], "steps_per_cycle": 2000, "max_cycles": 1_000_000,
            "time_limit": 300 if quick else 900}
    jumps = (0.01,) if quick else (0.01, 0.003, 0.001)
    jump_runs = []
    for jump in jumps:
        r = fatigue_case({**base, "level": 0.77, "jump": jump})
        jump_runs.append({"jump": jump, **r})
        writer.write(study="jump", radius=5e-3, seed=0, level=0.77, jump=jump, particles=coarse["particles"],
                     FS_max=coarse["FS_max"], life=r["life"] or 0, simulated_cycles=r["simulated_cycles"],
                     seconds=r["seconds"], per_unit=r["seconds"] / r["simulated_cycles"])
    levels = (0.95, 0.77) if quick else PAPER["levels"]
    sweep = run_sweep(fatigue_case, [{**base, "level": level, "jump": 0.003, "name": f"level{level:.2f}"}
                                     for level in levels], outdir / f"{NAME}_sn", backend="serial")
    sn = []
    for record in sweep:
        r, level = record["result"], record["params"]["level"]
        sn.append({"level": level, **r})
        writer.write(study="S-N", radius=5e-3, seed=0, level=level, jump=0.003, particles=coarse["particles"],
                     FS_max=coarse["FS_max"], life=r["life"] or 0, simulated_cycles=r["simulated_cycles"],
                     seconds=r["seconds"], per_unit=r["seconds"] / max(r["simulated_cycles"], 1))
    writer.close()
    failed = [s for s in sn if s["life"]]
    fit = None
    if len(failed) >= 2:
        slope, intercept = np.polyfit(np.log10([s["life"] for s in failed]), [s["level"] for s in failed], 1)
        fit = {"intercept": float(intercept), "slope_per_decade": float(slope)}
    strip = lambda rows, drop: [{k: v for k, v in r.items() if k not in drop} for r in rows]
    result = {"resolution": strip(resolution, ("curve",)), "jump": strip(jump_runs, ()), "sn": strip(sn, ()),
              "sn_fit": fit, "paper": PAPER, "quick": quick}
    write_json(outdir / f"{NAME}.json", result)

    fig, ax = plt.subplots(1, 3, figsize=(15, 4))
    for r in resolution:
        curve = r["curve"]
        ax[0].plot(np.asarray(curve["strain"]) * 1e3, np.asarray(curve["stress"]) / 1e3,
                   label=f"r = {r['radius'] * 1e3:.1f} mm, seed {r['seed']}")
    ax[0].set(xlabel="flexural strain [10⁻³]", ylabel="flexural stress [kPa]", title="monotonic (Eqs. 42, 43)")
    ax[0].legend(fontsize=7)
    for r in jump_runs:
        ax[1].plot(r["cycles"], r["modulus_ratio"], ".-", ms=3, label=f"ΔD_jump = {r['jump']} (life {r['life']})")
    ax[1].axhline(0.5, color="grey", lw=0.5)
    ax[1].set(xlabel="cycles N", ylabel="E_f / E_f,0", title="77 % of FS_max: modulus degradation")
    ax[1].legend(fontsize=7)
    ax[2].semilogx([s["life"] for s in failed], [100 * s["level"] for s in failed], "o", label="ours (5 mm beam)")
    if fit:
        n = np.logspace(np.log10(min(s["life"] for s in failed)), np.log10(max(s["life"] for s in failed)), 20)
        ax[2].semilogx(n, 100 * (fit["intercept"] + fit["slope_per_decade"] * np.log10(n)), "--", label="log fit")
    ax[2].set(xlabel="fatigue life N_f", ylabel="stress level [% FS_max]", title="S–N")
    ax[2].legend(fontsize=7)
    save_figure(fig, outdir / f"{NAME}.png")
    lines = [f"r = {r['radius'] * 1e3:.1f} mm seed {r['seed']}: {r['particles']} particles, FS_max "
             f"{r['FS_max'] / 1e3:.1f} kPa, E_f0 {r['modulus'] / 1e9:.2f} GPa, {r['ms_per_step']:.2f} ms/step, "
             f"{r['seconds_per_cycle']:.2f} s/cycle" for r in resolution]
    lines += [f"77 %, ΔD_jump = {r['jump']}: life {r['life']} in {r['simulated_cycles']} simulated cycles, "
              f"{r['seconds']:.0f} s" for r in jump_runs]
    lines += [f"S–N {100 * s['level']:.0f} %: life {s['life']} ({s['stopped']}, {s['simulated_cycles']} simulated)"
              for s in sn]
    result["summary"] = "\n".join(lines)
    return result


if __name__ == "__main__":
    command_line(main, __doc__)
