"""Benchmark of the scratch in the scene's own physics (finite strain, F-bar): time against error over the mesh levels.

The seed's scene (sphere R = 50 µm, d = 2 µm, μ = 0.1, St-52, 100 µm slide on the 200 µm block) on the mesh
levels of :data:`abrakit.scratch.scene.MESH_LEVELS` ("demo", "coarse", "default"; "fine" without ``--quick``), the
live scene of ``abrakit demo`` (``demo_scene``), and every level again with the 200 µm slide on a 300 µm block
(``<level>_long``: the slide that reaches the plowing limit, and issue 39's robustness check; the "finer" level,
:data:`LONG_ONLY`, only there). Per run: wall time,
DOF, increments, Newton iterations, cutbacks, the mean normal force F_N over the second half of the slide, the
groove area A_g after unloading, the degree of wear f_ab three ways (the steady rates of the volume budget over the
second half of the slide and over its last quarter, :func:`abrakit.scratch.budget.steady_rates`; the mean and range
of nine wake sections after unloading, from mid-slide to two footprint radii before the end), and the errors of
F_N, A_g and f_ab (rates) against the finest finished level of the same slide. A run that stops keeps its row with
the named cause (``stopped``).

Targets of issue 39, measured here (not in a timed test): default scene under 300 s, coarse mesh with the 200 µm
slide under 240 s, the demo scene under 30 s, on the 2-core machine.

Runs computed with the scene's inexact Newton corrections (``corrections`` column) are compared with the table of
exact corrections stored before them (:data:`EXACT_CORRECTIONS`, ``against_exact_corrections``).

Every run writes ``scratch_speed/<name>/`` (forces.csv, summary.json, a checkpoint, u.npy at the end) as it goes
and is resumed by a later call; finished runs are read back. Writes ``scratch_speed.csv``, ``scratch_speed.json`` and
``scratch_speed.png``.

    python benchmarks/bench_scratch_speed.py [--quick] [--outdir DIR]
"""

from __future__ import annotations

import functools
import platform
import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure

from abrakit.fem import StepFailed
from abrakit.io import CurveWriter, read_curve, read_json, write_json
from abrakit.scratch.budget import steady_rates
from abrakit.scratch.readouts import groove_along
from abrakit.scratch.record import slide_mean
from abrakit.scratch.run import run_scratch
from abrakit.scratch.scene import DEMO_SCENE, ScratchScene, build_specimen

TARGETS_S = {"default": 300.0, "coarse_long": 240.0, "demo_scene": 30.0}
"""Wall-time targets of issue 39, s (2-core machine); "demo_scene" is the live scene of ``abrakit demo`` and the
book (:data:`~abrakit.scratch.scene.DEMO_SCENE`: demo mesh, 30 µm slide on a 100 µm block)."""

COLUMNS = ("name", "mesh", "slide_um", "length_um", "dofs", "increments", "newton_iterations", "cutbacks",
           "wall_time_s", "target_s", "status", "corrections", "F_N", "A_g_um2", "f_ab_rates",
           "f_ab_rates_last_quarter", "f_ab_sections", "f_ab_sections_spread", "F_N_error", "A_g_error",
           "f_ab_rates_error", "note")

EXACT_CORRECTIONS = "scratch_speed_exact_corrections.json"
"""The table as it stood before the scene's inexact Newton corrections (:data:`~abrakit.scratch.run.SCENE_FORCING`;
every correction solved to 10⁻⁸; measured on an earlier machine, an Intel Xeon, where the later ones ran on an AMD
EPYC): each run computed again with them is compared with its row there (:func:`against_exact`)."""
COMPARED = ("F_N", "A_g_um2", "f_ab_rates", "f_ab_sections", "wall_time_s", "newton_iterations", "cutbacks")


LEVELS = ("demo", "coarse", "default", "fine")
LONG_ONLY = ("finer",)
"""Levels run only through the 200 µm slide (not with ``--quick``): the rest of
:data:`~abrakit.scratch.scene.MESH_LEVELS`, so that every level is shown to finish the long slide (issue 39's
robustness; "finer" has 149 520 DOF on the 300 µm block)."""


def planned(quick: bool) -> dict[str, ScratchScene]:
    """The runs: every level with the seed's 100 µm slide, the live scene, then every level with the 200 µm slide
    on a 300 µm block (the long slide that reaches the plowing limit; :data:`LONG_ONLY` only there)."""
    levels = list(LEVELS[:3] if quick else LEVELS)
    plan = {level: ScratchScene(mesh=level) for level in levels}
    plan["demo_scene"] = DEMO_SCENE
    for level in levels + ([] if quick else list(LONG_ONLY)):      # every level through the 200 µm slide
        plan[f"{level}_long"] = ScratchScene(mesh=level, slide=0.2, size=(0.1, 0.015, 0.3))
    return plan


def run_or_resume(folder: Path, scene: ScratchScene) -> dict:
    """One run's numbers: read back if finished, else run (resuming its checkpoint); a stopped run is a row too."""
    if (folder / "summary.json").exists():
        return read_json(folder / "summary.json") | {"status": "finished"}
    try:
        result = run_scratch(scene, output=folder, vtu_every=0, resume=True)
        np.save(folder / "u.npy", result.u)                    # the end state, for the wake's sections
    except StepFailed as stopped:
        curves = read_curve(folder / "forces.csv")
        note = str(stopped).replace(str(folder), f"scratch_speed/{folder.name}")     # no machine path stored
        return {"status": "stopped", "note": note, "dofs": np.nan, "increments": len(curves["step"]),
                "newton_iterations": int(np.sum(curves["iterations"])), "cutbacks": np.nan,
                "wall_time_s": float(curves["wall_time"][-1]), "groove_unloaded": None}
    return result.summary() | {"status": "finished"}


def row_of(name: str, scene: ScratchScene, summary: dict, folder: Path) -> dict:
    curves = read_curve(folder / "forces.csv")
    sliding = curves["phase"] == 1
    second_half = sliding & (curves["slide"] >= 0.5 * scene.slide)
    finished = summary["status"] == "finished"
    rates = steady_rates(curves).degree_of_wear if finished else np.nan
    last_quarter = steady_rates(curves, 0.75 * scene.slide).degree_of_wear if finished else np.nan
    wake = wake_readings(scene, folder) if finished else {"f_ab_sections": np.nan, "f_ab_sections_range": np.nan}
    groove = summary.get("groove_unloaded") or {}
    return {
        "name": name, "mesh": scene.mesh, "slide_um": scene.slide * 1e3, "length_um": scene.size[2] * 1e3,
        **{k: summary.get(k, np.nan) for k in ("dofs", "increments", "newton_iterations", "cutbacks",
                                                "wall_time_s")},
        "target_s": TARGETS_S.get(name, np.nan), "status": summary["status"],
        "corrections": "inexact" if any("inexact corrections" in n for n in summary.get("notes", [])) else "exact",
        "F_N": slide_mean(curves["slide"][second_half], curves["normal_force"][second_half]),
        "A_g_um2": groove.get("A_g_um2", np.nan), "f_ab_rates": rates, "f_ab_rates_last_quarter": last_quarter,
        "f_ab_sections": wake["f_ab_sections"], "f_ab_sections_spread": wake["f_ab_sections_range"],
        "note": summary.get("note", ""),
    }


def wake_sections(scene: ScratchScene, folder: Path) -> np.ndarray:
    """f_ab of the wake's sections after unloading, from the second half of the slide to two footprint radii before
    its end (the crater where the tip lifted): the sections beyond the transient of the indentation."""
    if not (folder / "u.npy").exists():
        return np.full(0, np.nan)
    z0, z1 = scene.path.z_start + 0.5 * scene.slide, scene.path.z_start + scene.slide - 2.0 * scene.footprint
    along = groove_along(build_specimen(scene), np.load(folder / "u.npy"), scene, np.linspace(z0, z1, 9))
    return along.degree_of_wear[np.isfinite(along.degree_of_wear)]


@functools.cache
def wake_readings(scene: ScratchScene, folder: Path) -> dict:
    """The mean and range of f_ab over the nine wake sections beyond mid-slide of a stored run
    (:func:`wake_sections`; NaN without its end state), computed once per run (several tables read
    the same runs)."""
    wake = wake_sections(scene, folder)
    return {"f_ab_sections": float(np.mean(wake)) if wake.size else np.nan,
            "f_ab_sections_range": float(np.ptp(wake)) if wake.size else np.nan}


def with_errors(rows: dict[str, dict]) -> str | None:
    """Relative errors of F_N, A_g and f_ab (rates) of every level against the finest finished level of the same
    slide (100 µm, or 200 µm for the ``_long`` runs); returns the reference of the 100 µm runs."""
    levels = (*LEVELS, *LONG_ONLY)                                        # coarsest to finest

    def finest(suffix: str) -> dict | None:
        names = [level + suffix for level in levels[::-1]]
        return next((rows[n] for n in names if n in rows and rows[n]["status"] == "finished"), None)

    references = {"": finest(""), "_long": finest("_long")}
    for name, row in rows.items():
        suffix = "_long" if name.endswith("_long") else ""
        ref = references[suffix] if name.removesuffix(suffix) in levels else None
        for key in ("F_N", "A_g_um2", "f_ab_rates"):
            row[f"{key.removesuffix('_um2')}_error"] = abs(row[key] / ref[key] - 1.0) if ref else np.nan
    return references[""]["name"] if references[""] else None


def against_exact(rows: dict[str, dict], before: dict[str, dict]) -> dict:
    """Per finished run with inexact corrections that the table of exact corrections has too: both rows' forces,
    groove area, f_ab (rates and sections), wall time, Newton iterations and cutbacks, and the changes (relative for
    F_N and A_g, absolute for f_ab)."""
    out = {}
    for name, row in rows.items():
        old = before.get(name)
        if row["corrections"] != "inexact" or row["status"] != "finished" or not old or old["status"] != "finished":
            continue
        out[name] = {"inexact": {k: row[k] for k in COMPARED}, "exact": {k: old[k] for k in COMPARED},
                     "change": {"F_N_relative": row["F_N"] / old["F_N"] - 1.0,
                                "A_g_relative": row["A_g_um2"] / old["A_g_um2"] - 1.0,
                                "f_ab_rates": row["f_ab_rates"] - old["f_ab_rates"],
                                "f_ab_sections": row["f_ab_sections"] - old["f_ab_sections"],
                                "speed_up": old["wall_time_s"] / row["wall_time_s"]}}
    return out


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    started = time.perf_counter()
    rows = {}
    exact = outdir / EXACT_CORRECTIONS
    before = {row["name"]: row for row in read_json(exact)["rows"]} if exact.exists() else {}
    for name, scene in planned(quick).items():
        folder = outdir / "scratch_speed" / name
        summary = run_or_resume(folder, scene)
        rows[name] = row_of(name, scene, summary, folder)
        reference = with_errors(rows)
        with CurveWriter(outdir / "scratch_speed.csv", COLUMNS) as writer:
            for row in rows.values():
                writer.write(**{k: row.get(k, np.nan) for k in COLUMNS})
        results = {"date": time.strftime("%Y-%m-%d %H:%M"), "host": platform.node(), "quick": quick,
                   "reference": reference, "rows": list(rows.values()), "targets_s": TARGETS_S,
                   "summary": summary_line(rows), "against_exact_corrections": against_exact(rows, before)}
        write_json(outdir / "scratch_speed.json", results)
    plot(rows, outdir / "scratch_speed.png")
    results["wall_time_s"] = time.perf_counter() - started
    return results


def summary_line(rows: dict) -> str:
    parts = []
    for name, row in rows.items():
        target = f" (target {row['target_s']:g} s)" if np.isfinite(row["target_s"]) else ""
        parts.append(f"{name}: {row['wall_time_s']:.0f} s{target}, {row['status']}")
    return "; ".join(parts)


def plot(rows: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for long, style in ((False, "-"), (True, "--")):                  # 100 µm slides solid, 200 µm dashed
        for key, marker, color in (("F_N_error", "o", "C0"), ("A_g_error", "s", "C1"),
                                   ("f_ab_rates_error", "^", "C2")):
            points = [(r["wall_time_s"], r[key], n) for n, r in rows.items() if n.endswith("_long") == long
                      and np.isfinite(r.get(key, np.nan)) and r[key] > 0]
            if points:
                t, e, names = zip(*points, strict=True)
                label = f"{key.removesuffix('_error')}, {'200' if long else '100'} µm slide"
                ax.loglog(t, e, marker=marker, linestyle=style, color=color, label=label)
                for ti, ei, ni in points:
                    ax.annotate(ni, (ti, ei), textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel("relative error to the finest level")
    ax.set_title("Scratch, finite strain + F-bar: time against error")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="demo, coarse and default levels (no fine) and the long slide")
