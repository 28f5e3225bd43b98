"""Benchmark: the 6 × 6 stiffness of the identification specimens in a periodic cell, the dynamic probe against the
exact network response and Eq. (5.20), over particle count and K^n/K^t, beside the walled tests.

Each packing (genesis without walls, consolidation to 1 MPa by straining the cell;
:func:`abrakit.experiments.periodic_cell.periodic_elastic_cases`) is made once and probed for K^n/K^t = 1, 2.5
(Table 5.4) and 4 at the material's friction 0.5:

- the dynamic probe (six strains of the cell, relaxed), E and ν of its isotropic projection, its anisotropy;
- the exact static linear response of the contact network, C = (A − Bᵀ H⁻¹ B)/V (:mod:`abrakit.dem.network`);
- the probe as it was before the tangential springs were shifted with the cell (positions only), to show what the
  fix changed;
- Eq. (5.20) in its published, consistent and affine forms with the cell's own contact density.

The amplitude study measures the probe's speed against its error: one packing (300 spheres, seed 0, K^n/K^t = 1)
at μ = 0.5 and μ = 10, probed with strains from 10⁻⁵ to 10⁻⁹ and two relaxation tolerances, against the exact
response: a large strain opens contacts and lets them slide, a small one measures the tangent stiffness.

The "issue scene" adds the packing on which the missing springs were found: 2000 spheres of radii 0.8–1.2 mm,
K^n = K^t, μ = 10 (nothing slides), p = 0.3 MPa. The walled compression tests of ``bench_experiments_elastic.py``
are read from its stored ``experiments_elastic.csv``. Rows are written as they finish and reused by a later call
(an interrupted run loses nothing).

    python benchmarks/bench_dem_periodic.py [--quick] [--outdir DIR]

writes ``dem_periodic.csv``, ``dem_periodic.json`` (means per N and K^n/K^t beside the walled means) and
``dem_periodic.png`` (E and ν against N; wall time and probe error against N; error against wall time over
the probe's strain).
"""

from __future__ import annotations

import csv
import time
from pathlib import Path

from _common import RESULTS, command_line, save_figure

from abrakit.experiments.closed_form_checks import mean_interval
from abrakit.experiments.periodic_cell import periodic_elastic_cases
from abrakit.identification import VARIANTS
from abrakit.io import CurveWriter, write_json

NAME = "dem_periodic"
RATIOS = (1.0, 2.5, 4.0)
FULL = {"sizes": (300, 600, 1200), "seeds": (0, 1, 2), "ratios": RATIOS, "issue_scene": True,
        "amplitudes": (1e-5, 1e-6, 1e-7, 1e-8, 1e-9)}
QUICK = {"sizes": (300,), "seeds": (0, 1), "ratios": (1.0, 4.0), "issue_scene": False, "amplitudes": (1e-6, 1e-8)}
ISSUE_SCENE = {"n_particles": 2000, "seed": 0, "radius_min": 0.8e-3, "size_ratio": 1.5, "stress": 0.3e6,
               "friction": 10.0}
SCENES = {"identification": {}, "issue": ISSUE_SCENE}
COLUMNS = ("scene", "n_particles", "seed", "stiffness_ratio", "friction", "E", "nu", "C11", "C12", "C44",
           "anisotropy", "C11_spread", "E_exact", "nu_exact", "anisotropy_exact", "E_positions_only",
           "nu_positions_only", "pressure", "porosity", "coordination", "rho_c",
           *(f"E_pred_{v}" for v in VARIANTS), *(f"nu_pred_{v}" for v in VARIANTS), "probe_seconds",
           "exact_seconds", "seconds")
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


def cases(plan: dict):
    """(scene, params, ratios) of the plan, in the order they run."""
    for n in plan["sizes"]:
        for seed in plan["seeds"]:
            yield "identification", {"n_particles": n, "seed": seed}, plan["ratios"]
    if plan["issue_scene"]:
        yield "issue", ISSUE_SCENE, (1.0,)


def summary(rows: list[dict]) -> dict:
    """Means and 95 % intervals of one group of rows (one scene, N and K^n/K^t)."""
    out = {q: mean_interval([r[q] for r in rows]) for q in (
        "E", "nu", "E_exact", "nu_exact", "E_positions_only", "nu_positions_only", "anisotropy", "porosity",
        "coordination", "rho_c", "C11_spread", "probe_seconds", "exact_seconds", "seconds")}
    out["error_E"] = mean_interval([r["E"] / r["E_exact"] - 1.0 for r in rows])
    out["error_nu"] = mean_interval([r["nu"] - r["nu_exact"] for r in rows])
    for v in VARIANTS:
        out[f"ratio_E_{v}"] = mean_interval([r["E"] / r[f"E_pred_{v}"] for r in rows])
        out[f"nu_pred_{v}"] = mean_interval([r[f"nu_pred_{v}"] for r in rows])
        out[f"diff_nu_{v}"] = mean_interval([r["nu"] - r[f"nu_pred_{v}"] for r in rows])
    return out


def amplitude_study(amplitudes) -> list[dict]:
    """Probe error against the exact response and wall time, over the probe's strain and tolerance."""
    from abrakit.dem import elastic_probe, relax
    from abrakit.dem.network import network_stiffness
    from abrakit.experiments.periodic_cell import periodic_genesis
    from abrakit.experiments.specimen import SpecimenSpec

    sim = periodic_genesis(SpecimenSpec(n_particles=300, seed=0))
    genesis = sim.snapshot()
    rows = []
    for friction in (0.5, 10.0):
        sim.restore(genesis)
        sim.particles.kt[:] = sim.particles.kn
        sim.particles.friction[:] = friction
        sim.refresh()
        relax(sim, tolerance=1e-7, min_steps=0, max_steps=40_000, check_every=100)
        exact = network_stiffness(sim)
        for strain in amplitudes:
            for tol in (1e-6, 1e-8):
                tic = time.perf_counter()
                probe = elastic_probe(sim, strain=strain, tol=tol, max_steps=40_000)
                rows.append({"friction": friction, "strain": strain, "tol": tol,
                             "seconds": time.perf_counter() - tic, "error_E": probe.E / exact.E - 1.0,
                             "error_nu": probe.nu - exact.nu})
                print(f"[amplitude] mu = {friction:g}, strain {strain:.0e}, tol {tol:.0e}: E error "
                      f"{rows[-1]['error_E']:+.2e}, nu error {rows[-1]['error_nu']:+.2e}, "
                      f"{rows[-1]['seconds']:.1f} s", flush=True)
    return rows


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    plan = QUICK if quick else FULL
    path = outdir / f"{NAME}.csv"
    done = {}
    if path.exists():
        with open(path, newline="") as fh:
            for old in csv.DictReader(fh):
                if set(old) != set(COLUMNS):             # rows of an earlier layout are run again
                    break
                row = {c: (old[c] if c == "scene" else float(old[c])) for c in COLUMNS}
                done[(row["scene"], int(row["n_particles"]), int(row["seed"]), row["stiffness_ratio"])] = row
    tic = time.perf_counter()
    with CurveWriter(path, COLUMNS) as writer:
        for row in done.values():
            writer.write(**row)
        for scene, params, ratios in cases(plan):
            n, seed = params["n_particles"], params["seed"]
            if all((scene, n, seed, float(r)) in done for r in ratios):
                continue
            for out in periodic_elastic_cases({**params, "positions_only": True}, ratios):
                row = {"scene": scene, **{c: out[c] for c in COLUMNS if c != "scene"}}
                done[(scene, n, seed, out["stiffness_ratio"])] = row
                writer.write(**row)
                print(f"[periodic {scene}] N = {n} seed {seed} Kn/Kt = {out['stiffness_ratio']:g}: "
                      f"E = {out['E'] / 1e9:.2f} GPa (exact {out['E_exact'] / 1e9:.2f}, positions only "
                      f"{out['E_positions_only'] / 1e9:.2f}), nu = {out['nu']:.3f} (exact {out['nu_exact']:.3f}, "
                      f"positions only {out['nu_positions_only']:.3f}), probe {out['probe_seconds']:.1f} s, "
                      f"exact {out['exact_seconds']:.2f} s", flush=True)
    groups = {}
    for (scene, n, _, ratio), row in done.items():
        groups.setdefault(scene, {}).setdefault(f"{n}", {}).setdefault(f"{ratio:g}", []).append(row)
    results = {scene: {n: {r: summary(rows) for r, rows in by_ratio.items()} for n, by_ratio in by_n.items()}
               for scene, by_n in groups.items()}
    amplitude_path = outdir / f"{NAME}_amplitude.json"
    amplitude = None
    if amplitude_path.exists():
        from abrakit.io import read_json

        amplitude = read_json(amplitude_path)
    if amplitude is None or {r["strain"] for r in amplitude} != set(plan["amplitudes"]):
        amplitude = amplitude_study(plan["amplitudes"])
        write_json(amplitude_path, amplitude)
    data = {"quick": quick, "periodic": results.get("identification", {}), "issue_scene": results.get("issue", {}),
            "amplitude": amplitude, "walled": walled(outdir), "wall_time_s": time.perf_counter() - tic,
            "date": time.strftime("%Y-%m-%d %H:%M")}
    write_json(outdir / f"{NAME}.json", data)
    plot(data, outdir / f"{NAME}.png")
    return data


def series(per: dict, ratio: str, key: str, scale: float = 1.0, field: str = "mean"):
    """Particle counts with results at ``ratio`` and the ``field`` of ``key`` there (times ``scale``)."""
    sizes = [m for m in sorted(per, key=int) if ratio in per[m]]
    return [int(m) for m in sizes], [per[m][ratio][key][field] * scale for m in sizes]


def plot(data: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 5, figsize=(25, 4.5))
    per, wal = data["periodic"], data["walled"]
    ratios = sorted({r for n in per for r in per[n]}, key=float)
    colours = dict(zip(ratios, ("C0", "C1", "C2", "C3"), strict=False))
    for k, q in enumerate(("E", "nu")):
        scale = 1e-9 if q == "E" else 1.0
        for r in ratios:
            n, mean = series(per, r, q, scale)
            ax[k].errorbar(n, mean, series(per, r, q, scale, "half_width")[1], fmt="s-", color=colours[r],
                           capsize=3, label=f"probe, Kn/Kt = {r}")
            ax[k].plot(*series(per, r, f"{q}_exact", scale), "x", color=colours[r], ms=9,
                       label=f"exact network, Kn/Kt = {r}")
            ax[k].plot(*series(per, r, f"{q}_positions_only", scale), "v:", color=colours[r],
                       label="positions-only jump (before)")
        if wal:
            m = sorted(wal)
            ax[k].errorbar(m, [wal[x][f"{q}_wall"]["mean"] * scale for x in m],
                           [wal[x][f"{q}_wall"]["half_width"] * scale for x in m], fmt="ko--", capsize=3,
                           label="walled, wall scheme (Kn/Kt = 2.5)")
        ax[k].set(xscale="log", xlabel="particles N", ylabel="E [GPa]" if q == "E" else "ν",
                  title=f"{q} of granular specimens (95 % intervals)")
        ax[k].legend(fontsize=6, ncol=2)
    for r in ratios:
        ax[2].plot(*series(per, r, "probe_seconds"), "s-", color=colours[r], label=f"dynamic probe, Kn/Kt = {r}")
        ax[2].plot(*series(per, r, "exact_seconds"), "x--", color=colours[r], label=f"exact network, Kn/Kt = {r}")
        n, error_E = series(per, r, "error_E")
        ax[3].plot(n, [max(abs(e), 1e-7) for e in error_E], "s-", color=colours[r],
                   label=f"|E/E_exact − 1|, Kn/Kt = {r}")
        n, error_nu = series(per, r, "error_nu")
        ax[3].plot(n, [max(abs(e), 1e-7) for e in error_nu], "o:", color=colours[r],
                   label=f"|ν − ν_exact|, Kn/Kt = {r}")
    ax[2].set(xscale="log", yscale="log", xlabel="particles N", ylabel="wall time per 6 × 6 stiffness [s]",
              title="cost")
    ax[3].set(xscale="log", yscale="log", xlabel="particles N", ylabel="probe against exact response",
              title="error of the probe (strain 1e-8, μ = 0.5)")
    for friction, colour in ((0.5, "C0"), (10.0, "C1")):
        for tol, style in ((1e-6, "o-"), (1e-8, "s--")):
            sel = [r for r in data["amplitude"] if r["friction"] == friction and r["tol"] == tol]
            ax[4].plot([r["seconds"] for r in sel], [max(abs(r["error_E"]), 1e-7) for r in sel], style,
                       color=colour, label=f"μ = {friction:g}, tol {tol:.0e}")
            for r in sel:
                ax[4].annotate(f"{r['strain']:.0e}", (r["seconds"], max(abs(r["error_E"]), 1e-7)), fontsize=6)
    ax[4].set(xscale="log", yscale="log", xlabel="wall time per 6 × 6 stiffness [s]",
              ylabel="|E_probe / E_exact − 1|", title="probe strain: speed against error (N = 300, Kn = Kt)")
    for a in ax[2:]:
        a.legend(fontsize=7)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="N = 300, two seeds, Kn/Kt = 1 and 4")
