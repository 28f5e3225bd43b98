"""Contacting particles (Ch. 8.3): N_c·D² against box size and diameter, and binary mixtures against Eq. (8.12).

Run: ``python benchmarks/bench_experiments_contacting.py [--quick]`` →
``benchmarks/results/experiments_contacting.{csv,json,png}``; every case is also kept as its own JSON file in
``benchmarks/results/experiments_contacting_cases/`` (:func:`abrakit.experiments.run_sweep`), so an interrupted run
resumes where it stopped and a second run only re-does the analysis.

Studies (beds of :func:`abrakit.experiments.contacting.pressed_bed`, frictionless as in the seed, p = 10 kPa,
overlap scale ε = 10⁻², bed weight = p L²/2, quartz density 2200 kg/m³):

- ``box``: one grain size in the seed's unit box (L = 1 m), D = L/6 … L/24, several seeds. By exact similarity
  this is also the box-size study at fixed D: N_c·D² in the interior window (wall zones of 1 D excluded) and on the
  whole floor, its error against the largest box, and the run time — speed against error;
- ``sensitivity``: L = 12 D with one parameter changed at a time: friction 0.3 (the seed says friction hardly
  matters), a shallower bed (3 layers, as in the mixtures), a stricter equilibrium (unbalanced-force ratio 10⁻⁵
  instead of 10⁻³);
- ``overlap``: L = 12 D, overlap scale ε = 10⁻² … 3·10⁻⁴ (stiffer grains), extrapolated to rigid grains;
- ``mixture``: r_AB = 1.5, 2, 3 and θ_A = 0.1 … 0.9 (0.25 … 0.9 for r_AB = 3, whose fine-rich beds are the
  costliest) in a box of 8 D_A with 3 layers of D_A, two seeds; the exponents α_A,
  α_B of Eq. (8.10) fitted by Poisson maximum likelihood (a held at our homogeneous value, and free), against
  Eq. (8.11).

The tolerance of the contact criterion and the width of the wall zones are varied on every case for free.
"""

from __future__ import annotations

import pathlib
import platform
import time
from datetime import datetime, timezone

import numpy as np
from _common import command_line, save_figure

from abrakit.experiments import run_sweep
from abrakit.experiments.closed_form_checks import mean_interval
from abrakit.experiments.contacting import (
    SEED_COEFFICIENT,
    contacting_case,
    fit_contact_coefficient,
    fit_mixture_exponent,
    seed_exponents,
)
from abrakit.io import CurveWriter, write_json

NAME = "experiments_contacting"
VERSION = 1                       # bump to invalidate the cached cases after a protocol change
BASE = {"pressure": 1e4, "overlap": 1e-2, "gravity_ratio": 0.5, "friction": 0.0, "density": 2200.0,
        "version": VERSION}
FULL = {
    "box_seeds": {6: (0, 1, 2), 8: (0, 1, 2), 12: (0, 1, 2), 16: (0, 1, 2), 24: (0, 1)}, "layers": 4,
    "sensitivity_size": 12, "sensitivity_seeds": (0, 1, 2),
    "sensitivity": {"friction 0.3": {"friction": 0.3}, "3 layers": {"layers": 3}, "balance 1e-5": {"balance": 1e-5}},
    "overlap_size": 12, "overlaps": (1e-2, 3e-3, 1e-3, 3e-4), "overlap_seeds": (0, 1, 2, 3),
    "thetas": {1.5: (0.1, 0.25, 0.5, 0.75, 0.9), 2.0: (0.1, 0.25, 0.5, 0.75, 0.9), 3.0: (0.25, 0.5, 0.75, 0.9)},
    "mixture_seeds": (0, 1), "mixture_box": 8, "mixture_layers": 3,
}
"""What the result files hold: sized for a shared two-core machine (≈ 30 CPU-minutes). More seeds or sizes only
add cases: the finished ones are read back from the case directory."""
QUICK = {
    "box_seeds": {6: (0, 1), 8: (0, 1)}, "layers": 3,
    "sensitivity_size": 6, "sensitivity_seeds": (0,), "sensitivity": {"friction 0.3": {"friction": 0.3}},
    "overlap_size": 6, "overlaps": (1e-2, 3e-3), "overlap_seeds": (0,),
    "thetas": {2.0: (0.25, 0.75)}, "mixture_seeds": (0,), "mixture_box": 5, "mixture_layers": 2,
}


def cases(plan) -> list[dict]:
    """All sweep cases of a plan: one grain size first, then the mixtures from r = 1.5 to 3 (so a run stopped
    early has finished the cheap, central studies)."""
    out = []
    for n, seeds in plan["box_seeds"].items():
        for seed in seeds:
            out.append({**BASE, "study": "box", "diameter": 1.0 / n, "box": 1.0, "layers": plan["layers"],
                        "seed": seed})
    n = plan["sensitivity_size"]
    for label, change in plan["sensitivity"].items():
        for seed in plan["sensitivity_seeds"]:
            out.append({**BASE, "study": "sensitivity", "variant": label, "diameter": 1.0 / n, "box": 1.0,
                        "layers": plan["layers"], "seed": seed, **change})
    n = plan["overlap_size"]
    for overlap in plan["overlaps"]:
        for seed in plan["overlap_seeds"]:
            out.append({**BASE, "study": "overlap", "diameter": 1.0 / n, "box": 1.0, "layers": plan["layers"],
                        "seed": seed, "overlap": overlap, "max_steps": 400_000})
    for ratio, thetas in plan["thetas"].items():
        for theta in thetas:
            for seed in plan["mixture_seeds"]:
                out.append({**BASE, "study": "mixture", "diameter": 1.0 / plan["mixture_box"], "box": 1.0,
                            "fine_diameter": 1.0 / (plan["mixture_box"] * ratio), "theta_coarse": theta,
                            "layers": plan["mixture_layers"], "seed": seed})
    return out


def rows_of(records) -> list[dict]:
    rows = []
    for rec in records:
        p, res = rec["params"], rec["result"]
        bed, census = res["bed"], res["census"]
        D = p["diameter"]
        rows.append({
            "study": p["study"], "variant": p.get("variant", ""), "L_over_D": round(p["box"] / D, 9),
            "ratio": round(D / p["fine_diameter"], 9) if "fine_diameter" in p else 1.0,
            "theta_coarse": p.get("theta_coarse", 1.0), "theta_actual": bed["theta_coarse_actual"],
            "seed": p["seed"], "friction": p["friction"], "overlap": p["overlap"], "layers": p["layers"],
            "gravity_ratio": p["gravity_ratio"], "particles": bed["coarse_grains"] + bed["fine_grains"],
            "steps": bed["steps"], "seconds": rec["seconds"], "converged": bed["converged"],
            "unbalanced": bed["unbalanced"], "solid_fraction": bed["solid_fraction"],
            "floor_overlap": bed["floor_overlap"], "window_area_D2": census["area"] / D**2,
            "count_all": census["all"]["count"], "N_c_D2_all": census["all"]["N_c_D2"],
            "count_coarse": census["coarse"]["count"], "N_c_D2_coarse": census["coarse"]["N_c_D2"],
            "count_fine": census["fine"]["count"], "N_c_D2_fine": census["fine"]["N_c_D2"],
            "N_c_D2_whole_floor": res["by_zone"]["0"]["all"]["N_c_D2"],
        })
    return rows


def interior_density(record, zone) -> float:
    """N_c D² of a one-size bed over the floor farther than ``zone`` diameters from every side wall, from its
    floor profile (bins of D/4, so ``zone`` must be a multiple of 1/4)."""
    profile, D, L = record["result"]["profile"], record["params"]["diameter"], record["params"]["box"]
    inner_edge = np.array(profile["distance"]) / D - 0.125          # bin centres → inner edges, in D
    count = np.array(profile["count"])[inner_edge >= zone - 1e-9].sum()
    return float(count / (L / D - 2 * zone) ** 2)


def box_study(records, plan) -> dict:
    sel = [r for r in records if r["params"]["study"] == "box"]
    sizes = sorted({round(r["params"]["box"] / r["params"]["diameter"], 9) for r in sel})
    table = []
    for n in sizes:
        here = [r for r in sel if round(r["params"]["box"] / r["params"]["diameter"], 9) == n]
        window = mean_interval([r["result"]["census"]["all"]["N_c_D2"] for r in here])
        whole = mean_interval([r["result"]["by_zone"]["0"]["all"]["N_c_D2"] for r in here])
        table.append({"L_over_D": n, "D_over_L": 1 / n, "window": window, "whole_floor": whole,
                      "count_mean": float(np.mean([r["result"]["census"]["all"]["count"] for r in here])),
                      "seconds_mean": float(np.mean([r["seconds"] for r in here])),
                      "particles": int(np.mean([r["result"]["bed"]["coarse_grains"] for r in here]))})
    reference = table[-1]["window"]["mean"]
    for row in table:
        row["error_vs_largest"] = abs(row["window"]["mean"] - reference) / reference
        row["whole_floor_error_vs_largest"] = abs(row["whole_floor"]["mean"] - reference) / reference
    D = np.array([r["params"]["diameter"] for r in sel])
    window_area = np.array([r["result"]["census"]["area"] for r in sel])
    N_window = np.array([r["result"]["census"]["all"]["count"] for r in sel]) / window_area
    N_whole = np.array([r["result"]["by_zone"]["0"]["all"]["count"] for r in sel]) / 1.0
    large = [r for r in sel if r["params"]["box"] / r["params"]["diameter"] >= 12 - 1e-9] or sel
    pooled = mean_interval([r["result"]["census"]["all"]["N_c_D2"] for r in large])
    tolerance = {t: mean_interval([r["result"]["by_tol"][t]["all"]["N_c_D2"] for r in large])
                 for t in large[0]["result"]["by_tol"]}
    zones = {z: mean_interval([r["result"]["by_zone"][z]["all"]["N_c_D2"] for r in large
                                    if z in r["result"]["by_zone"]]) for z in large[0]["result"]["by_zone"]}
    biggest = [r for r in sel if round(r["params"]["box"] / r["params"]["diameter"], 9) == sizes[-1]]
    profile = np.mean([r["result"]["profile"]["N_c"] for r in biggest], axis=0)
    D_big = biggest[0]["params"]["diameter"]
    zones_big = {f"{w:g}": mean_interval([interior_density(r, w) for r in biggest])
                 for w in np.arange(0.0, min(5.0, sizes[-1] / 2 - 1) + 0.25, 0.5)}
    return {"table": table, "fit_window": fit_contact_coefficient(D, N_window),
            "fit_whole_floor": fit_contact_coefficient(D, N_whole), "pooled_large_boxes": pooled,
            "large_box_threshold": 12, "by_tolerance": tolerance, "by_wall_zone": zones,
            "by_wall_zone_largest_box": zones_big,
            "profile": {"distance_D": (np.array(biggest[0]["result"]["profile"]["distance"]) / D_big).tolist(),
                        "N_c_D2": (profile * D_big**2).tolist(), "L_over_D": sizes[-1]}}


def sensitivity_study(records, plan, box) -> dict:
    n = plan["sensitivity_size"]
    baseline = [r["result"]["census"]["all"]["N_c_D2"] for r in records if r["params"]["study"] == "box"
                and round(r["params"]["box"] / r["params"]["diameter"], 9) == n
                and r["params"]["seed"] in plan["sensitivity_seeds"]]
    out = {"baseline": mean_interval(baseline)}
    for label in plan["sensitivity"]:
        values = [r["result"]["census"]["all"]["N_c_D2"] for r in records
                  if r["params"]["study"] == "sensitivity" and r["params"]["variant"] == label]
        stat = mean_interval(values)
        stat["change"] = stat["mean"] / out["baseline"]["mean"] - 1
        out[label] = stat
    return out


def overlap_study(records, plan) -> dict:
    """N_c D² against the overlap scale ε (stiffness k = 2pD/ε) and its rigid-grain limit ε → 0.

    The limit is extrapolated with N_c D² = N₀ + c ε^q: q fitted, and q = 1/2 and 1 held (the spread of the three
    N₀ is the systematic uncertainty of the extrapolation)."""
    from scipy.optimize import curve_fit

    sel = [r for r in records if r["params"]["study"] == "overlap"]
    eps = np.array([r["params"]["overlap"] for r in sel])
    value = np.array([r["result"]["census"]["all"]["N_c_D2"] for r in sel])
    table = []
    for e in plan["overlaps"]:
        here = [r for r in sel if r["params"]["overlap"] == e]
        table.append({"overlap": e, **mean_interval([r["result"]["census"]["all"]["N_c_D2"] for r in here]),
                      "steps_mean": float(np.mean([r["result"]["bed"]["steps"] for r in here])),
                      "seconds_mean": float(np.mean([r["seconds"] for r in here])),
                      "converged": int(sum(r["result"]["bed"]["converged"] for r in here)),
                      "floor_overlap_mean": float(np.mean([r["result"]["bed"]["floor_overlap"] for r in here]))})
    fits = {}
    for q in (0.5, 1.0):
        A = np.column_stack([np.ones_like(eps), eps**q])
        coef, *_ = np.linalg.lstsq(A, value, rcond=None)
        sigma2 = float(np.sum((value - A @ coef) ** 2) / max(len(value) - 2, 1))
        cov = sigma2 * np.linalg.inv(A.T @ A)
        fits[f"q={q:g}"] = {"N0": float(coef[0]), "N0_stderr": float(np.sqrt(cov[0, 0])), "c": float(coef[1]), "q": q}
    try:
        popt, pcov = curve_fit(lambda e, n0, c, q: n0 + c * e**q, eps, value, p0=(0.95, 1.0, 0.5),
                               bounds=((0.0, 0.0, 0.05), (2.0, 100.0, 2.0)))
        fits["q free"] = {"N0": float(popt[0]), "N0_stderr": float(np.sqrt(pcov[0, 0])), "c": float(popt[1]),
                          "q": float(popt[2]), "q_stderr": float(np.sqrt(pcov[2, 2]))}
    except (RuntimeError, TypeError, ValueError):                # too few points, or no convergence
        pass
    limits = [f["N0"] for f in fits.values()]
    return {"table": table, "fits": fits, "rigid_limit_low": float(min(limits)),
            "rigid_limit_high": float(max(limits)), "L_over_D": plan["overlap_size"]}


def mixture_study(records, plan, a_homogeneous) -> dict:
    out = {}
    for ratio, thetas in plan["thetas"].items():
        sel = [r for r in records if r["params"]["study"] == "mixture"
               and abs(r["params"]["diameter"] / r["params"]["fine_diameter"] - ratio) < 1e-9]
        alpha_A, alpha_B = seed_exponents(ratio)
        entry = {"ratio": ratio, "seed_alpha_coarse": alpha_A, "seed_alpha_fine": alpha_B, "table": []}
        for theta in thetas:
            here = [r for r in sel if r["params"]["theta_coarse"] == theta]
            entry["table"].append({
                "theta_coarse": theta,
                "theta_actual": float(np.mean([r["result"]["bed"]["theta_coarse_actual"] for r in here])),
                "coarse": mean_interval([r["result"]["census"]["coarse"]["N_c_D2"] for r in here]),
                "fine": mean_interval([r["result"]["census"]["fine"]["N_c_D2"] for r in here]),
                "seconds_mean": float(np.mean([r["seconds"] for r in here])),
                "particles": float(np.mean([r["result"]["bed"]["coarse_grains"] + r["result"]["bed"]["fine_grains"]
                                            for r in here]))})
        for kind in ("coarse", "fine"):
            theta = np.array([r["result"]["bed"]["theta_coarse_actual"] for r in sel])
            theta = theta if kind == "coarse" else 1 - theta
            count = np.array([r["result"]["census"][kind]["count"] for r in sel])
            area = np.array([r["result"]["census"]["area"] for r in sel])
            diameter = np.array([r["result"]["census"][kind]["diameter"] for r in sel])
            entry[f"fit_{kind}"] = fit_mixture_exponent(theta, count, area, diameter)
            entry[f"fit_{kind}_fixed_a"] = fit_mixture_exponent(theta, count, area, diameter, a=a_homogeneous)
            per_seed = []
            for seed in plan["mixture_seeds"]:
                m = np.array([r["params"]["seed"] == seed for r in sel])
                if count[m].sum() > 0 and np.ptp(theta[m]) > 0:
                    per_seed.append(fit_mixture_exponent(theta[m], count[m], area[m], diameter[m],
                                                         a=a_homogeneous)["alpha"])
            entry[f"alpha_{kind}_per_seed"] = per_seed
            entry[f"alpha_{kind}_seed_spread"] = float(np.std(per_seed, ddof=1)) if len(per_seed) > 1 else np.nan
        out[f"{ratio:g}"] = entry
    return out


def plot(result, path):
    import matplotlib.pyplot as plt

    box, mix = result["box"], result["mixture"]
    ratios = list(mix)
    fig, axes = plt.subplots(2, 4, figsize=(20, 8.5))
    a, b, c, d = axes[0]
    t = box["table"]
    n = np.array([r["L_over_D"] for r in t])
    for key, label, marker in (("window", "interior window (wall zones of 1 D excluded)", "o"),
                               ("whole_floor", "whole floor", "s")):
        a.errorbar(1 / n, [r[key]["mean"] for r in t], yerr=[r[key]["std"] for r in t], fmt=marker + "-",
                   capsize=3, label=label)
    a.axhline(SEED_COEFFICIENT, color="k", ls=":", label="seed, Eq. (8.7): 0.9")
    a.axhline(box["fit_window"]["a"], color="C0", lw=0.8, ls="--", label=f"fit: {box['fit_window']['a']:.3f}")
    a.set_xlabel("D / L (seed's axis; L = box edge)")
    a.set_ylabel("$N_c D^2$")
    a.set_title("one grain size: $N_c D^2$ (mean ± std over seeds)")
    a.legend(fontsize=7)
    secs = np.array([r["seconds_mean"] for r in t])[:-1]          # the largest box is the reference
    for key, label, marker in (("error_vs_largest", "interior window", "o"),
                               ("whole_floor_error_vs_largest", "whole floor", "s")):
        err = np.maximum([r[key] for r in t[:-1]], 1e-4)
        b.loglog(secs, err, marker + "-", label=label)
        for x, y, m in zip(secs, err, n[:-1], strict=True):
            b.annotate(f"L = {m:g} D", (x, y), fontsize=7)
    spread = t[-1]["window"]["std"] / t[-1]["window"]["mean"] / np.sqrt(t[-1]["window"]["n"])
    if np.isfinite(spread):
        b.axhline(spread, color="k", ls=":", lw=0.8, label="standard error of the reference")
    b.set_xlabel("run time per case [s]")
    b.set_ylabel(f"|N_c D² − value at L = {n[-1]:g} D| / value")
    b.set_title("speed against error: box size")
    b.legend(fontsize=7)
    prof = box["profile"]
    c.step(prof["distance_D"], prof["N_c_D2"], where="mid")
    c.axvspan(0, 1, color="0.85", label="wall zone (excluded)")
    c.axhline(box["pooled_large_boxes"]["mean"], color="C0", ls="--", lw=0.8, label="interior mean")
    c.set_xlabel("distance of the contact point from the nearest side wall [D]")
    c.set_ylabel("$N_c D^2$ in the band")
    c.set_title(f"floor density near the side walls (L = {prof['L_over_D']:g} D)")
    c.legend(fontsize=7)
    over = result["overlap"]
    eps = np.array([r["overlap"] for r in over["table"]])
    d.errorbar(eps, [r["mean"] for r in over["table"]], yerr=[np.nan_to_num(r["std"]) for r in over["table"]],
               fmt="o", capsize=3, label="DEM (mean ± std over seeds)")
    grid = np.geomspace(1e-5, eps.max(), 100)
    for (label, f), style in zip(over["fits"].items(), ("--", ":", "-."), strict=False):
        d.semilogx(grid, f["N0"] + f["c"] * grid ** f["q"], style, lw=1,
                   label=f"{label}: ε → 0 gives {f['N0']:.3f}")
    d.axhline(SEED_COEFFICIENT, color="k", lw=0.8, ls=":", label="seed 0.9")
    d.set_xlabel("overlap scale ε (contact stiffness 2pD/ε)")
    d.set_ylabel("$N_c D^2$")
    d.set_title(f"stiffer grains, L = {over['L_over_D']:g} D")
    d.legend(fontsize=7)
    sens = result["sensitivity"]
    labels = [k for k in sens if k != "baseline"]
    e = axes[1][3]
    e.barh(["baseline"] + labels, [sens["baseline"]["mean"]] + [sens[k]["mean"] for k in labels],
           xerr=[np.nan_to_num(sens["baseline"]["std"])] + [np.nan_to_num(sens[k]["std"]) for k in labels],
           color=["0.6"] + ["C0"] * len(labels))
    e.axvline(SEED_COEFFICIENT, color="k", ls=":", lw=0.8)
    e.set_xlim(0.7, 1.15)
    e.set_xlabel("$N_c D^2$")
    e.set_title("one change at a time (L = 12 D)")
    for ax, key in zip(axes[1][:3], ratios, strict=False):
        entry = mix[key]
        theta = np.array([r["theta_coarse"] for r in entry["table"]])
        grid = np.linspace(0.05, 1, 100)
        for kind, th, color in (("coarse", theta, "C0"), ("fine", 1 - theta, "C3")):
            mean = np.array([r[kind]["mean"] for r in entry["table"]])
            std = np.array([np.nan_to_num(r[kind]["std"]) for r in entry["table"]])
            ax.errorbar(th, np.maximum(mean, 1e-3), yerr=std, fmt="o", color=color, capsize=3,
                        label=f"{'A (coarse)' if kind == 'coarse' else 'B (fine)'}, DEM")
            fit = entry[f"fit_{kind}_fixed_a"]
            ax.loglog(grid, fit["a"] * grid ** fit["alpha"], "-", color=color, lw=1,
                      label=f"fit α = {fit['alpha']:.2f} ± {fit['alpha_stderr']:.2f}")
            alpha_seed = entry[f"seed_alpha_{kind}"]
            ax.loglog(grid, SEED_COEFFICIENT * grid**alpha_seed, ":", color=color,
                      label=f"Eq. (8.12): α = {alpha_seed:.2f}")
        ax.set_xlabel(r"volume fraction $\theta_i$ of the grain type")
        ax.set_ylabel(r"$N_{c,i} D_i^2$")
        ax.set_title(f"binary mixture, $r_{{AB}}$ = {float(key):g}")
        ax.legend(fontsize=6.5)
    for ax in axes[1][len(ratios):3]:
        ax.axis("off")
    save_figure(fig, path)


def main(outdir: pathlib.Path = pathlib.Path(__file__).parent / "results", quick: bool = False,
         n_jobs: int = 2) -> dict:
    outdir = pathlib.Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    plan = QUICK if quick else FULL
    start = time.perf_counter()
    records = run_sweep(contacting_case, cases(plan), outdir / f"{NAME}_cases", backend="joblib", n_jobs=n_jobs,
                        progress=True)
    rows = rows_of(records)
    with CurveWriter(outdir / f"{NAME}.csv", list(rows[0])) as out:
        for row in sorted(rows, key=lambda r: (r["study"], r["variant"], r["ratio"], r["theta_coarse"],
                                               r["L_over_D"], r["seed"])):
            out.write(**row)
    box = box_study(records, plan)
    a_ours = box["pooled_large_boxes"]["mean"]
    result = {
        "produced": {"date": datetime.now(timezone.utc).isoformat(timespec="seconds"), "host": platform.node(),
                     "mode": "quick" if quick else "full",
                     "command": f"python benchmarks/bench_{NAME}.py" + (" --quick" if quick else ""),
                     "cases": len(records), "case_cpu_seconds": float(sum(r["seconds"] for r in records)),
                     "wall_seconds_this_call": time.perf_counter() - start,
                     "resumed_cases": int(sum(r["resumed"] for r in records)),
                     "not_converged": int(sum(not r["result"]["bed"]["converged"] for r in records))},
        "protocol": {**{k: v for k, v in BASE.items() if k != "version"}, "box_edge_m": 1.0, "wall_zone_D": 1.0,
                     "tol_D": 1e-3, "plan": {k: v for k, v in plan.items() if k != "sensitivity"},
                     "sensitivity_variants": plan["sensitivity"]},
        "box": box,
        "sensitivity": sensitivity_study(records, plan, box),
        "overlap": overlap_study(records, plan),
        "mixture": mixture_study(records, plan, a_ours),
    }
    mix = result["mixture"]
    over = result["overlap"]
    result["summary"] = (
        f"N_c D^2 = {a_ours:.3f} ± {box['pooled_large_boxes']['half_width']:.3f} (95 % CI, L >= 12 D, "
        f"{box['pooled_large_boxes']['n']} beds, eps = 1e-2; rigid-grain limit {over['rigid_limit_low']:.3f}–"
        f"{over['rigid_limit_high']:.3f}; seed 0.9); free fit beta = {box['fit_window']['beta']:.3f}; "
        + "; ".join(f"r={k}: alpha_A = {v['fit_coarse_fixed_a']['alpha']:.2f}"
                    f"±{v['fit_coarse_fixed_a']['alpha_stderr']:.2f}"
                    f" (seed {v['seed_alpha_coarse']:.2f}), alpha_B = {v['fit_fine_fixed_a']['alpha']:.2f}"
                    f"±{v['fit_fine_fixed_a']['alpha_stderr']:.2f} (seed {v['seed_alpha_fine']:.2f})"
                    for k, v in mix.items()))
    write_json(outdir / f"{NAME}.json", result)
    plot(result, outdir / f"{NAME}.png")
    return result


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="two small boxes, one mixture, one seed (about a minute)")
