"""Speed against error of the cycle jump (seed 002, Eqs. 40, 41), and the paper's sensitivity numbers beside ours.

Three studies:

1. *Single bond*, pure tension, 20–60 kPa cycles from D = 0.01 to 0.4 (Table 1): wall time, simulated cycles and
   the damage error against the cycle-by-cycle run, over ΔD_jump = 0, 0.001, 0.003, 0.005, 0.01.
2. *Small bonded specimen* (:func:`abrakit.dem.fatigue_specimen.bonded_bar`, 10 disks, 17 bonds, hexagonal,
   25–75 kPa nominal, to a largest D of 0.3): the same sweep, with the error of the largest and the mean damage
   against the cycle-by-cycle DEM run interpolated at the same cycle; cost per simulated cycle; the engine's
   ``kernel="numba"`` against NumPy on the cycle-by-cycle run.
3. *Sensitivity* (Fig. 11): cycles from D = 0.01 to 0.4 for m = 0.8, 1.0, 1.2 and C = 0.5, 1.0, 1.5·10⁻⁸, with the
   printed 20–60 kPa range and with a 0–60 kPa range, beside the paper's 2008 and 50; and the cycle-jump reduction
   (the paper's measure, 100 × full / simulated cycles on the 0–60 kPa cycle: `jump_reduction_percent`) beside its
   388.8 % and 797.4 %.

    python benchmarks/bench_fatigue.py [--quick] [--outdir DIR]

writes ``fatigue.csv`` (one row per study and ΔD_jump, flushed as it goes), ``fatigue.json`` and ``fatigue.png``.
"""

from __future__ import annotations

import importlib.util
import time
from pathlib import Path

import matplotlib.pyplot as plt
from _common import command_line, save_figure

from abrakit.dem.fatigue_specimen import bonded_bar, cyclic_bar, history_deviation
from abrakit.fatigue import BondParameters, cyclic_test
from abrakit.fatigue.single_bond import jump_reduction_percent
from abrakit.io import CurveWriter, write_json

NAME = "fatigue"
JUMPS = (0.0, 0.001, 0.003, 0.005, 0.01)
PAPER = {"cycles m=0.8": 2008, "cycles m=1.2": 50, "jump reduction 0.005 [%]": 388.8,
         "jump reduction 0.01 [%]": 797.4}


def single_bond(writer, jumps):
    rows, reference = [], None
    for jump in jumps:
        tic = time.perf_counter()
        t = cyclic_test(BondParameters(), "tension", to_failure=False, jump=jump or None)
        seconds = time.perf_counter() - tic
        run = {"cycles": t.cycles, "damage": t.cycle_damage}
        reference = reference or run
        row = {"study": "single bond", "jump": jump, "simulated_cycles": t.simulated_cycles, "cycles": t.cycles[-1],
               "seconds": seconds, "seconds_per_cycle": seconds / t.simulated_cycles,
               "error_max_damage": history_deviation(run, reference, "damage", start=0.01),
               "error_mean_damage": float("nan")}
        writer.write(**row)
        rows.append(row | {"history": (t.cycles, t.cycle_damage)})
    return rows


def specimen(writer, jumps, *, target, ramp_steps, kernel="numpy"):
    rows, reference = [], None
    for jump in jumps:
        sim, _, loaded = bonded_bar(BondParameters())
        sim.kernel = kernel
        r = cyclic_bar(sim, loaded, 25e3, 75e3, target_damage=target, jump=jump or None, ramp_steps=ramp_steps)
        reference = reference or r
        row = {"study": f"specimen ({kernel})", "jump": jump, "simulated_cycles": r["simulated_cycles"],
               "cycles": int(r["cycles"][-1]), "seconds": r["seconds"],
               "seconds_per_cycle": r["seconds"] / r["simulated_cycles"],
               "error_max_damage": history_deviation(r, reference, "max_damage", start=0.01),
               "error_mean_damage": history_deviation(r, reference, "mean_damage", start=0.01)}
        writer.write(**row)
        rows.append(row | {"history": (r["cycles"], r["max_damage"])})
    return rows


def sensitivity():
    table = []
    base = BondParameters()
    for name, change in (("m", "paris_exponent"), ("C", "paris_coefficient")):
        values = (0.8, 1.0, 1.2) if name == "m" else (0.5e-8, 1.0e-8, 1.5e-8)
        for value in values:
            p = base.replace(**{change: value})
            printed = cyclic_test(p, "tension", to_failure=False).cycles[-1]
            peak = cyclic_test(p, "tension", stress_min=0.0, to_failure=False).cycles[-1]
            paper = {0.8: 2008, 1.2: 50}.get(value) if name == "m" else None
            table.append({"parameter": name, "value": value, "ours (20-60 kPa range)": printed,
                          "ours (0-60 kPa range)": peak, "paper": paper})
    return table


def main(outdir: Path, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    columns = ("study", "jump", "simulated_cycles", "cycles", "seconds", "seconds_per_cycle", "error_max_damage",
               "error_mean_damage")
    jumps = (0.0, 0.005, 0.01) if quick else JUMPS
    with CurveWriter(outdir / f"{NAME}.csv", columns) as writer:
        bond = single_bond(writer, jumps)
        target, ramp = (0.05, 100) if quick else (0.3, 200)
        bar = specimen(writer, jumps, target=target, ramp_steps=ramp)
        compiled = []
        if importlib.util.find_spec("numba") is not None:
            compiled = specimen(writer, (0.0,), target=target, ramp_steps=ramp, kernel="numba")
    table = sensitivity()
    reductions = {jump: jump_reduction_percent(BondParameters(), jump) for jump in (0.005, 0.01)}   # the paper's
    strip = lambda rows: [{k: v for k, v in r.items() if k != "history"} for r in rows]
    result = {"single_bond": strip(bond), "specimen": strip(bar), "specimen_numba": strip(compiled),
              "sensitivity": table, "jump_reduction_percent": reductions, "paper": PAPER, "quick": quick}
    write_json(outdir / f"{NAME}.json", result)

    fig, ax = plt.subplots(1, 3, figsize=(14, 4))
    for rows, axis, label in ((bond, ax[0], "single bond"), (bar, ax[1], "bonded specimen (largest D)")):
        for r in rows:
            axis.plot(*r["history"], ".-" if r["jump"] else "-", ms=3, label=f"ΔD_jump = {r['jump']}")
        axis.set(xlabel="cycles N", ylabel="damage D", title=label)
        axis.legend(fontsize=8)
    for rows, marker, label in ((bond, "o", "single bond"), (bar, "s", "specimen")):
        jumped = [r for r in rows if r["jump"]]
        ax[2].loglog([r["seconds"] for r in jumped], [max(r["error_max_damage"], 1e-16) for r in jumped],
                     marker + "-", label=label)
        for r in jumped:
            ax[2].annotate(str(r["jump"]), (r["seconds"], max(r["error_max_damage"], 1e-16)), fontsize=7)
    ax[2].set(xlabel="wall time [s]", ylabel="largest relative error of D(N)", title="cycle jump: speed vs error")
    ax[2].legend(fontsize=8)
    save_figure(fig, outdir / f"{NAME}.png")
    lines = [f"{r['study']:<18} ΔD_jump={r['jump']:<6} simulated {r['simulated_cycles']:>5} of {r['cycles']:>5} cycles"
             f"  {r['seconds']:8.2f} s  error {r['error_max_damage']:.2e}" for r in bond + bar + compiled]
    lines += [f"sensitivity {t['parameter']}={t['value']:g}: ours {t['ours (20-60 kPa range)']} (20-60 kPa), "
              f"{t['ours (0-60 kPa range)']} (0-60 kPa), paper {t['paper']}" for t in table]
    result["summary"] = "\n".join(lines)
    return result


if __name__ == "__main__":
    command_line(main, __doc__)
