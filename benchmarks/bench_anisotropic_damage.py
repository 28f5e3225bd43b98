"""Benchmark: seed 001's anisotropic softening damage, speed against error on three problems with a reference.

1. **Crack-band bar** (:class:`abrakit.damage.CrackBandBar`, E = 1000 MPa, sigma_c = 1 MPa, G_Ic = 0.1 N/mm, the
   middle element 5 % weaker): the energy dissipated to separation against G_Ic A, for n = 1 … 256 elements
   (displacement steps of 0.5 %), and for n = 64 against the load step (4 % … 0.25 %): CPU time, error of the
   work, of the material's dissipation and of the peak.
2. **Double cantilever beam** (:class:`abrakit.damage.crack_band.DoubleCantileverBeam`: half model, arm 10 mm,
   pre-crack 30 mm, E = 3000 MPa, nu = 0.3, G_Ic = 0.5 N/mm): the propagation force against LEFM, P(delta) from beam
   theory with the crack lengthened by 0.64 h (Kanninen), which the elastic finite element compliance confirms to
   0.2 % (``lefm_check``). Element sizes 1 … 0.125 mm at sigma_c = 30 MPa (characteristic length E G/sigma² =
   1.67 mm) and sigma_c = 60 MPa (0.42 mm), path-followed by dissipation: mean and largest excess of the force over
   LEFM on the propagation branch (delta from 0.8 to 2 mm), CPU time.
3. **Mesh objectivity on Chapter 7 specimens** (double notch and sharp notch, plane strain × 3 mm, Table 7.1
   elasticity, sigma_c = 120, tau_c = 80 MPa, G_Ic = 10, G_IIc = 20 N/mm): the three mesh levels, path-followed;
   peak force, the energy dissipated when the force has fallen to half the peak, wall time; spreads over the
   meshes, for the comparison chapter beside Model I and II.
4. **Every failure surface against runtime** (sharp notch on the 250, 500 and 1000 element meshes of
   ``bench_damage.py``'s stored Model I and II study): the deviation of the peak and of the dissipated energy from
   the finest mesh of the same surface, against wall time; and the cost per step beside Model I and Model II on the
   same specimen and meshes (read from ``damage.json``).

Every case is written to ``anisotropic_damage_cases/`` as it finishes (:func:`abrakit.experiments.run_sweep`), so
an interrupted run resumes where it stopped.

    python benchmarks/bench_anisotropic_damage.py [--quick] [--outdir DIR]

writes ``anisotropic_damage.csv``, ``anisotropic_damage.json`` and ``anisotropic_damage.png``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure

from abrakit.damage import CrackBandBar, metrics, run_specimen, specimen
from abrakit.damage.crack_band import DoubleCantileverBeam
from abrakit.experiments import run_sweep
from abrakit.fem import PathControl, StepControl
from abrakit.io import CurveWriter, read_json, write_json

NAME = "anisotropic_damage"
BAR_SIZES, QUICK_BAR_SIZES = (1, 4, 16, 64, 256), (1, 8, 64)
BAR_STEPS, QUICK_BAR_STEPS = (0.04, 0.02, 0.01, 0.005, 0.0025), (0.02, 0.005)
DCB = ((30.0, 1.0), (30.0, 0.5), (30.0, 0.25), (30.0, 0.125), (60.0, 0.25), (60.0, 0.125))
QUICK_DCB = ((30.0, 1.0), (30.0, 0.5))
SPECIMENS, QUICK_SPECIMENS = (("double_notched", ("coarse", "medium", "fine")),
                              ("sharp_notch", ("coarse", "medium", "fine"))), (("sharp_notch", (300, 1000)),)
SURFACE_LEVELS, QUICK_SURFACE_LEVELS = (250, 500, 1000), (250, 500)
TOUGHNESS = 10.0
PROPAGATION = (0.8, 2.0)          # the DCB's arm deflections (mm) over which the force is compared with LEFM
COLUMNS = ("study", "case", "size", "elements", "steps", "cutbacks", "cpu_seconds", "error_pct", "max_error_pct",
           "peak", "dissipated", "status")


def bar_case(p: dict) -> dict:
    bar = CrackBandBar(p["n"])
    solver = bar.solver(follow=False, control=StepControl(initial=p["step"], maximum=p["step"]))
    dissipated = [0.0]
    tic = time.process_time()
    result = solver.run(progress=False, on_step=lambda r: dissipated.append(
        float(np.sum(solver.material.dissipation(r.state) * solver.kin.dx))))
    seconds = time.process_time() - tic
    v, F = result.curves["u_right"], result.curves["F_right"]
    work = metrics.work(v, F)
    return {"elements": p["n"], "steps": len(v) - 1, "cutbacks": result.cutbacks, "cpu_seconds": seconds,
            "error_pct": 100 * (work / bar.fracture_energy - 1.0),
            "max_error_pct": 100 * (dissipated[-1] / bar.fracture_energy - 1.0),
            "peak": float(F.max()) / bar.strength, "dissipated": dissipated[-1], "status": "separated"}


def dcb_case(p: dict) -> dict:
    dcb = DoubleCantileverBeam(sigma_c=p["sigma_c"], element=p["element"])
    solver = dcb.solver(PROPAGATION[1] + 0.2, path=PathControl(initial=0.02, maximum=0.02,
                                                               dissipation=0.25 * dcb.G_Ic))
    tic = time.process_time()
    result = solver.run(progress=False)
    seconds = time.process_time() - tic
    delta, force = result.curves["u_load"], result.curves["F_load"]
    branch = (np.arange(len(force)) > np.argmax(force)) & (delta >= PROPAGATION[0]) & (delta <= PROPAGATION[1])
    excess = force[branch] / dcb.beam_theory(delta[branch]) - 1.0
    return {"elements": int(solver.kin.nel), "steps": len(delta) - 1, "cutbacks": result.cutbacks,
            "cpu_seconds": seconds, "error_pct": 100 * float(np.mean(excess)),
            "max_error_pct": 100 * float(np.max(np.abs(excess))), "peak": float(force.max()),
            "dissipated": float("nan"), "status": "propagated",
            "curve": [delta.tolist(), force.tolist()]}


def specimen_case(p: dict) -> dict:
    sp = specimen(p["specimen"], p["level"])
    run = run_specimen(sp, "anisotropic", TOUGHNESS, stop_fraction=0.1,
                       material_options={"surface": p["surface"]} if "surface" in p else None)
    peak = int(np.argmax(run.F))
    # the energy dissipated at half the peak is read from the stored curve in main(), for every case alike
    return {"elements": sp.elements, "steps": run.steps, "cutbacks": run.cutbacks, "cpu_seconds": run.seconds,
            "error_pct": float("nan"), "max_error_pct": float("nan"), "peak": float(run.F[peak]),
            "status": run.status, "lowest_force_fraction": float(run.F[peak:].min() / run.F[peak]),
            "seconds_per_step": run.seconds / max(run.steps, 1),
            "curve": [run.u.tolist(), run.F.tolist(), run.dissipated.tolist()]}


def at_first_drop(F, values, fraction: float) -> float:
    """``values`` where the force first falls to ``fraction`` of its peak after the peak (linear between the two
    steps around the crossing), NaN if it never does. The force may rise again later (a locked band)."""
    F, values = np.asarray(F, dtype=float), np.asarray(values, dtype=float)
    peak = int(np.argmax(F))
    below = np.flatnonzero(F[peak:] <= fraction * F[peak])
    if below.size == 0:
        return float("nan")
    i = peak + int(below[0])
    s = (F[i - 1] - fraction * F[peak]) / (F[i - 1] - F[i])
    return float(values[i - 1] + s * (values[i] - values[i - 1]))


CASES = {"bar": bar_case, "bar_steps": bar_case, "dcb": dcb_case, "specimen": specimen_case,
         "surface": specimen_case}


def case(p: dict) -> dict:
    return CASES[p["study"]](p)


def plan(quick: bool) -> list[dict]:
    cases = [{"study": "bar", "n": n, "step": 0.005} for n in (QUICK_BAR_SIZES if quick else BAR_SIZES)]
    cases += [{"study": "bar_steps", "n": 64, "step": s} for s in (QUICK_BAR_STEPS if quick else BAR_STEPS)]
    cases += [{"study": "dcb", "sigma_c": s, "element": e} for s, e in (QUICK_DCB if quick else DCB)]
    cases += [{"study": "specimen", "specimen": name, "level": level}
              for name, levels in (QUICK_SPECIMENS if quick else SPECIMENS) for level in levels]
    cases += [{"study": "surface", "specimen": "sharp_notch", "level": level, "surface": surface}
              for surface in range(4) for level in (QUICK_SURFACE_LEVELS if quick else SURFACE_LEVELS)]
    return cases


def label(p: dict) -> tuple[str, float]:
    if p["study"] in ("bar", "bar_steps"):
        return f"n = {p['n']}, step {p['step']:g}", p["n"] if p["study"] == "bar" else p["step"]
    if p["study"] == "dcb":
        return f"sigma_c = {p['sigma_c']:g} MPa, h = {p['element']:g} mm", p["element"]
    if p["study"] == "surface":
        return f"{p['specimen']} {p['level']} surface {p['surface']}", float(p["surface"])
    return f"{p['specimen']} {p['level']}", 0.0


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    cases = plan(quick)
    records = run_sweep(case, cases, outdir / f"{NAME}_cases", backend="serial")
    rows, curves = [], {}
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for p, record in zip(cases, records, strict=True):
            result = dict(record["result"])
            name, size = label(p)
            curve = result.pop("curve", None)
            if curve is not None:
                curves[name] = curve
            if p["study"] in ("specimen", "surface"):       # energy dissipated when F first falls to half the peak
                result["dissipated"] = at_first_drop(curve[1], curve[2], 0.5)
            row = {"study": p["study"], "case": name, "size": size, **{k: result[k] for k in COLUMNS[3:]}}
            rows.append({**row, **{k: v for k, v in result.items() if k not in row}})
            writer.write(**row)
            print(f"[{NAME}] {p['study']:9s} {name:40s} {row['cpu_seconds']:7.1f} s  error {row['error_pct']:.3g} % "
                  f"(max {row['max_error_pct']:.3g} %)  peak {row['peak']:.5g}  dissipated {row['dissipated']:.4g}",
                  flush=True)
    dcb = DoubleCantileverBeam(element=0.25 if not quick else 0.5)
    delta, force = dcb.lefm_curve(np.linspace(30.0, 70.0, 9))
    lefm_check = float(np.max(np.abs(force / dcb.beam_theory(delta) - 1.0)))
    spreads = {}
    for name in {r["case"].split()[0] for r in rows if r["study"] == "specimen"}:
        group = [r for r in rows if r["study"] == "specimen" and r["case"].startswith(name + " ")]
        peaks = np.array([r["peak"] for r in group])
        energy = np.array([r["dissipated"] for r in group])
        spreads[name] = {"peak_spread_pct": 100 * float(np.ptp(peaks) / peaks.mean()),
                         "dissipated_spread_pct": 100 * float(np.ptp(energy) / np.mean(energy)),
                         "peaks_kN": (peaks / 1000).tolist(), "dissipated_Nmm": energy.tolist(),
                         "elements": [r["elements"] for r in group], "status": [r["status"] for r in group],
                         "lowest_force_fraction": [r["lowest_force_fraction"] for r in group]}
    surfaces = surface_study(rows, outdir)
    data = {"rows": rows, "curves": curves, "quick": quick, "date": time.strftime("%Y-%m-%d %H:%M"),
            "lefm_check_pct": 100 * lefm_check, "objectivity": spreads, "surfaces": surfaces,
            "summary": "; ".join([f"bar G error {max(abs(r['error_pct']) for r in rows if r['study'] == 'bar'):.2g} %"]
                                 + [f"DCB {r['case']}: {r['error_pct']:.2g} % above LEFM"
                                    for r in rows if r["study"] == "dcb"]
                                 + [f"{k}: peaks spread {v['peak_spread_pct']:.2g} %, dissipation at half the peak "
                                    f"{v['dissipated_spread_pct']:.2g} %" for k, v in spreads.items()])}
    write_json(outdir / f"{NAME}.json", data)
    plot(rows, curves, outdir / f"{NAME}.png")
    return data


def surface_study(rows, outdir: Path) -> dict:
    """Per surface: the deviation of peak and dissipation from its finest mesh, and the wall time, per mesh; the
    cost per step beside Model I and II on the same meshes (their stored ``damage.json``, if present)."""
    study = [r for r in rows if r["study"] == "surface"]
    stored = Path(outdir) / "damage.json"
    others = read_json(stored)["cases"] if stored.exists() else {}
    out = {}
    for surface in sorted({int(r["size"]) for r in study}):
        group = sorted((r for r in study if int(r["size"]) == surface), key=lambda r: r["elements"])
        finest = group[-1]
        out[str(surface)] = [{"elements": r["elements"], "seconds": r["cpu_seconds"],
                              "seconds_per_step": r["seconds_per_step"], "status": r["status"],
                              "peak_error_pct": 100 * (r["peak"] / finest["peak"] - 1),
                              "dissipated_error_pct": 100 * (r["dissipated"] / finest["dissipated"] - 1)}
                             for r in group]
    levels = sorted({r["case"].split()[1] for r in study}, key=int)
    cost = {}
    for level in levels:
        cost[level] = {"anisotropic (ovoid)": next((r["seconds_per_step"] for r in study
                                                    if r["case"].split()[1] == level and int(r["size"]) == 2), None)}
        for model in ("I", "II"):
            for strength in ("weak", "strong"):
                run = others.get(f"sharp_notch/{model}/{strength}", {}).get("runs", {}).get(f"{level}@0.002")
                cost[level][f"Model {model} ({strength})"] = None if run is None else run["seconds_per_step"]
    return {"by_surface": out, "seconds_per_step": cost}


def plot(rows, curves, path):
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 4, figsize=(21, 4.6))
    ax = axes[0]
    steps = sorted((r for r in rows if r["study"] == "bar_steps"), key=lambda r: r["cpu_seconds"])
    sizes = sorted((r for r in rows if r["study"] == "bar"), key=lambda r: r["size"])
    ax.loglog([r["cpu_seconds"] for r in steps], [max(abs(r["max_error_pct"]), 1e-6) for r in steps], "o-",
              label="n = 64: dissipation error over the load step")
    ax.loglog([r["cpu_seconds"] for r in sizes], [max(abs(r["max_error_pct"]), 1e-6) for r in sizes], "s--",
              label="n = 1 … 256 at 0.5 % steps")
    ax.set(xlabel="CPU time (s)", ylabel="|dissipated / G_Ic A − 1| (%)", title="crack-band bar")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    bx = axes[1]
    dcb = DoubleCantileverBeam()
    d = np.linspace(0.4, PROPAGATION[1] + 0.2, 200)
    bx.plot(d, dcb.beam_theory(d), "k-", lw=3, alpha=0.3, label="LEFM (beam theory, a + 0.64 h)")
    for r in rows:
        if r["study"] == "dcb" and r["case"] in curves:
            bx.plot(*curves[r["case"]], lw=1, label=f"{r['case']}: {r['error_pct']:.1f} %")
    bx.set(xlabel="arm deflection δ (mm)", ylabel="force P (N per mm)", title="DCB: damage against LEFM",
           ylim=(0, 14))
    bx.legend(fontsize=7)
    cx = axes[2]
    for k, r in enumerate(r for r in rows if r["study"] == "specimen"):
        u, F, _ = curves[r["case"]]
        cx.plot(u, np.asarray(F) / 1000, color=f"C{k}", label=f"{r['case']} ({r['elements']} el.)")
    cx.set(xlabel="u (mm)", ylabel="F (kN)", xlim=(0.0, 0.6),
           title=f"Ch. 7 specimens, G_Ic = {TOUGHNESS:g} N/mm (locked bands run on beyond)")
    cx.legend(fontsize=7)
    dx = axes[3]
    study = [r for r in rows if r["study"] == "surface"]
    for surface in sorted({int(r["size"]) for r in study}):
        group = sorted((r for r in study if int(r["size"]) == surface), key=lambda r: r["elements"])
        finest = group[-1]
        dx.loglog([r["cpu_seconds"] for r in group[:-1]],
                  [max(abs(r["dissipated"] / finest["dissipated"] - 1), 1e-5) * 100 for r in group[:-1]], "o-",
                  label=f"surface {surface}: dissipation")
        dx.loglog([r["cpu_seconds"] for r in group[:-1]],
                  [max(abs(r["peak"] / finest["peak"] - 1), 1e-5) * 100 for r in group[:-1]], "x--",
                  color=dx.lines[-1].get_color(), label=f"surface {surface}: peak")
    dx.set(xlabel="wall time (s)", ylabel="deviation from the finest mesh (%)",
           title="sharp notch, every failure surface")
    dx.grid(True, which="both", alpha=0.3)
    dx.legend(fontsize=7)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__)
