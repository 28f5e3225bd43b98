"""Benchmark of the scratch in the scene's own physics (finite strain, F-bar): time against error over the mesh levels.

The seed's scene (sphere R = 50 µm, d = 2 µm, μ = 0.1, St-52, 100 µm slide on the 200 µm block) on the mesh
levels of :data:`abrakit.scratch.scene.MESH_LEVELS` ("demo", "coarse", "default"; "fine" without ``--quick``), and
the long slide that reaches the plowing limit (the "coarse" mesh, 200 µm on a 300 µm block), and the live scene of
``abrakit demo`` and the book (``demo_scene``). Per run: wall time,
DOF, increments, Newton iterations, cutbacks, the mean normal force F_N over the second half of the slide, the
groove area A_g after unloading, the steady-rate degree of wear f_ab from the volume budget
(:func:`abrakit.scratch.budget.steady_rates`), and their errors against the finest finished level. A run that
stops keeps its row with the named cause (``stopped``).

Targets of issue 39, measured here (not in a timed test): default scene under 300 s, coarse mesh with the 200 µm
slide under 240 s, the demo scene under 30 s, on the 2-core machine.

Every run writes ``scratch_speed/<name>/`` (forces.csv, summary.json, a checkpoint) as it goes and is resumed by
a later call; finished runs are read back. Writes ``scratch_speed.csv``, ``scratch_speed.json`` and
``scratch_speed.png``.

    python benchmarks/bench_scratch_speed.py [--quick] [--outdir DIR]
"""

from __future__ import annotations

import platform
import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure

from abrakit.fem import StepFailed
from abrakit.io import CurveWriter, read_curve, read_json, write_json
from abrakit.scratch.budget import steady_rates
from abrakit.scratch.scene import DEMO_SCENE, ScratchScene, run_scratch

TARGETS_S = {"default": 300.0, "coarse_long": 240.0, "demo_scene": 30.0}
"""Wall-time targets of issue 39, s (2-core machine); "demo_scene" is the live scene of ``abrakit demo`` and the
book (:data:`~abrakit.scratch.scene.DEMO_SCENE`: demo mesh, 30 µm slide on a 100 µm block)."""

COLUMNS = ("name", "mesh", "slide_um", "length_um", "dofs", "increments", "newton_iterations", "cutbacks",
           "wall_time_s", "target_s", "status", "F_N", "A_g_um2", "f_ab_rates", "F_N_error", "A_g_error",
           "f_ab_rates_error", "note")


def planned(quick: bool) -> dict[str, ScratchScene]:
    """The runs, coarse to fine, then the long slide."""
    levels = ["demo", "coarse", "default"] + ([] if quick else ["fine"])
    plan = {level: ScratchScene(mesh=level) for level in levels}
    plan["coarse_long"] = ScratchScene(mesh="coarse", slide=0.2, size=(0.1, 0.015, 0.3))
    plan["demo_scene"] = DEMO_SCENE
    return plan


def run_or_resume(folder: Path, scene: ScratchScene) -> dict:
    """One run's numbers: read back if finished, else run (resuming its checkpoint); a stopped run is a row too."""
    if (folder / "summary.json").exists():
        return read_json(folder / "summary.json") | {"status": "finished"}
    try:
        result = run_scratch(scene, output=folder, vtu_every=0, resume=True)
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
    groove = summary.get("groove_unloaded") or {}
    return {
        "name": name, "mesh": scene.mesh, "slide_um": scene.slide * 1e3, "length_um": scene.size[2] * 1e3,
        **{k: summary.get(k, np.nan) for k in ("dofs", "increments", "newton_iterations", "cutbacks",
                                                "wall_time_s")},
        "target_s": TARGETS_S.get(name, np.nan), "status": summary["status"],
        "F_N": float(curves["normal_force"][second_half].mean()) if np.any(second_half) else np.nan,
        "A_g_um2": groove.get("A_g_um2", np.nan), "f_ab_rates": rates, "note": summary.get("note", ""),
    }


def with_errors(rows: dict[str, dict]) -> str | None:
    """Relative errors of F_N, A_g and f_ab (rates) against the finest finished level (100 µm slide runs)."""
    levels = [n for n in ("fine", "default", "coarse", "demo") if n in rows and rows[n]["status"] == "finished"]
    if not levels:
        return None
    reference = rows[levels[0]]
    for name, row in rows.items():
        same_scene = name in ("demo", "coarse", "default", "fine")
        for key in ("F_N", "A_g_um2", "f_ab_rates"):
            error = abs(row[key] / reference[key] - 1.0) if same_scene else np.nan
            row[f"{key.removesuffix('_um2')}_error"] = error
    return levels[0]


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    started = time.perf_counter()
    rows = {}
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
                   "summary": summary_line(rows)}
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
    for key, marker in (("F_N_error", "o"), ("A_g_error", "s"), ("f_ab_rates_error", "^")):
        points = [(r["wall_time_s"], r[key], n) for n, r in rows.items() if np.isfinite(r.get(key, np.nan))
                  and r[key] > 0]
        if points:
            t, e, names = zip(*points, strict=True)
            ax.loglog(t, e, marker=marker, linestyle="-", label=key.removesuffix("_error"))
            for ti, ei, ni in points:
                ax.annotate(ni, (ti, ei), textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel("relative error to the finest level")
    ax.set_title("Scratch, finite strain + F-bar: time against error")
    if ax.get_legend_handles_labels()[0]:
        ax.legend()
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="demo, coarse and default levels (no fine) and the long slide")
