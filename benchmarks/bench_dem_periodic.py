"""Benchmark: E and ν of the identification specimens in a periodic cell, beside the walled tests and Eq. (5.20).

The walled compression tests of ``bench_experiments_elastic.py`` (study ``size``: granular specimens, N = 300 …
2400 spheres, seeds 0–4; E by the wall, specimen and sphere schemes of Fig. 5.2) are read from its stored
``experiments_elastic.csv``. The same specimen specifications are made again in a periodic cube
(:func:`abrakit.experiments.periodic_cell.periodic_elastic_case`: genesis without walls, consolidation to 1 MPa
by straining the cell, the elastic probe), and Eq. (5.20) is evaluated with the cell's own contact density.
Rows are written as they finish and reused by a later call (an interrupted run loses nothing).

    python benchmarks/bench_dem_periodic.py [--quick] [--outdir DIR]

writes ``dem_periodic.csv``, ``dem_periodic.json`` (means per N beside the walled means) and ``dem_periodic.png``.
"""

from __future__ import annotations

import csv
import time
from pathlib import Path

from _common import RESULTS, command_line, save_figure

from abrakit.experiments.closed_form_checks import mean_interval
from abrakit.experiments.periodic_cell import periodic_elastic_case
from abrakit.identification import VARIANTS
from abrakit.io import CurveWriter, read_curve, write_json

NAME = "dem_periodic"
FULL = {"sizes": (300, 600, 1200), "seeds": (0, 1, 2)}
QUICK = {"sizes": (300,), "seeds": (0, 1)}
COLUMNS = ("n_particles", "seed", "E", "nu", "C11", "C12", "C11_spread", "pressure", "porosity", "coordination",
           "rho_c", *(f"E_pred_{v}" for v in VARIANTS), *(f"nu_pred_{v}" for v in VARIANTS), "seconds")
WALL_SCHEMES = ("wall", "specimen", "sphere")


def walled(outdir: Path) -> dict:
    """Walled granular E and ν per N from ``experiments_elastic.csv`` (empty if that benchmark has not run)."""
    path = outdir / "experiments_elastic.csv"
    if not path.exists():
        return {}
    with open(path, newline="") as fh:
        rows = [r for r in csv.DictReader(fh) if r["study"] == "size" and r["bonded"] == "False"]
    out = {}
    for n in sorted({int(r["n_particles"]) for r in rows}):
        sel = [r for r in rows if int(r["n_particles"]) == n]
        out[n] = {f"{q}_{s}": mean_interval([float(r[f"{q}_{s}"]) for r in sel])
                  for q in ("E", "nu") for s in WALL_SCHEMES}
        for q in ("rho_c", "coordination"):
            out[n][q] = mean_interval([float(r[q]) for r in sel])
    return out


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    plan = QUICK if quick else FULL
    path = outdir / f"{NAME}.csv"
    done = {}
    if path.exists():
        old = read_curve(path)
        for k in range(len(old["seed"])):
            done[(int(old["n_particles"][k]), int(old["seed"][k]))] = {c: float(old[c][k]) for c in COLUMNS}
    tic = time.perf_counter()
    with CurveWriter(path, COLUMNS) as writer:
        for row in done.values():
            writer.write(**row)
        for n in plan["sizes"]:
            for seed in plan["seeds"]:
                if (n, seed) in done:
                    continue
                out = periodic_elastic_case({"n_particles": n, "seed": seed})
                done[(n, seed)] = {c: out[c] for c in COLUMNS}
                writer.write(**done[(n, seed)])
                print(f"[periodic] N = {n} seed {seed}: E = {out['E'] / 1e9:.2f} GPa, nu = {out['nu']:.3f}, "
                      f"porosity {out['porosity']:.3f}, Z = {out['coordination']:.2f}, {out['seconds']:.0f} s",
                      flush=True)
    periodic = {}
    for n in plan["sizes"]:
        rows = [r for (m, _), r in done.items() if m == n]
        periodic[n] = {q: mean_interval([r[q] for r in rows]) for q in ("E", "nu", "porosity", "coordination",
                                                                        "rho_c", "C11_spread", "seconds")}
        for v in VARIANTS:
            periodic[n][f"ratio_E_{v}"] = mean_interval([r["E"] / r[f"E_pred_{v}"] for r in rows])
            periodic[n][f"ratio_nu_{v}"] = mean_interval([r["nu"] / r[f"nu_pred_{v}"] for r in rows])
    data = {"quick": quick, "periodic": periodic, "walled": walled(outdir), "wall_time_s": time.perf_counter() - tic,
            "date": time.strftime("%Y-%m-%d %H:%M")}
    write_json(outdir / f"{NAME}.json", data)
    plot(data, outdir / f"{NAME}.png")
    return data


def plot(data: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    per, wal = data["periodic"], data["walled"]
    for k, q in enumerate(("E", "nu")):
        scale = 1e-9 if q == "E" else 1.0
        n = sorted(per)
        ax[k].errorbar(n, [per[m][q]["mean"] * scale for m in n], [per[m][q]["half_width"] * scale for m in n],
                       fmt="ks-", capsize=3, label="periodic cell (probe)")
        for s, style in zip(WALL_SCHEMES, ("o--", "^--", "v--"), strict=True):
            m = sorted(wal)
            if m:
                ax[k].errorbar(m, [wal[x][f"{q}_{s}"]["mean"] * scale for x in m],
                               [wal[x][f"{q}_{s}"]["half_width"] * scale for x in m], fmt=style, capsize=3,
                               label=f"walled, {s} scheme")
        ax[k].set(xscale="log", xlabel="particles N", ylabel="E [GPa]" if q == "E" else "ν",
                  title=f"{q} of granular specimens (95 % intervals)")
        ax[k].legend(fontsize=8)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="N = 300, two seeds")
