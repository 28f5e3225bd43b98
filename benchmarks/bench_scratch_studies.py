"""Benchmark: the seed's depth and radius studies (Ch. 8, Figs. 8.8–8.12) in the scene's own physics.

``bench_scratch.py`` reproduces the studies in the seed's formulation (small strain, full integration). Here the
same scenes run in the scene's physics (finite strain with F-bar, the faster solver of issue 39): the depth study
(sphere R = 50 µm, d = 1…5 µm) and the radius study (sphere-tipped 60° cones, R = 25, 50, 100 µm, d = 3 µm), each
with the seed's 100 µm slide on the seed's 200 µm block. Per run: wall time, DOF, increments, Newton iterations,
cutbacks, the mean normal and tangential forces over the steady slide, the groove after unloading at mid-length
(A_g, A_s, f_ab, the degree of penetration D_p and the regime), and the same numbers of the seed-formulation run of
the same name where ``scratch.json`` stores one (on its own mesh level, named in the table). A run that stops keeps
its row with the named cause.

Every run is kept in ``scratch_studies/scratch_runs/<name>/run.json`` and read back by later calls (an interrupted
study loses nothing it has finished). Writes ``scratch_studies.csv``, ``scratch_studies.json`` and
``scratch_studies.png``.

    python benchmarks/bench_scratch_studies.py [--quick] [--outdir DIR]

``--quick`` runs the demo mesh, the default the coarse one.
"""

from __future__ import annotations

import platform
import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure
from bench_scratch import BLOCK, STUDY_SLIDE, Runner

from abrakit.fem import StepFailed
from abrakit.io import CurveWriter, read_json, write_json
from abrakit.scratch import ConicalIndenter
from abrakit.scratch.scene import ScratchScene

DEPTHS_MM = (0.001, 0.002, 0.003, 0.004, 0.005)
"""Depths of the depth study (sphere R = 50 µm), mm."""
CONE_RADII_MM = (0.025, 0.05, 0.1)
"""Tip radii of the radius study (60° cones at d = 3 µm), mm."""
COLUMNS = ("name", "part", "R_um", "d_um", "tip", "mesh", "status", "dofs", "increments", "newton_iterations",
           "cutbacks", "wall_time_s", "mean_normal_force_N", "mean_tangential_force_N", "A_g_um2", "A_s_um2",
           "f_ab", "D_p", "regime", "seed_formulation_mesh", "seed_formulation_F_N", "seed_formulation_A_g_um2",
           "seed_formulation_f_ab", "note")


def planned(mesh: str) -> list[tuple[str, str, ScratchScene]]:
    """(name, part, scene) of the depth and radius studies in the scene's physics on ``mesh``."""
    plan = [(f"depth_{d * 1e3:g}um", "depth", ScratchScene(depth=d, slide=STUDY_SLIDE, mesh=mesh, size=BLOCK))
            for d in DEPTHS_MM]
    plan += [(f"radius_{R * 1e3:g}um", "radius",
              ScratchScene(indenter=ConicalIndenter.from_included_angle(R, 60.0), depth=0.003, slide=STUDY_SLIDE,
                           mesh=mesh, size=BLOCK))
             for R in CONE_RADII_MM]
    return plan


def seed_formulation_rows(results: Path) -> tuple[dict, str | None]:
    """The rows of ``bench_scratch.py``'s studies (the seed's formulation) by name, and their mesh level."""
    stored = results / "scratch.json"
    if not stored.exists():
        return {}, None
    data = read_json(stored)
    rows = {name: entry["row"] for name, entry in data["runs"].items() if entry["row"]["part"] in ("depth", "radius")}
    return rows, data.get("study_mesh")


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    mesh = "demo" if quick else "coarse"
    run = Runner(outdir / "scratch_studies")
    seed_rows, seed_mesh = seed_formulation_rows(outdir)
    t0 = time.perf_counter()
    rows = []
    for name, part, scene in planned(mesh):
        base = {"name": name, "part": part, "R_um": scene.indenter.radius * 1e3, "d_um": scene.depth * 1e3,
                "tip": "cone60" if isinstance(scene.indenter, ConicalIndenter) else "sphere", "mesh": mesh}
        try:
            row = dict(run(name, part, scene)["row"])
            row.update(status="finished", note="")
        except StepFailed as stopped:
            row = {"status": "stopped", "note": str(stopped).split(" [")[0][:300]}
        seed = seed_rows.get(name, {})
        rows.append({k: np.nan for k in COLUMNS} | row | base | {
            "seed_formulation_mesh": seed_mesh if seed else "",
            "seed_formulation_F_N": seed.get("mean_normal_force_N", np.nan),
            "seed_formulation_A_g_um2": seed.get("A_g_um2", np.nan),
            "seed_formulation_f_ab": seed.get("f_ab", np.nan)})
        print(f"[scratch studies] {name}: {rows[-1]['status']}, {rows[-1]['wall_time_s']:.0f} s", flush=True)
    with CurveWriter(outdir / "scratch_studies.csv", COLUMNS) as w:
        for r in rows:
            w.write(**{k: r[k] for k in COLUMNS})
    run_time = sum(r["wall_time_s"] for r in rows if r["status"] == "finished")
    results = {"mode": "quick" if quick else "full", "mesh": mesh, "date": time.strftime("%Y-%m-%d %H:%M"),
               "host": platform.node(), "wall_time_s": time.perf_counter() - t0, "run_time_s": run_time,
               "slide_um": STUDY_SLIDE * 1e3, "seed_formulation_mesh": seed_mesh, "rows": rows}
    write_json(outdir / "scratch_studies.json", results)
    plot(results, outdir / "scratch_studies.png")
    results["summary"] = (f"{sum(r['status'] == 'finished' for r in rows)} of {len(rows)} runs finished on the "
                          f"{mesh} mesh in {run_time:.0f} s of run time")
    return results


def plot(results: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    rows = [r for r in results["rows"] if r["status"] == "finished"]
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    depth = sorted((r for r in rows if r["part"] == "depth"), key=lambda r: r["d_um"])
    d = [r["d_um"] for r in depth]
    label = f"seed's formulation ({results['seed_formulation_mesh']} mesh)"
    for a, key, seed_key, ylabel in ((ax[0], "mean_normal_force_N", "seed_formulation_F_N", "mean F_N [N]"),
                                     (ax[1], "A_g_um2", "seed_formulation_A_g_um2", "A_g after unloading [µm²]"),
                                     (ax[2], "f_ab", "seed_formulation_f_ab", "f_ab after unloading")):
        a.plot(d, [r[key] for r in depth], "o-", label=f"scene's physics ({results['mesh']} mesh)")
        a.plot(d, [r[seed_key] for r in depth], "s--", label=label)
        a.set(xlabel="depth d [µm] (sphere R = 50 µm)", ylabel=ylabel)
        a.legend(fontsize=8)
    ax[0].set_title("Fig. 8.8: normal force against depth")
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__)
