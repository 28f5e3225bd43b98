"""Speed against error of the regularised damage models on the three Ch. 7 specimens (Model I and Model II).

For every specimen (plate with a hole, double-notched strip, sharp notch), model (I: gradient-enhanced, beta;
II: ERVE, alpha) and regularisation (weak: beta = 0.1 MPa mm^2 / alpha = 0.05 1/(N mm); strong: beta = 1 /
alpha = 0.005), three meshes and two load-step sizes are run (``abrakit.damage.runs.run_specimen``; plane
strain, forces for the 3 mm plates, stop once the force has fallen below 10 % of its peak):

- full mode: meshes of about 1000, 4000 and 8000 elements (the seed's), steps of 0.002 and 0.004 mm;
- quick mode: meshes of about 250, 500 and 1000 elements, the same steps.

The reference of every (specimen, model, regularisation) is its finest mesh with the small step. Per run:
runtime, steps, Newton iterations, peak force and its error against the reference, the relative L2 distance of
the force–displacement curve from the reference (``abrakit.damage.metrics.curve_distance``), the work over the
common displacement range, the band width (stiffness loss >= 0.5; full width for bands on a symmetry line), the
number of separate damaged pieces (stiffness loss >= 0.9, at least 5 % of the damaged area) and the principal
angle of the largest one (0 degrees: horizontal, 90: vertical), the transition ratio (width at 0.1 / at 0.9), the
softening displacement (peak to half the peak force) and the largest alpha_p; all from
``abrakit.damage.metrics.specimen_metrics``. ``--reanalyse`` recomputes them from the stored runs.

    python benchmarks/bench_damage.py [--quick] [--outdir DIR] [--models I II] [--specimens ...]
                                      [--formulation plane_strain|extruded] [--control displacement|path]
                                      [--against DIR] [--reanalyse]

``--formulation extruded`` builds the specimens as the seed did, one hexahedron through the 3 mm plate (plane
stress in effect); the default is plane strain with the forces of the 3 mm plate. The stored extruded study is
in ``benchmarks/results/damage_extruded/``.

``--control path`` follows every path through its snap-back instead (one run per mesh, the step adapts): Model I by
its damage dissipation, 1e-3 r_d V per step (displacements, damage and load factor in one Newton system,
``abrakit.damage.model_one_path.DamageControl``), Model II by Crisfield's arc length. ``--models I`` reruns Model I
and keeps the stored Model II rows (``--specimens`` likewise keeps the other specimens' rows). Its rows add the work
along the whole followed path (``work_Nmm``: at 10 % of the peak almost all of it is dissipated), the smallest top
displacement after the peak (below ``u_at_peak_mm`` where the path snaps back), and the steps, Newton iterations and
seconds of the displacement-controlled run on the same mesh at the small step (read from ``--against``, default the
stored ``damage.json`` of the same mode). The curve metrics against the reference take the displacement-controlled
meaning only (a followed path is not a function of u), so they are left out. Stored in
``benchmarks/results/damage_path/`` (``damage_path_extruded/``); its ``damage.json`` is written after every run
(``--control path --reanalyse`` rebuilds it from ``damage.csv``).

writes ``damage.csv`` (one row per run, flushed as it goes), ``damage.json`` (mesh-independence metrics per case,
cost of Model I vs Model II, how and when it was produced), ``damage.png`` (runtime against curve error; cost per
step), ``damage_curves.png`` (force–displacement curves), ``damage_maps.png`` (stiffness loss on the finest
meshes) and ``damage_runs/*.npz`` (curve and element fields of every run, read by the book).
"""

from __future__ import annotations

import argparse
import datetime
import platform
import time
from pathlib import Path

import numpy as np

from abrakit.damage import metrics as M
from abrakit.damage.runs import REGULARISATION, run_specimen
from abrakit.damage.specimens import SPECIMENS, plot_field, specimen
from abrakit.fem import PathControl
from abrakit.io import CurveWriter, write_json
from abrakit.materials import TABLE_7_1

NAME = "damage"
LEVELS = {"full": ("coarse", "medium", "fine"), "quick": (250, 500, 1000)}
STEPS = (0.002, 0.004)  # mm per load step: small (reference) and twice as large
STOP_FRACTION = 0.1
DISPLACEMENT = 0.3  # mm, enough for every specimen to fall below 10 % of its peak
COLUMNS = ["specimen", "formulation", "model", "regularisation", "parameter", "level", "elements", "dofs", "step_mm",
           "status", "steps", "newton_iterations", "cutbacks", "seconds", "seconds_per_step", "peak_force_N",
           "u_at_peak_mm", "peak_error", "curve_distance", "work_common_Nmm", "final_u_mm", "band_width_mm",
           "band_angle_deg", "damaged_pieces", "transition_ratio", "softening_mm", "max_alpha_p"]


def case_name(spec, model, strength, level, step):
    return f"{spec}_{model}_{strength}_{level}_{step:g}".replace(" ", "")


RESULTS = Path(__file__).resolve().parent / "results"
TIMING = ("status", "steps", "newton_iterations", "cutbacks", "seconds", "seconds_per_step")


def analyse(meta: dict, u, F, stiffness_loss, alpha_p, reference, sp=None) -> dict:
    """The CSV row of one run: ``meta`` (case, mesh, timing) plus the curve and field metrics against
    ``reference = (u_ref, F_ref)`` (the finest mesh at the small step); ``sp``: the run's specimen (rebuilt from
    ``meta`` when not given, as when reanalysing stored runs)."""
    if sp is None:
        sp = specimen(meta["specimen"], _level(meta["level"]), displacement=DISPLACEMENT,
                      formulation=meta.get("formulation", "plane_strain"))
    m = M.specimen_metrics(sp, u, F, stiffness_loss)
    F_ref = M.peak(*reference)[0]
    return {**meta, "elements": sp.elements, "dofs": int(sp.basis.N),
            "peak_force_N": m["peak_force_N"], "u_at_peak_mm": m["u_at_peak_mm"],
            "peak_error": abs(m["peak_force_N"] - F_ref) / F_ref,
            "curve_distance": M.curve_distance(u, F, *reference),
            "work_common_Nmm": M.work(u, F, upto=min(u[-1], reference[0][-1])), "final_u_mm": float(u[-1]),
            "max_alpha_p": float(np.max(alpha_p)),
            **{k: m[k] for k in ("band_width_mm", "band_angle_deg", "damaged_pieces", "transition_ratio",
                                 "softening_mm")}}


def _level(level):
    return int(level) if str(level).isdigit() else str(level)


def _order(levels):
    """The reference (finest mesh, small step) first, so that every row can be compared as it is written."""
    return [(levels[-1], STEPS[0])] + [(lv, st) for st in STEPS for lv in levels if (lv, st) != (levels[-1], STEPS[0])]


def main(outdir: Path = RESULTS, quick: bool = False,
         models=("I", "II"), specimens=tuple(SPECIMENS), formulation: str = "plane_strain") -> dict:
    outdir = Path(outdir)
    runs_dir = outdir / f"{NAME}_runs"
    runs_dir.mkdir(parents=True, exist_ok=True)
    mode = "quick" if quick else "full"
    levels = LEVELS[mode]
    started = datetime.datetime.now().isoformat(timespec="seconds")
    t_start = time.perf_counter()
    records = []
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for spec_name in specimens:
            for model in models:
                for strength, parameter in REGULARISATION[model].items():
                    reference = None
                    for level, step in _order(levels):
                        sp = specimen(spec_name, level, displacement=DISPLACEMENT, formulation=formulation)
                        run = run_specimen(sp, model, parameter, step=step, stop_fraction=STOP_FRACTION)
                        u, F = np.asarray(run.u), np.asarray(run.F)
                        reference = (u, F) if reference is None else reference
                        meta = {"specimen": spec_name, "formulation": formulation, "model": model,
                                "regularisation": strength,
                                "parameter": parameter, "level": str(level), "step_mm": step, "status": run.status,
                                "steps": run.steps, "newton_iterations": run.iterations, "cutbacks": run.cutbacks,
                                "seconds": run.seconds, "seconds_per_step": run.seconds / max(run.steps, 1)}
                        row = analyse(meta, u, F, run.stiffness_loss, run.alpha_p, reference, sp)
                        writer.write(**row)
                        records.append(row)
                        key = case_name(spec_name, model, strength, level, step)
                        np.savez_compressed(runs_dir / f"{key}.npz", u=u, F=F,
                                            stiffness_loss=run.stiffness_loss.astype(np.float32),
                                            alpha_p=run.alpha_p.astype(np.float32))
                        print(f"{key}: {run.status}, {run.steps} steps, {run.seconds:.1f} s, peak "
                              f"{row['peak_force_N']:.0f} N, curve distance {row['curve_distance']:.3f}", flush=True)
    summary = {"mode": mode, "started": started, "finished": datetime.datetime.now().isoformat(timespec="seconds"),
               "wall_time_s": time.perf_counter() - t_start, "machine": platform.platform(),
               "python": platform.python_version(), "levels": [str(lv) for lv in levels], "steps_mm": list(STEPS),
               "stop_fraction": STOP_FRACTION, "displacement_mm": DISPLACEMENT, "formulation": formulation}
    return finish(outdir, records, summary)


PATH_COLUMNS = ["specimen", "formulation", "model", "control", "regularisation", "parameter", "level", "elements",
                "dofs", "status", "steps", "newton_iterations", "cutbacks", "seconds", "peak_force_N", "u_at_peak_mm",
                "smallest_u_after_peak_mm", "work_Nmm", "final_force_fraction", "band_width_mm", "damaged_pieces",
                "displacement_status", "displacement_steps", "displacement_iterations", "displacement_cutbacks",
                "displacement_seconds", "displacement_peak_force_N", "displacement_work_Nmm"]
PATH_CONTROLS = {"I": "damage", "II": "arc length"}
"""How ``--control path`` follows each model: Model I by its damage dissipation (monolithic Newton), Model II by
Crisfield's arc length."""
#: Model I's damage dissipation per step, relative to r_d times the specimen's volume (about 200 steps to fracture)
DAMAGE_STEP = 1e-3


def follow_specimen(sp, model: str, parameter: float, step: float):
    """One path-followed run (see the module docstring): Model I by its damage dissipation,
    :data:`DAMAGE_STEP` times r_d times the specimen's volume per step (load steps of ``step`` up to the first
    damage), Model II by arc length (load-factor steps of 2 ``step`` / displacement at first).

    Model I was followed by the opening of a gauge across the band in equal openings before (converged
    staggered sweeps): its peak depended on the opening step (double notch, 250 elements, beta = 1: 6037 / 7883 /
    9564 N for a first step of 10 ``step`` growing, ``step`` growing, ``step`` equal, against 10 494 N under
    displacement control), and on finer meshes the sweeps stopped settling (500 elements, beta = 0.1: failed
    before the peak). Damage control grows in every damaging step and leaves no such choice; its 250-element peak
    is 9587 N."""
    h = step / sp.displacement
    if model == "I":
        tau = DAMAGE_STEP * TABLE_7_1["r_d"] * float(np.sum(sp.basis.dx))     # per mm in plane strain
        return run_specimen(sp, "I", parameter, step=step, stop_fraction=STOP_FRACTION, damage_step=tau)
    return run_specimen(sp, "II", parameter, step=step, stop_fraction=STOP_FRACTION,
                        path=PathControl(initial=2 * h, maximum=2 * h, target_iterations=8, max_steps=4000))


def displacement_rows(against: Path) -> dict:
    """The displacement-controlled runs at the small step of the stored study ``against`` (its CSV read once),
    by (specimen, model, regularisation, level): their cost, status, peak and work (from their stored curves)."""
    import csv

    against = Path(against)
    if not (against / f"{NAME}.csv").exists():
        return {}
    with open(against / f"{NAME}.csv", newline="") as fh:
        rows = [r for r in csv.DictReader(fh) if float(r["step_mm"]) == STEPS[0]]
    out = {}
    for r in rows:
        key = (r["specimen"], r["model"], r["regularisation"], r["level"])
        stored = against / f"{NAME}_runs" / f"{case_name(*key, STEPS[0])}.npz"
        if key in out or not stored.exists():
            continue
        data = np.load(stored)
        out[key] = {"displacement_status": r["status"], "displacement_steps": int(r["steps"]),
                    "displacement_iterations": int(r["newton_iterations"]),
                    "displacement_cutbacks": int(r["cutbacks"]), "displacement_seconds": float(r["seconds"]),
                    "displacement_peak_force_N": float(np.max(data["F"])),
                    "displacement_work_Nmm": M.work(data["u"], data["F"])}
    return out


def main_path(outdir: Path, against: Path, quick: bool = False, models=("I", "II"), specimens=tuple(SPECIMENS),
              formulation: str = "plane_strain", resume: bool = False) -> dict:
    """``--control path``: every specimen, model, regularisation and mesh followed through its snap-back.

    ``resume``: keep every stored row and run only the cases of ``models`` and ``specimens`` without one (an
    interrupted study continues where it stopped)."""
    outdir = Path(outdir)
    runs_dir = outdir / f"{NAME}_runs"
    runs_dir.mkdir(parents=True, exist_ok=True)
    mode = "quick" if quick else "full"
    levels = LEVELS[mode]
    summary = {}
    # rows not rerun are kept from the stored study (e.g. --models I after a change of Model I)
    stored = read_path_rows(outdir)
    rows = stored if resume else [r for r in stored if not (r["model"] in models and r["specimen"] in specimens)]
    done = {(r["specimen"], r["model"], r["regularisation"], r["level"]) for r in rows}
    stepped = displacement_rows(against)
    with CurveWriter(outdir / f"{NAME}.csv", PATH_COLUMNS) as writer:
        for row in rows:
            row.setdefault("control", PATH_CONTROLS[row["model"]])
            writer.write(**path_csv_row(row))
        for spec_name in specimens:
            for model in models:
                for strength, parameter in REGULARISATION[model].items():
                    for level in levels:
                        if (spec_name, model, strength, str(level)) in done:
                            continue
                        sp = specimen(spec_name, level, displacement=DISPLACEMENT, formulation=formulation)
                        run = follow_specimen(sp, model, parameter, STEPS[0])
                        u, F = np.asarray(run.u), np.asarray(run.F)
                        i = int(np.argmax(F))
                        band = M.band_width(sp.plane_mesh, run.stiffness_loss, 0.5, length=sp.band_length,
                                            mirror=sp.band_mirror)
                        row = {"specimen": spec_name, "formulation": formulation, "model": model,
                               "control": PATH_CONTROLS[model],
                               "regularisation": strength, "parameter": parameter, "level": str(level),
                               "elements": sp.elements, "dofs": int(sp.basis.N), "status": run.status,
                               "steps": run.steps, "newton_iterations": run.iterations, "cutbacks": run.cutbacks,
                               "seconds": run.seconds, "peak_force_N": float(F[i]), "u_at_peak_mm": float(u[i]),
                               "smallest_u_after_peak_mm": float(np.min(u[i:])),
                               "work_Nmm": M.path_work(u, F),
                               "final_force_fraction": float(F[-1] / F[i]), "band_width_mm": band.width,
                               "damaged_pieces": M.damaged_components(sp.plane_mesh, run.stiffness_loss, 0.9,
                                                                      min_fraction=0.05),
                               **stepped.get((spec_name, model, strength, str(level)), {})}
                        writer.write(**path_csv_row(row))
                        rows.append(row)
                        np.savez_compressed(runs_dir / f"{case_name(spec_name, model, strength, level, 0)}.npz",
                                            u=u, F=F, stiffness_loss=run.stiffness_loss.astype(np.float32))
                        print(f"[damage path] {spec_name} {model} {strength} {level}: {run.status}, {run.steps} "
                              f"steps, {run.seconds:.1f} s, peak {row['peak_force_N']:.0f} N, work "
                              f"{row['work_Nmm']:.0f} N mm", flush=True)
                        summary = summarise_path(outdir, rows, {
                            "mode": mode, "formulation": formulation, "levels": [str(lv) for lv in levels],
                            "wall_time_s": sum(r["seconds"] for r in rows), "against": _relative(against)})
    return summary


def path_csv_row(row: dict) -> dict:
    """``row`` with every column of :data:`PATH_COLUMNS`, empty where it has no value (a run without a
    displacement-controlled twin, or a stored row read back without one)."""
    return {column: row.get(column) for column in PATH_COLUMNS}


def read_path_rows(outdir: Path) -> list[dict]:
    """The rows of a path-following study's ``damage.csv`` with their numbers converted (none if it is missing)."""
    import csv

    path = Path(outdir) / f"{NAME}.csv"
    if not path.exists():
        return []
    with open(path, newline="") as fh:
        raw = list(csv.DictReader(fh))
    text = {"specimen", "formulation", "model", "regularisation", "level", "status", "displacement_status",
            "control"}
    counts = {"elements", "dofs", "steps", "newton_iterations", "cutbacks", "damaged_pieces", "displacement_steps",
              "displacement_iterations", "displacement_cutbacks"}
    return [{k: v if k in text else int(float(v)) if k in counts else float(v) for k, v in r.items() if v != ""}
            for r in raw]


def reanalyse_path(outdir: Path) -> dict:
    """``damage.json`` of a path-following study rebuilt from its ``damage.csv`` (e.g. of a study stopped early)."""
    outdir = Path(outdir)
    rows = read_path_rows(outdir)
    levels = list(dict.fromkeys(r["level"] for r in rows))
    mode = "quick" if all(lv in map(str, LEVELS["quick"]) for lv in levels) else "full"
    return summarise_path(outdir, rows, {"mode": mode, "formulation": rows[0]["formulation"] if rows else "",
                                         "levels": levels, "wall_time_s": sum(r["seconds"] for r in rows),
                                         "against": "", "reanalysed": True})


def _spread(values) -> float | None:
    """:func:`abrakit.damage.metrics.relative_spread` of a case's runs so far (None before its second run)."""
    return M.relative_spread(values) if len(values) > 1 else None


def summarise_path(outdir: Path, rows: list[dict], meta: dict) -> dict:
    """``damage.json`` of a path-following study from its rows so far (written after every run, so that an
    interrupted study keeps a readable summary): per case the mesh spreads of peak and work, whether a path
    snapped back, and the cost beside the displacement-controlled runs."""
    cases = {}
    for r in rows:
        cases.setdefault(f"{r['specimen']}/{r['model']}/{r['regularisation']}", []).append(r)
    summary = {**meta, "control": "path", "stop_fraction": STOP_FRACTION, "damage_step": DAMAGE_STEP, "runs": len(rows),
               "date": datetime.datetime.now().isoformat(timespec="seconds"), "machine": platform.platform(),
               "cases": {key: {"peak_spread": _spread([r["peak_force_N"] for r in case]),
                               "work_spread": _spread([r["work_Nmm"] for r in case]),
                               "snaps_back": any(r["smallest_u_after_peak_mm"] < r["u_at_peak_mm"] for r in case),
                               "steps": sum(r["steps"] for r in case), "seconds": sum(r["seconds"] for r in case),
                               "cutbacks": sum(r["cutbacks"] for r in case),
                               "displacement_steps": sum(r.get("displacement_steps", 0) for r in case),
                               "displacement_seconds": sum(r.get("displacement_seconds", 0.0) for r in case),
                               "displacement_cutbacks": sum(r.get("displacement_cutbacks", 0) for r in case),
                               "runs": case} for key, case in cases.items()}}
    write_json(Path(outdir) / f"{NAME}.json", summary)
    return summary


def finish(outdir: Path, records: list, summary: dict) -> dict:
    """Cases, cost summary, JSON and figures from the rows."""
    levels = [_level(lv) for lv in summary["levels"]]
    cases = {}
    for r in records:
        case = cases.setdefault(f"{r['specimen']}/{r['model']}/{r['regularisation']}",
                                {"parameter": r["parameter"], "runs": {}})
        case["runs"][f"{r['level']}@{r['step_mm']:g}"] = r
    for case in cases.values():
        case.update(summarise(case["runs"], levels))
    summary = {**summary, "cases": cases, "cost": cost_summary(records)}
    write_json(outdir / f"{NAME}.json", summary)
    plot(outdir, records, levels)
    return summary


def _relative(path: Path) -> str:
    """``path`` relative to the repository's root where it lies inside it (``benchmarks/results/...``), else as
    given."""
    try:
        return str(Path(path).resolve().relative_to(RESULTS.parent.parent))
    except ValueError:
        return str(path)


def reanalyse(outdir: Path = RESULTS) -> dict:
    """Recompute every metric from the stored runs (``damage.csv`` timings + ``damage_runs/*.npz`` curves and
    fields) after a change of a metric's definition, without rerunning the simulations."""
    import csv

    from abrakit.io import read_json

    outdir = Path(outdir)
    old = read_json(outdir / f"{NAME}.json")
    with open(outdir / f"{NAME}.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    levels = old["levels"]
    references, records = {}, []
    for r in rows:
        meta = {"specimen": r["specimen"], "formulation": r.get("formulation", "plane_strain"),
                "model": r["model"], "regularisation": r["regularisation"], "parameter": float(r["parameter"]),
                "level": r["level"], "step_mm": float(r["step_mm"]),
                "status": r["status"], **{k: float(r[k]) for k in TIMING[1:]}}
        for k in ("steps", "newton_iterations", "cutbacks"):
            meta[k] = int(meta[k])
        case = (r["specimen"], r["model"], r["regularisation"])
        data = np.load(outdir / f"{NAME}_runs" / f"{case_name(*case, r['level'], meta['step_mm'])}.npz")
        if r["level"] == levels[-1] and meta["step_mm"] == STEPS[0]:
            references[case] = (data["u"], data["F"])
        records.append((meta, data, case))
    rows_out = [analyse(meta, data["u"], data["F"], data["stiffness_loss"], data["alpha_p"], references[case])
                for meta, data, case in records]
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for row in rows_out:
            writer.write(**row)
    summary = {k: v for k, v in old.items() if k not in ("cases", "cost")}
    summary["reanalysed"] = datetime.datetime.now().isoformat(timespec="seconds")
    return finish(outdir, rows_out, summary)


def summarise(runs: dict, levels) -> dict:
    """Mesh-independence numbers at the small step, and the step-size effect on the finest mesh."""
    small = [runs[f"{lv}@{STEPS[0]:g}"] for lv in levels]
    out = {"peak_spread": M.relative_spread([r["peak_force_N"] for r in small]),
           "max_curve_distance": max(r["curve_distance"] for r in small[:-1]),
           "work_spread": M.relative_spread([r["work_common_Nmm"] for r in small]),
           "step_effect_curve_distance": runs[f"{levels[-1]}@{STEPS[1]:g}"]["curve_distance"],
           "seconds_total": sum(r["seconds"] for r in runs.values())}
    widths = [r["band_width_mm"] for r in small]
    if min(widths) > 0:
        out["band_width_spread"] = M.relative_spread(widths)
    out["band_widths_mm"] = widths
    return out


def cost_summary(records) -> dict:
    """Seconds per step and per run of Model I against Model II on the same specimen, mesh and step."""
    out = {}
    by_key = {(r["specimen"], r["regularisation"], r["level"], r["step_mm"], r["model"]): r for r in records}
    ratios_step, ratios_run = [], []
    for (spec, strength, level, step, model), r in by_key.items():
        other = by_key.get((spec, strength, level, step, "II"))
        if model == "I" and other is not None:
            ratios_step.append(r["seconds_per_step"] / other["seconds_per_step"])
            ratios_run.append(r["seconds"] / other["seconds"])
    for model in ("I", "II"):
        rows = [r for r in records if r["model"] == model]
        if rows:
            out[f"model_{model}"] = {
                "runs": len(rows), "seconds": float(sum(r["seconds"] for r in rows)),
                "median_seconds_per_step": float(np.median([r["seconds_per_step"] for r in rows])),
                "median_iterations_per_step": float(np.median([r["newton_iterations"] / max(r["steps"], 1)
                                                               for r in rows])),
                "median_steps": float(np.median([r["steps"] for r in rows]))}
    if ratios_step:
        out["I_over_II_per_step_median"] = float(np.median(ratios_step))
        out["I_over_II_per_run_median"] = float(np.median(ratios_run))
    return out


def plot(outdir: Path, records, levels) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # speed against error, and cost per step against the mesh size
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.5))
    markers = {"plate_with_hole": "o", "double_notched": "s", "sharp_notch": "^"}
    colours = {("I", "weak"): "tab:blue", ("I", "strong"): "tab:cyan", ("II", "weak"): "tab:red",
               ("II", "strong"): "tab:orange"}
    for r in records:
        c = colours[(r["model"], r["regularisation"])]
        filled = r["step_mm"] == STEPS[0]
        if r["curve_distance"] > 0:
            ax1.loglog(r["seconds"], r["curve_distance"], markers[r["specimen"]], color=c,
                       mfc=c if filled else "none")
        ax2.loglog(r["elements"], r["seconds_per_step"], markers[r["specimen"]], color=c, mfc=c if filled else "none")
    for (model, strength), c in colours.items():
        ax1.plot([], [], "-", color=c, label=f"Model {model}, {strength}")
    for spec, mk in markers.items():
        ax1.plot([], [], mk, color="gray", label=spec.replace("_", " "))
    ax1.plot([], [], "o", color="gray", mfc="none", label=f"step {STEPS[1]} mm (open)")
    ax1.set(xlabel="runtime (s)", ylabel="L2 curve distance to the finest mesh",
            title="speed against error (filled: step 0.002 mm)")
    ax1.legend(fontsize=7)
    ax2.set(xlabel="elements", ylabel="seconds per load step", title="cost per step")
    fig.tight_layout()
    fig.savefig(outdir / f"{NAME}.png", dpi=120)
    plt.close(fig)

    runs_dir = outdir / f"{NAME}_runs"
    specs = sorted({r["specimen"] for r in records}, key=list(SPECIMENS).index)
    combos = [(m, s) for m in ("I", "II") for s in ("weak", "strong") if any(
        r["model"] == m and r["regularisation"] == s for r in records)]
    fig, axes = plt.subplots(len(specs), len(combos), figsize=(3.6 * len(combos), 2.8 * len(specs)),
                             squeeze=False)
    for i, spec in enumerate(specs):
        for j, (model, strength) in enumerate(combos):
            ax = axes[i, j]
            for level in levels:
                path = runs_dir / f"{case_name(spec, model, strength, level, STEPS[0])}.npz"
                if path.exists():
                    data = np.load(path)
                    ax.plot(data["u"], data["F"] / 1000, lw=1, label=str(level))
            ax.set_title(f"{spec.replace('_', ' ')}: Model {model} {strength}", fontsize=8)
            ax.set(xlabel="u (mm)", ylabel="F (kN)")
            ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(outdir / f"{NAME}_curves.png", dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(len(specs), len(combos), figsize=(3.6 * len(combos), 3.0 * len(specs)),
                             squeeze=False)
    for i, spec in enumerate(specs):
        sp = specimen(spec, levels[-1])
        for j, (model, strength) in enumerate(combos):
            ax = axes[i, j]
            path = runs_dir / f"{case_name(spec, model, strength, levels[-1], STEPS[0])}.npz"
            if path.exists():
                plot_field(sp, np.load(path)["stiffness_loss"], ax, colorbar=False, clim=(0.0, 1.0))
            ax.set_title(f"Model {model} {strength}", fontsize=8)
            ax.set_xticks([]), ax.set_yticks([])
    fig.suptitle(f"stiffness loss at the end, {levels[-1]} meshes", fontsize=9)
    fig.tight_layout()
    fig.savefig(outdir / f"{NAME}_maps.png", dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="small meshes (about 250/500/1000 elements)")
    parser.add_argument("--outdir", type=Path, default=RESULTS)
    parser.add_argument("--models", nargs="+", default=["I", "II"], choices=["I", "II"])
    parser.add_argument("--specimens", nargs="+", default=list(SPECIMENS), choices=list(SPECIMENS))
    parser.add_argument("--formulation", default="plane_strain", choices=["plane_strain", "extruded"],
                        help="plane strain x 3 mm, or the seed's one element through the 3 mm plate")
    parser.add_argument("--control", default="displacement", choices=["displacement", "path"],
                        help="displacement steps with cutbacks, or path following through the snap-back")
    parser.add_argument("--against", type=Path, default=None,
                        help="the displacement-controlled study the path-followed rows compare with (default: "
                             "results/ for plane strain, results/damage_extruded/ for extruded)")
    parser.add_argument("--resume", action="store_true",
                        help="with --control path: keep the stored rows and run only the missing cases")
    parser.add_argument("--reanalyse", action="store_true",
                        help="recompute the metrics of the stored runs in OUTDIR without rerunning them")
    args = parser.parse_args()
    if args.reanalyse:
        result = reanalyse_path(args.outdir) if args.control == "path" else reanalyse(args.outdir)
    elif args.control == "path":
        extruded = args.formulation == "extruded"
        outdir = args.outdir if args.outdir != RESULTS else RESULTS / ("damage_path_extruded" if extruded
                                                                       else "damage_path")
        against = args.against or (RESULTS / "damage_extruded" if extruded else RESULTS)
        result = main_path(outdir, against, quick=args.quick, models=tuple(args.models),
                           specimens=tuple(args.specimens), formulation=args.formulation, resume=args.resume)
    else:
        result = main(args.outdir, quick=args.quick, models=tuple(args.models), specimens=tuple(args.specimens),
                      formulation=args.formulation)
    print({k: v for k, v in result.items() if k not in ("cases",)})
