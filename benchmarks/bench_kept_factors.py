"""Benchmark: the scratch's Newton corrections exact or inexact (GMRES with kept factors), on one thread and on two.

Issue 39's third round. :data:`abrakit.scratch.run.SCENE_FORCING` takes a correction within an increment from
GMRES preconditioned with the factors kept from the increment's last factorisation, to 3 % of the residual in at
most eight iterations, and factorises only when that fails. Whether that pays depends on what a factorisation
costs against a GMRES iteration (one solve with the kept factors, one product with the tangent): this benchmark
runs the coarse mesh's 100 µm slide (the seed's scene, finite strain, F-bar; ``--quick``: the demo scene) four
ways:

- one thread per process (``ABRAKIT_THREADS=1``), exact and inexact side by side on the two cores, as two test
  workers or two sweep processes run;
- two threads, exact and then inexact, each alone on the machine.

Per run: wall time, Newton iterations, cutbacks, factorisations and their seconds, solves, GMRES iterations, and
F_N, A_g, f_ab (steady rates) with the inexact run's changes against the exact one. Every run is a subprocess that
writes ``kept_factors_runs/<name>/`` (``kept_factors_quick/`` with ``--quick``; forces.csv, summary.json) and is
read back by a later call. Writes ``kept_factors.json``, ``.csv`` and ``.png``.

    python benchmarks/bench_kept_factors.py [--quick] [--outdir DIR]
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure
from bench_scratch_speed import row_of as speed_row

from abrakit.io import CurveWriter, read_json, write_json
from abrakit.scratch.run import run_scratch
from abrakit.scratch.scene import DEMO_SCENE, ScratchScene

NAME = "kept_factors"
CASES = {"1thread_exact": (1, False), "1thread_inexact": (1, True), "2threads_exact": (2, False),
         "2threads_inexact": (2, True)}
"""Run name: (threads, inexact corrections)."""
COLUMNS = ("name", "threads", "inexact", "wall_time_s", "newton_iterations", "cutbacks", "factorisations",
           "factorise_s", "solves", "gmres_iterations", "krylov_solves", "krylov_fallbacks", "F_N", "A_g_um2",
           "f_ab_rates")


def scene_for(quick: bool) -> ScratchScene:
    return DEMO_SCENE if quick else ScratchScene(mesh="coarse")


def run_case(name: str, folder: Path, quick: bool) -> None:
    """One run, in this process (the subprocess of :func:`launch`)."""
    run_scratch(scene_for(quick), output=folder, vtu_every=0, inexact=CASES[name][1])


def runs_folder(outdir: Path, quick: bool) -> Path:
    return outdir / ("kept_factors_quick" if quick else "kept_factors_runs")


def launch(name: str, outdir: Path, quick: bool) -> subprocess.Popen | None:
    """Start the run ``name`` in a subprocess with its thread count, unless it is stored."""
    folder = runs_folder(outdir, quick) / name
    if (folder / "summary.json").exists():
        return None
    env = {**os.environ, "ABRAKIT_THREADS": str(CASES[name][0])}
    command = [sys.executable, __file__, "--case", name, "--folder", str(folder)] + (["--quick"] if quick else [])
    return subprocess.Popen(command, env=env)


def row_of(name: str, folder: Path, quick: bool) -> dict:
    """A run's counters from its summary, and F_N, A_g, f_ab read as the speed table reads them
    (:func:`bench_scratch_speed.row_of`)."""
    summary = read_json(folder / "summary.json")
    counts = summary.get("solver_counts", {})
    read = speed_row(name, scene_for(quick), summary | {"status": "finished"}, folder)
    return {"name": name, "threads": CASES[name][0], "inexact": CASES[name][1],
            **{k: summary[k] for k in ("wall_time_s", "newton_iterations", "cutbacks")},
            "factorisations": counts.get("factorisations", np.nan), "factorise_s": counts.get("factorise_s", np.nan),
            "solves": counts.get("solves", np.nan), "gmres_iterations": counts.get("gmres_iterations", 0),
            "krylov_solves": counts.get("krylov_solves", 0), "krylov_fallbacks": counts.get("krylov_fallbacks", 0),
            **{k: read[k] for k in ("F_N", "A_g_um2", "f_ab_rates")}}


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    started = time.perf_counter()
    for batch in (("1thread_exact", "1thread_inexact"), ("2threads_exact",), ("2threads_inexact",)):
        processes = [p for p in (launch(name, outdir, quick) for name in batch) if p is not None]
        for process in processes:
            if process.wait() != 0:
                raise RuntimeError(f"a run of {batch} failed (exit code {process.returncode})")
    rows = {name: row_of(name, runs_folder(outdir, quick) / name, quick) for name in CASES}
    comparison = {}
    for threads in (1, 2):
        exact, inexact = (rows[f"{threads}thread{'s' if threads == 2 else ''}_{kind}"] for kind in ("exact", "inexact"))
        comparison[f"{threads} thread{'s' if threads == 2 else ''}"] = {
            "speed_up": exact["wall_time_s"] / inexact["wall_time_s"],
            "factorisations_saved": 1.0 - inexact["factorisations"] / exact["factorisations"],
            "iterations_ratio": inexact["newton_iterations"] / exact["newton_iterations"],
            "seconds_per_factorisation": exact["factorise_s"] / exact["factorisations"],
            "F_N_relative": inexact["F_N"] / exact["F_N"] - 1.0,
            "A_g_relative": inexact["A_g_um2"] / exact["A_g_um2"] - 1.0,
            "f_ab_rates": inexact["f_ab_rates"] - exact["f_ab_rates"]}
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for row in rows.values():
            writer.write(**row)
    results = {"date": time.strftime("%Y-%m-%d %H:%M"), "quick": quick, "scene": repr(scene_for(quick)),
               "rows": list(rows.values()), "comparison": comparison, "wall_time_s": time.perf_counter() - started,
               "summary": "; ".join(f"{k}: inexact {v['speed_up']:.2f}x as fast, {v['iterations_ratio']:.2f}x the "
                                    f"iterations, F_N {v['F_N_relative']:+.1e}" for k, v in comparison.items())}
    write_json(outdir / f"{NAME}.json", results)
    plot(rows, outdir / f"{NAME}.png")
    return results


def plot(rows: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 3.8))
    names = list(rows)
    factorise = [rows[n]["factorise_s"] for n in names]
    rest = [rows[n]["wall_time_s"] - rows[n]["factorise_s"] for n in names]
    ax.barh(names, factorise, color="C0", label="factorisations")
    ax.barh(names, rest, left=factorise, color="C1", label="everything else (GMRES, residuals, tangents)")
    for k, n in enumerate(names):
        ax.annotate(f"{rows[n]['newton_iterations']} it., {rows[n]['factorisations']} fact.",
                    (rows[n]["wall_time_s"], k), xytext=(4, -3), textcoords="offset points", fontsize=8)
    ax.set_xlabel("wall time [s]")
    ax.set_title("Scratch corrections: exact or by GMRES with kept factors")
    ax.legend(fontsize=7, loc="lower right")
    save_figure(fig, path)


if __name__ == "__main__":
    if "--case" in sys.argv:
        name, folder = sys.argv[sys.argv.index("--case") + 1], Path(sys.argv[sys.argv.index("--folder") + 1])
        run_case(name, folder, "--quick" in sys.argv)
    else:
        command_line(main, __doc__, quick_help="the demo scene instead of the coarse mesh's 100 um slide")
