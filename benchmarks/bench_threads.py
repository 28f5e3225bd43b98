"""Benchmark of the thread policy (:mod:`abrakit.threads`): the pieces of one scratch Newton iteration under it and
under the libraries' own defaults, alone and as two concurrent processes (two test workers on the 2-core machine).

The pieces, on the scratch's "default" mesh (24 510 DOF, finite strain, F-bar; "coarse" with ``--quick``), the
fastest of five after a warm-up: the residual evaluation (material update, F-bar forces, contact), the material
tangent, the F-bar element tangents, the whole tangent, PARDISO's factorisation and solve, and the element tangents
right after a factorisation (where a spinning OpenMP pool of the solver steals the cores from numba's threads).

Settings, each in a fresh process (thread pools read their environment when they load):

* ``policy``: what ``import abrakit`` chooses (cores // workers threads per pool; the stored results of
  2026-11-28 were measured while the policy also set passive OpenMP waits, since dropped: ``abrakit.threads``);
* ``library defaults``: OpenMP threads spin after their parallel regions (``OMP_WAIT_POLICY=ACTIVE``,
  ``KMP_BLOCKTIME=200``), every pool as many threads as cores;
* ``one thread``: every pool one thread (``ABRAKIT_THREADS=1``);
* ``2 workers, policy`` / ``2 workers, library defaults``: two such processes at once, as pytest-xdist's two
  workers (``PYTEST_XDIST_WORKER_COUNT=2`` lets the policy give each one thread).

The pieces timed alone miss what a whole run shows: OpenBLAS's threads, woken by every ``dot`` of a vector long
enough to be split, spin and hold the cores the OpenMP pools (numba, PARDISO) wait for. So a second table
(``runs``) times whole scratch runs (:data:`RUN_SCENE`: the default mesh, a 20 µm slide, 15 390 DOF) under the
policy, under the policy with OpenBLAS as many threads as the other pools (``OPENBLAS_NUM_THREADS`` = cores, the
policy before OpenBLAS got one thread), and with one thread in every pool.

Writes ``threads.csv``, ``threads.json`` and ``threads.png``.

    python benchmarks/bench_threads.py [--quick] [--outdir DIR]
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure

from abrakit.io import CurveWriter, write_json

PIECES = ("evaluate", "material_tangent", "element_tangents", "tangent", "factorise_solve",
          "element_tangents_after_factorising")

PROBE = r"""
import json, sys, time
import numpy as np
from abrakit.fem import Solver
from abrakit.fem.solver import LineSearch, StepContext
from abrakit.materials import LogStrainPlasticity
from abrakit.scratch.run import scene_linear_solver
from abrakit.scratch.scene import ScratchScene, build_specimen, st52_material

scene = ScratchScene(mesh=sys.argv[1])
specimen = build_specimen(scene)
material = LogStrainPlasticity(st52_material())
solver = Solver(specimen.basis, material, specimen.conditions, bbar=True, finite_strain=True,
                line_search=LineSearch())
solver.linear_solver = scene_linear_solver(solver, "auto")
kin, free = solver.kin, solver.constraints.free
u = np.zeros(kin.ndof)
u[free] = 1e-5 * np.random.default_rng(0).standard_normal(free.size)
state = material.initial_state((kin.nel, kin.nqp))
ctx = StepContext(1, 0.1, 0.1, 0.1, 0.1, 0, u, u, state, np.zeros(kin.ndof))


def fastest(fn, repeat=6):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times[1:])


def evaluate():
    kin._memo[0] = None
    return solver.evaluate(u, state, ctx)


response, residual, *_ = evaluate()
_, K_II = solver.tangent(response, [], u, full=False)
rhs = -residual[free]
out = {"dofs": int(kin.ndof),
       "evaluate": fastest(evaluate),
       "material_tangent": fastest(lambda: material.update(state, solver.assembler.strain(u)).tangent),
       "element_tangents": fastest(lambda: kin.element_tangents(response.tangent, response.stress, u)),
       "tangent": fastest(lambda: solver.tangent(response, [], u, full=False)),
       # a load step's first correction factorises (within a step the inexact corrections reuse the factors)
       "factorise_solve": fastest(lambda: solver.linear_solver.solve(K_II, rhs))}


def after_factorising():
    solver.linear_solver.solve(K_II, rhs)
    t0 = time.perf_counter()
    kin.element_tangents(response.tangent, response.stress, u)
    return time.perf_counter() - t0


out["element_tangents_after_factorising"] = min(after_factorising() for _ in range(5))
print(json.dumps(out))
"""

RUN = r"""
import json, sys, time
from abrakit.scratch.run import run_scratch
from abrakit.scratch.scene import ScratchScene

t0 = time.perf_counter()
result = run_scratch(ScratchScene(mesh=sys.argv[1], slide=float(sys.argv[2])), vtu_every=0)
print(json.dumps({"wall_time_s": time.perf_counter() - t0, "newton_iterations": result.newton_iterations,
                  "dofs": result.summary()["dofs"]}))
"""

RUN_SCENE = {"mesh": "default", "slide": 0.02}
"""The whole run of the ``runs`` table (``--quick``: the same slide on the coarse mesh, below the vector length
where OpenBLAS splits its work, so the settings differ less)."""

LIBRARY_DEFAULTS = {"OMP_WAIT_POLICY": "ACTIVE", "KMP_BLOCKTIME": "200"}
_OURS = ("OMP_WAIT_POLICY", "KMP_BLOCKTIME", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS",
         "NUMBA_NUM_THREADS", "ABRAKIT_THREADS", "PYTEST_XDIST_WORKER_COUNT", "ABRAKIT_SET_THREADS")


def settings() -> dict[str, tuple[int, dict]]:
    """Name -> (processes at once, environment)."""
    cores = str(len(os.sched_getaffinity(0)))
    defaults = LIBRARY_DEFAULTS | {k: cores for k in _OURS[2:6]}
    return {
        "policy": (1, {}),
        "library defaults": (1, defaults),
        "one thread": (1, {"ABRAKIT_THREADS": "1"}),
        "2 workers, policy": (2, {"PYTEST_XDIST_WORKER_COUNT": "2"}),
        "2 workers, library defaults": (2, defaults),
    }


def run_settings() -> dict[str, dict]:
    """Name -> environment of the whole runs (one process each)."""
    cores = str(len(os.sched_getaffinity(0)))
    return {"policy": {}, "OpenBLAS as the other pools": {"OPENBLAS_NUM_THREADS": cores},
            "one thread": {"ABRAKIT_THREADS": "1"}}


def child_environment(env: dict) -> dict:
    """This process's environment without the thread settings (:data:`_OURS`), with a setting's ``env``."""
    return {k: v for k, v in os.environ.items() if k not in _OURS} | env


def measure_run(mesh: str, slide: float, env: dict) -> dict:
    """Wall time, Newton iterations and DOF of one whole scratch run in a fresh process."""
    out = subprocess.run([sys.executable, "-c", RUN, mesh, str(slide)], env=child_environment(env),
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def measure(mesh: str, processes: int, env: dict) -> dict:
    """The pieces' seconds, the mean over ``processes`` concurrent probes."""
    running = [subprocess.Popen([sys.executable, "-c", PROBE, mesh], env=child_environment(env),
                                stdout=subprocess.PIPE, text=True) for _ in range(processes)]
    results = [json.loads(p.communicate()[0].strip().splitlines()[-1]) for p in running]
    return {k: float(np.mean([r[k] for r in results])) for k in results[0]}


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    mesh = "coarse" if quick else "default"
    rows = []
    with CurveWriter(outdir / "threads.csv", ["setting", "processes", "dofs", *(f"{p}_ms" for p in PIECES)]) as w:
        for name, (processes, env) in settings().items():
            seconds = measure(mesh, processes, env)
            row = {"setting": name, "processes": processes, "dofs": seconds["dofs"],
                   **{f"{p}_ms": 1e3 * seconds[p] for p in PIECES}}
            w.write(**row)
            rows.append(row)
    per_iteration = {r["setting"]: r["evaluate_ms"] + r["tangent_ms"] + r["factorise_solve_ms"] for r in rows}
    run_mesh = "coarse" if quick else RUN_SCENE["mesh"]
    runs = [{"setting": name, "mesh": run_mesh, "slide_um": 1e3 * RUN_SCENE["slide"],
             **measure_run(run_mesh, RUN_SCENE["slide"], env)} for name, env in run_settings().items()]
    results = {"date": time.strftime("%Y-%m-%d %H:%M"), "host": platform.node(), "mesh": mesh, "rows": rows,
               "iteration_ms": per_iteration, "runs": runs,
               "summary": "; ".join(f"{k}: {v:.0f} ms per Newton iteration" for k, v in per_iteration.items())
               + "; whole runs: " + ", ".join(f"{r['setting']} {r['wall_time_s']:.0f} s" for r in runs)}
    write_json(outdir / "threads.json", results)
    plot(rows, runs, outdir / "threads.png")
    return results


def plot(rows, runs, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, (ax, ax_runs) = plt.subplots(1, 2, figsize=(11.0, 4.2), width_ratios=(2.2, 1.0))
    width = 0.8 / len(rows)
    x = np.arange(len(PIECES))
    for k, row in enumerate(rows):
        ax.bar(x + k * width, [row[f"{p}_ms"] for p in PIECES], width, label=row["setting"])
    ax.set_xticks(x + 0.4 - width / 2, [p.replace("_", " ") for p in PIECES], rotation=20, ha="right", fontsize=8)
    ax.set_ylabel("ms (fastest of five; mean over concurrent processes)")
    ax.set_title("One scratch Newton iteration's pieces under the thread settings")
    ax.legend(fontsize=8)
    ax_runs.barh([r["setting"] for r in runs], [r["wall_time_s"] for r in runs], color="0.5")
    ax_runs.set(xlabel="wall time [s]", title=f"Whole runs ({runs[0]['mesh']} mesh, {runs[0]['slide_um']:g} µm slide)")
    ax_runs.tick_params(axis="y", labelsize=8)
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="the coarse mesh instead of the default one")
