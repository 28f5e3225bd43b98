"""Speed against error of the DEM compression tests (Ch. 5.3–5.4) and how far Eq. (5.20)/(5.26) hold.

Studies (each case one specimen and one test, run through :func:`abrakit.experiments.sweeps.run_sweep`, so an
interrupted run resumes; case files in ``<outdir>/experiments_elastic_cases/``):

- ``size``: E and ν by the three schemes (Fig. 5.2) for N = 300 … 2400 spheres × 5 seeds, granular and bonded
  (Table 5.2 used 277 … 16115 particles × 5 seeds); the error of E against the mean at the largest N, the
  runtime, and the ratios measured/predicted for the three variants of Eq. (5.20) with 95 % intervals;
- ``rate``: E at N = 300 and 1200 for loading windows of 10 … 80 elastic wave transits (the rate check);
- ``bond_gap``: bonded E and ν against the coordination number, bonds installed up to a gap of 0.001 … 0.05 r̄;
- ``bond_strength``: Table 5.3, failure stress against σ_y^Rankine and σ_y^Tresca (Eq. 5.26, Fig. 5.8);
- ``envelope``: triaxial peaks at four confinements, granular and bonded, Mohr–Coulomb fits (Fig. 5.3, 5.4);
- ``shape``: spheres against the Table 5.4 mixture (50 % peanuts, 25 % dyads, 25 % spheres) at 1 and 10 MPa.

Writes ``experiments_elastic.csv`` (one row per elastic case), ``.json`` (aggregates, with how and when they were
produced) and ``.png``. Specimens are cached by :func:`abrakit.experiments.specimen.genesis`.

Run: ``python benchmarks/bench_experiments_elastic.py [--quick] [--outdir DIR]`` (two worker processes).
"""

from __future__ import annotations

import os
import platform
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from _common import RESULTS, command_line, save_figure

from abrakit.experiments.closed_form_checks import (
    BOND_CASES,
    MIXTURE,
    bond_strength_case,
    elastic_case,
    envelope_case,
    mean_interval,
    mohr_coulomb_fit,
)
from abrakit.experiments.specimen import SpecimenSpec, genesis
from abrakit.experiments.sweeps import run_sweep
from abrakit.identification import VARIANTS
from abrakit.io import CurveWriter, write_json

VERSION = 2                       # bump to recompute the cases of a study after a change of the experiments
ELASTIC_VERSION = 3               # elastic studies: quiet start (unbalanced force ratio 1e-6) since version 3
SCHEMES = ("wall", "specimen", "sphere")
FULL = {"sizes": [300, 600, 1200, 2400], "seeds": [0, 1, 2, 3, 4], "rate_sizes": [300, 1200],
        "crossings": [10, 20, 40, 80], "gaps": [1e-3, 1e-2, 5e-2], "gap_size": 1200, "strength_size": 1200,
        "strength_seeds": [0, 1, 2], "envelope_size": 600, "envelope_seeds": [0, 1], "shape_size": 600}
QUICK = {"sizes": [200, 300], "seeds": [0, 1], "rate_sizes": [200], "crossings": [20, 40], "gaps": [1e-3, 5e-2],
         "gap_size": 200, "strength_size": 200, "strength_seeds": [0], "envelope_size": 200, "envelope_seeds": [0],
         "shape_size": 150}
GRANULAR_CONFINEMENTS = [0.5e6, 1e6, 2e6, 4e6]            # Pa (Chende sand: 0.1-0.7 MPa; Table 5.4: 1, 10 MPa)
BONDED_CONFINEMENTS = [0.0, 1e6, 5e6, 10e6]               # Pa (granite, Fig. 5.3: 0.1, 1, 10, 20 MPa)
TARGET = 100e6                                            # Pa, failure stress Eq. (5.26) is set to predict
COLUMNS = ["study", "n_particles", "seed", "bonded", "crossings", "bond_gap", "coordination", "rho_c",
           "rho_c_vessel", "kn", "kt", "radius", "strain_rate", "window_strain", "sliding", "seconds",
           *[f"{q}_{s}" for q in ("E", "nu") for s in SCHEMES],
           *[f"{q}_pred_{v}" for q in ("E", "nu") for v in VARIANTS]]


def _elastic_params(cfg):
    params = []
    for bonded in (False, True):               # granular first: two workers never make the same specimen at once
        for n in cfg["sizes"]:
            for seed in cfg["seeds"]:
                params.append({"study": "size", "n_particles": n, "seed": seed, "bonded": bonded})
    for n in cfg["rate_sizes"]:
        for crossings in cfg["crossings"]:
            for bonded in (False, True):
                params.append({"study": "rate", "n_particles": n, "seed": 0, "bonded": bonded,
                               "crossings": float(crossings)})
    for gap in cfg["gaps"]:
        for seed in cfg["seeds"][:3]:
            params.append({"study": "bond_gap", "n_particles": cfg["gap_size"], "seed": seed, "bonded": True,
                           "bond_gap": gap})
    return [{**p, "version": ELASTIC_VERSION} for p in params]


def _strength_params(cfg):
    params = [{"study": "bond_strength", "n_particles": cfg["strength_size"], "seed": seed, "case": case,
               "target_stress": TARGET} for seed in cfg["strength_seeds"] for case in BOND_CASES]
    return [{**p, "version": VERSION} for p in params]


def _envelope_params(cfg, bond_strength):
    params = []
    n = cfg["envelope_size"]
    for seed in cfg["envelope_seeds"]:
        params += [{"study": "envelope", "n_particles": n, "seed": seed, "bonded": False, "confinement": s3}
                   for s3 in GRANULAR_CONFINEMENTS]
        params += [{"study": "envelope", "n_particles": n, "seed": seed, "bonded": True, "confinement": s3,
                    "bond_strength": bond_strength} for s3 in BONDED_CONFINEMENTS]
    for shapes in ([1.0, 0.0, 0.0], list(MIXTURE)):
        for bonded in (False, True):
            for s3 in (1e6, 10e6):                                   # Ch. 5.4.2: 1 and 10 MPa
                p = {"study": "shape", "n_particles": cfg["shape_size"], "seed": 0, "bonded": bonded,
                     "confinement": s3, "shapes": shapes, "max_strain": 0.01}
                if bonded:
                    p["bond_strength"] = bond_strength
                params.append(p)
    return [{**p, "version": VERSION} for p in params]


def _results(records, finished=None):
    if finished is not None:
        finished.extend(r["finished"] for r in records)
    return [{**r["params"], **r["result"]} for r in records]


def _genesis_seconds(n, seed) -> float:
    """Wall time of the (cached) genesis of a specimen, as recorded when it was made."""
    return float(genesis(SpecimenSpec(n_particles=n, seed=seed)).info["seconds"])


def _aggregate_elastic(rows, sizes):
    size_rows = [r for r in rows if r["study"] == "size"]
    out = {}
    for bonded in (False, True):
        kind = "bonded" if bonded else "granular"
        mine = [r for r in size_rows if r["bonded"] == bonded]
        large = [r for r in mine if r["n_particles"] == max(sizes)]
        ref = {s: float(np.mean([r[f"E_{s}"] for r in large])) for s in SCHEMES}
        ref_nu = {s: float(np.mean([r[f"nu_{s}"] for r in large])) for s in SCHEMES}
        per_size = {}
        for n in sizes:
            at = [r for r in mine if r["n_particles"] == n]
            entry = {"seconds": mean_interval([r["seconds"] for r in at]),
                     "genesis_seconds": mean_interval([_genesis_seconds(n, r["seed"]) for r in at]),
                     "coordination": mean_interval([r["coordination"] for r in at]),
                     "porosity": mean_interval([r["porosity"] for r in at]),
                     "porosity_interior": mean_interval([r["porosity_interior"] for r in at])}
            for s in SCHEMES:
                E = np.array([r[f"E_{s}"] for r in at])
                entry[f"E_{s}"] = mean_interval(E)
                entry[f"nu_{s}"] = mean_interval([r[f"nu_{s}"] for r in at])
                entry[f"E_error_{s}"] = mean_interval(np.abs(E / ref[s] - 1.0))
                for v in VARIANTS:
                    entry[f"ratio_E_{s}_{v}"] = mean_interval([r[f"E_{s}"] / r[f"E_pred_{v}"] for r in at])
                    entry[f"ratio_nu_{s}_{v}"] = mean_interval([r[f"nu_{s}"] / r[f"nu_pred_{v}"] for r in at])
            for v in VARIANTS:
                entry[f"E_pred_{v}"] = mean_interval([r[f"E_pred_{v}"] for r in at])
                entry[f"nu_pred_{v}"] = mean_interval([r[f"nu_pred_{v}"] for r in at])
            per_size[str(n)] = entry
        out[kind] = {"large": {"n_particles": max(sizes), "E": ref, "nu": ref_nu, "seeds": len(large)},
                     "sizes": per_size}
    rate = {}
    for r in (r for r in rows if r["study"] == "rate"):
        rate.setdefault(f"{'bonded' if r['bonded'] else 'granular'}_{r['n_particles']}", []).append(
            {"crossings": r["crossings"], "E_wall": r["E_wall"], "nu_wall": r["nu_wall"],
             "strain_rate": r["strain_rate"], "seconds": r["seconds"]})
    for series in rate.values():
        series.sort(key=lambda e: e["crossings"])
        for e in series:
            e["E_change_to_slowest"] = e["E_wall"] / series[-1]["E_wall"] - 1.0
    gaps = {}
    for r in (r for r in rows if r["study"] == "bond_gap"):
        gaps.setdefault(str(r["bond_gap"]), []).append(r)
    gap_summary = {g: {"coordination": mean_interval([r["coordination"] for r in rs]),
                       **{f"ratio_E_{s}_{v}": mean_interval([r[f"E_{s}"] / r[f"E_pred_{v}"] for r in rs])
                          for s in ("wall", "sphere") for v in VARIANTS},
                       **{f"nu_{s}": mean_interval([r[f"nu_{s}"] for r in rs]) for s in ("wall", "sphere")}}
                   for g, rs in gaps.items()}
    return out, rate, gap_summary


def _aggregate_strength(rows):
    out = {}
    for case in BOND_CASES:
        at = [r for r in rows if r["case"] == case]
        entry = {"f_n/f_t": BOND_CASES[case][0] / BOND_CASES[case][1],
                 "tension_share": mean_interval([r["tension_share"] for r in at]),
                 "sigma_ci": mean_interval([r["sigma_ci"] for r in at])}
        for s in SCHEMES:
            entry[f"sigma_f_{s}"] = mean_interval([r[f"sigma_f_{s}"] for r in at])
            for v in ("published", "consistent"):
                governing = [min(r[f"rankine_{v}"], r[f"tresca_{v}"]) for r in at]
                entry[f"ratio_{s}_{v}"] = mean_interval([r[f"sigma_f_{s}"] / g for r, g in zip(at, governing,
                                                                                                strict=True)])
        for v in ("published", "consistent"):
            entry[f"rankine_{v}"] = mean_interval([r[f"rankine_{v}"] for r in at])
            entry[f"tresca_{v}"] = mean_interval([r[f"tresca_{v}"] for r in at])
        out[str(case)] = entry
    return out


def _aggregate_envelope(rows):
    out = {}
    for bonded in (False, True):
        kind = "bonded" if bonded else "granular"
        at = [r for r in rows if r["study"] == "envelope" and r["bonded"] == bonded]
        s3 = np.array([r["sigma3"] for r in at])
        s1 = np.array([r["sigma1"] for r in at])
        entry = {"sigma3": s3.tolist(), "sigma1": s1.tolist(), "seeds": sorted({r["seed"] for r in at})}
        entry["fit"] = mohr_coulomb_fit(s3, s1)
        if not bonded:
            entry["fit_cohesionless"] = mohr_coulomb_fit(s3, s1, cohesionless=True)
        out[kind] = entry
    shape = {}
    for r in (r for r in rows if r["study"] == "shape"):
        name = "spheres" if r["shapes"][0] == 1.0 else "mixture"
        shape[f"{name}_{'bonded' if r['bonded'] else 'granular'}_{r['sigma3'] / 1e6:g}MPa"] = {
            "sigma1": r["sigma1"], "eps_peak": r["eps_peak"], "seconds": r["seconds"]}
    return out, shape


def _errorbars(ax, elastic, sizes, prefix, names, colors):
    """Mean ± 95 % of ``<prefix><name>`` against the particle count, granular (solid) and bonded (dashed)."""
    for kind, marker in (("granular", "o"), ("bonded", "s")):
        for name, color in zip(names, colors, strict=True):
            e = [elastic[kind]["sizes"][str(n)][f"{prefix}{name}"] for n in sizes]
            ax.errorbar(sizes, [x["mean"] for x in e], yerr=[x["half_width"] for x in e], marker=marker,
                        color=color, ls="-" if kind == "granular" else "--", capsize=3, label=f"{kind}, {name}")


def _plot(path, elastic, rate, gaps, strength, sizes):
    fig, axes = plt.subplots(2, 2, figsize=(12, 8.5))
    ax = axes[0, 0]
    _errorbars(ax, elastic, sizes, "E_error_", SCHEMES, ("C0", "C1", "C2"))
    ax.set(xscale="log", xlabel="particles N", ylabel=f"|E/E(N={max(sizes)}) − 1|, mean ± 95 %",
           title="error of E against the large-N mean")
    twin = ax.twinx()
    twin.plot(sizes, [elastic["granular"]["sizes"][str(n)]["seconds"]["mean"] for n in sizes], "k:", marker="x",
              label="test")
    twin.plot(sizes, [elastic["granular"]["sizes"][str(n)]["genesis_seconds"]["mean"] for n in sizes], "k-.",
              marker="+", label="genesis")
    twin.set(ylabel="runtime [s]: test (dotted), genesis (dash-dot)", yscale="log")
    ax.legend(fontsize=7)
    ax = axes[0, 1]
    _errorbars(ax, elastic, sizes, "ratio_E_sphere_", VARIANTS, ("C3", "C4", "C5"))
    ax.axhline(1.0, color="grey", lw=0.8)
    ax.set(xscale="log", xlabel="particles N", ylabel="E measured (sphere) / Eq. (5.20)",
           title="measured / predicted Young's modulus")
    ax.legend(fontsize=7)
    ax = axes[1, 0]
    for key, series in sorted(rate.items()):
        ax.plot([e["crossings"] for e in series], [e["E_change_to_slowest"] * 100 for e in series], marker="o",
                label=key)
    ax.axhspan(-2, 2, color="grey", alpha=0.15, label="±2 %")
    ax.set(xscale="log", xlabel="wave transits over the elastic window", ylabel="E change to the slowest [%]",
           title="loading rate")
    ax.legend(fontsize=7)
    ax = axes[1, 1]
    cases = sorted(strength, key=int)
    x = np.arange(len(cases))
    for k, (s, color) in enumerate(zip(SCHEMES, ("C0", "C1", "C2"), strict=True)):
        ax.bar(x + (k - 1) * 0.2, [strength[c][f"sigma_f_{s}"]["mean"] / 1e6 for c in cases], 0.2,
               yerr=[strength[c][f"sigma_f_{s}"]["half_width"] / 1e6 for c in cases], color=color, label=s)
    for v, ls in (("published", "-"), ("consistent", "--")):
        for c in cases:
            k = int(c) - 1
            for crit, color in (("rankine", "C3"), ("tresca", "C4")):
                value = strength[c][f"{crit}_{v}"]["mean"] / 1e6
                if value < 1e3:                                  # the other criterion is 100 times higher
                    ax.hlines(value, k - 0.4, k + 0.4, colors=color, ls=ls)
    ax.set(xticks=x, xticklabels=[f"Test {c}" for c in cases], ylabel="peak σ1 − σ3 [MPa]",
           title="Table 5.3: DEM vs Eq. (5.26), Rankine red, Tresca purple;\npublished solid, consistent dashed")
    ax.legend(fontsize=7)
    save_figure(fig, path)


def main(outdir: Path = RESULTS, quick: bool = False, n_jobs: int | None = None) -> dict:
    outdir = Path(outdir)
    cfg = QUICK if quick else FULL
    name = "experiments_elastic" + ("_quick" if quick else "")
    cases_dir = outdir / f"{name}_cases"
    n_jobs = n_jobs or min(2, os.cpu_count() or 1)
    start = time.perf_counter()
    sweep = {"backend": "joblib", "n_jobs": n_jobs, "progress": True}

    finished = []
    elastic_rows = _results(run_sweep(elastic_case, _elastic_params(cfg), cases_dir, **sweep), finished)
    with CurveWriter(outdir / f"{name}.csv", COLUMNS) as writer:
        for r in elastic_rows:
            writer.write(**{c: r.get(c, np.nan) for c in COLUMNS})
    elastic, rate, gaps = _aggregate_elastic(elastic_rows, cfg["sizes"])

    strength_rows = _results(run_sweep(bond_strength_case, _strength_params(cfg), cases_dir, **sweep), finished)
    strength = _aggregate_strength(strength_rows)
    # one bond strength for the envelopes and the shape study: Eq. (5.26) with the seed-0 specimen's ρc r
    base = next(r for r in strength_rows if r["case"] == 1 and r["seed"] == cfg["strength_seeds"][0])
    bond_strength = round(TARGET / (base["rho_c"] * base["radius"]), 3)
    envelope_rows = _results(run_sweep(envelope_case, _envelope_params(cfg, bond_strength), cases_dir, **sweep),
                             finished)
    envelope, shape = _aggregate_envelope(envelope_rows)

    _plot(outdir / f"{name}.png", elastic, rate, gaps, strength, cfg["sizes"])
    seconds = time.perf_counter() - start
    summary = _summary(elastic, rate, strength, envelope, shape, cfg)
    result = {
        "produced": {"when": datetime.now(timezone.utc).isoformat(timespec="seconds"),
                     "cases_finished": [min(finished), max(finished)], "cases": len(finished),
                     "how": f"python benchmarks/bench_experiments_elastic.py{' --quick' if quick else ''} "
                            f"(joblib, {n_jobs} processes)",
                     "host": platform.node(), "python": sys.version.split()[0], "load_average":
                     list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
                     "wall_seconds_this_run": seconds, "version": [ELASTIC_VERSION, VERSION],
                     "case_seconds_total": float(sum(r["seconds"] for r in elastic_rows + strength_rows
                                                     + envelope_rows))},
        "config": cfg, "elastic": elastic, "rate": rate, "bond_gap": gaps, "bond_strength": strength,
        "bond_strength_force": bond_strength, "envelope": envelope, "shape": shape, "summary": summary,
    }
    write_json(outdir / f"{name}.json", result)
    return result


def _summary(elastic, rate, strength, envelope, shape, cfg) -> str:
    n = str(max(cfg["sizes"]))
    lines = [f"DEM compression tests, N = {cfg['sizes']} × {len(cfg['seeds'])} seeds"]
    for kind in ("granular", "bonded"):
        e = elastic[kind]["sizes"][n]
        for s in ("wall", "sphere"):
            parts = [f"{v} {e[f'ratio_E_{s}_{v}']['mean']:.2f}±{e[f'ratio_E_{s}_{v}']['half_width']:.2f}"
                     for v in VARIANTS]
            lines.append(f"{kind:8s} N={n} {s:6s}: E/pred " + ", ".join(parts)
                         + f"; ν = {e[f'nu_{s}']['mean']:.3f}±{e[f'nu_{s}']['half_width']:.3f}"
                         f" (pred {e['nu_pred_published']['mean']:.3f} / affine {e['nu_pred_affine']['mean']:.3f})")
    worst = max(abs(x["E_change_to_slowest"]) for series in rate.values() for x in series if x["crossings"] >= 20)
    lines.append(f"rate: |ΔE| ≤ {worst:.1%} for ≥ 20 wave transits over the window")
    for c, e in strength.items():
        lines.append(f"Table 5.3 Test {c}: σ_f (wall) = {e['sigma_f_wall']['mean'] / 1e6:.1f} MPa, "
                     f"/published {e['ratio_wall_published']['mean']:.2f}, /consistent "
                     f"{e['ratio_wall_consistent']['mean']:.2f}, tension share {e['tension_share']['mean']:.2f}")
    for kind, e in envelope.items():
        fit = e["fit"]
        lines.append(f"envelope {kind}: φ = {fit['friction_angle']:.1f}°, c = {fit['cohesion'] / 1e6:.2f} MPa")
    for key, e in sorted(shape.items()):
        lines.append(f"shape {key}: σ1 = {e['sigma1'] / 1e6:.2f} MPa")
    return "\n".join(lines)


if __name__ == "__main__":
    command_line(main, __doc__)
