"""Cost of the fatigue beam's cycles against the number of disks, with the compiled bond update and without.

Issue 37: the bond update was about half of a 0.7–0.9 ms step on the 98-disk beam, all NumPy call overhead. With
numba installed :meth:`abrakit.dem.fatigue_bonds.FatigueBonds.update` takes the kinematics, the elastic trial and the
yield test in one compiled loop (:func:`abrakit.dem.kernels.fatigue_bond_trial`) and returns only the yielding
bonds through :func:`abrakit.fatigue.bond_law.plastic_return`.

Per lattice beam (largest radius 5, 3.5, 2.5 and 1.75 mm; 5 and 3.5 with ``--quick``), force-controlled at 90 N
(about 40 % of the 5 mm beam's P_max, elastic but for a few bonds), one haversine cycle of 2000 steps each way:
disks, bonds, the wall time per step and per cycle with the NumPy and the compiled update (the faster of two
cycles after a warm-up), the speed-up, and the largest difference of the peak deflection between the two paths
(they agree to the return's tolerance, 10⁻¹¹ measured; ``tests/test_fatigue_dem.py`` pins it). The monotonic and
fatigue studies of ``bench_fatigue_beam.py`` read their stored runs, made with the NumPy update.

The elastic cycles hardly yield. Where bonds yield, the return map dominates: per lattice beam (5 and 3.5 mm; 5 with
``--quick``) a monotonic test to 70 % of its peak with the NumPy update, the compiled trial with the NumPy return,
and the compiled trial and return (:mod:`abrakit.fatigue._return_kernel`): wall time, steps, ms per step, FS_max and
its deviation from the NumPy path's, and the largest deviation of the load curve up to the peak, relative to the
peak (the compiled return stops each bond at its own tolerance, so the paths agree to the tolerance amplified by
the softening, not to round-off).

The whole step of the beam on the rocker fixture (the S–N study's set-up): per lattice beam, one cycle at 40 N
(seating load 10 %) with every piece on its NumPy path (the contacts and leap-frog, the bond update, the pair
loads' sums, the pads' contacts) and with every piece compiled (:data:`~abrakit.experiments.bending.BEAM_KERNEL`,
:data:`~abrakit.dem.fatigue_bonds.COMPILED_UPDATE`, :data:`~abrakit.dem.simulation.COMPILED_SCATTER`,
:data:`~abrakit.experiments.rollers.COMPILED_CONTACTS`), and on the Fuller-graded 6 mm beam (seed 0) too.

Writes ``fatigue_bond_kernel.csv``, ``fatigue_bond_kernel_step.csv``, ``fatigue_bond_kernel.json`` and
``fatigue_bond_kernel.png``.

    python benchmarks/bench_fatigue_bond_kernel.py [--quick] [--outdir DIR]
"""

from __future__ import annotations

import platform
import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from _common import command_line, save_figure

from abrakit.dem import fatigue_bonds, simulation
from abrakit.dem.kernels import HAVE_NUMBA
from abrakit.experiments import rollers
from abrakit.experiments.bending import BeamSpec, four_point_beam, monotonic_bending
from abrakit.experiments.cyclic import cyclic_bending
from abrakit.io import CurveWriter, write_json

NAME = "fatigue_bond_kernel"
LOAD = 90.0              # N
STEPS_PER_CYCLE = 2000
COLUMNS = ("radius_mm", "disks", "bonds", "ms_per_step_numpy", "ms_per_step_compiled", "s_per_cycle_numpy",
           "s_per_cycle_compiled", "speedup", "deflection_difference")


def one_cycle(radius: float, compiled: bool) -> tuple[float, float, int, int]:
    """Seconds per cycle (best of two after a warm-up cycle) and the first cycle's peak deflection."""
    fatigue_bonds.COMPILED_UPDATE = compiled
    beam = four_point_beam(BeamSpec(radius=radius), control="force", fixture="pads")
    run = lambda: cyclic_bending(beam, LOAD, steps_per_cycle=STEPS_PER_CYCLE, max_simulated=1,
                                 quasi_static_check=False)
    first = run()
    times = []
    for _ in range(2):
        tic = time.perf_counter()
        run()
        times.append(time.perf_counter() - tic)
    return min(times), float(first["deflection"][0]), len(beam.sim.particles), len(beam.sim.fatigue_bonds)


MONOTONIC_COLUMNS = ("radius_mm", "path", "seconds", "steps", "ms_per_step", "FS_max", "FS_max_deviation",
                     "curve_deviation")
PATHS = {"numpy": (False, False), "compiled trial": (True, False), "compiled trial and return": (True, True)}


def monotonic(radius: float, path: str) -> dict:
    """The monotonic test to 70 % of the peak on one update path: time, steps and the load curve."""
    fatigue_bonds.COMPILED_UPDATE, fatigue_bonds.COMPILED_RETURN = PATHS[path]
    beam = four_point_beam(BeamSpec(radius=radius), fixture="pads")
    r = monotonic_bending(beam, record_every=200, drop=0.7)
    return {"radius_mm": radius * 1e3, "path": path, "seconds": r["seconds"], "steps": r["steps"],
            "ms_per_step": 1e3 * r["seconds"] / r["steps"], "FS_max": r["FS_max"], "load": r["load"]}


def monotonic_study(radii) -> list[dict]:
    rows = []
    for radius in radii:
        runs = [monotonic(radius, path) for path in PATHS]
        reference = runs[0]["load"]
        peak = int(np.argmax(reference))
        for run in runs:
            load = run.pop("load")
            n = min(peak + 1, len(load))
            run["FS_max_deviation"] = run["FS_max"] / runs[0]["FS_max"] - 1.0
            run["curve_deviation"] = float(np.max(np.abs(load[:n] - reference[:n])) / reference[peak])
            rows.append(run)
    return rows


STEP_COLUMNS = ("beam", "disks", "bonds", "ms_per_step_numpy", "ms_per_step_compiled", "speedup",
                "s_per_8000_step_cycle")
ROCKER_LOAD = 40.0       # N, about a third of the 5 mm lattice's P_max on rockers


def compile_everything(compiled: bool) -> None:
    """Every piece of the beam's step on its compiled path or on its NumPy path."""
    fatigue_bonds.COMPILED_UPDATE = fatigue_bonds.COMPILED_RETURN = compiled
    simulation.COMPILED_SCATTER = rollers.COMPILED_CONTACTS = compiled


def whole_step(spec: BeamSpec, compiled: bool) -> tuple[float, int, int]:
    """Seconds of one 2000-step cycle on rockers (best of two after a warm-up), every piece compiled or not."""
    compile_everything(compiled)
    beam = four_point_beam(spec, control="force", fixture="rockers")
    beam.sim.kernel = "numba" if compiled else "numpy"
    run = lambda: cyclic_bending(beam, ROCKER_LOAD, load_min_ratio=0.1, steps_per_cycle=STEPS_PER_CYCLE,
                                 max_simulated=1, quasi_static_check=False)
    run()
    times = []
    for _ in range(2):
        tic = time.perf_counter()
        run()
        times.append(time.perf_counter() - tic)
    return min(times), len(beam.sim.particles), len(beam.sim.fatigue_bonds)


def step_study(radii) -> list[dict]:
    rows = []
    specs = [(f"lattice {r * 1e3:.2f} mm", BeamSpec(radius=r)) for r in radii]
    specs.append(("Fuller 6 mm, seed 0", BeamSpec(radius=6e-3, grading="fuller")))
    try:
        for name, spec in specs:
            numpy_s, disks, bonds = whole_step(spec, compiled=False)
            compiled_s, _, _ = whole_step(spec, compiled=True)
            rows.append({"beam": name, "disks": disks, "bonds": bonds,
                         "ms_per_step_numpy": 1e3 * numpy_s / STEPS_PER_CYCLE,
                         "ms_per_step_compiled": 1e3 * compiled_s / STEPS_PER_CYCLE, "speedup": numpy_s / compiled_s,
                         "s_per_8000_step_cycle": 4 * compiled_s})
    finally:
        compile_everything(HAVE_NUMBA)
    return rows


def main(outdir: Path, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    if not HAVE_NUMBA:
        raise SystemExit("this benchmark compares the compiled bond update with NumPy's: pip install abrakit[fast]")
    radii = (5e-3, 3.5e-3) if quick else (5e-3, 3.5e-3, 2.5e-3, 1.75e-3)
    rows = []
    writer = CurveWriter(outdir / f"{NAME}.csv", COLUMNS)
    try:
        for radius in radii:
            numpy_s, numpy_d, disks, bonds = one_cycle(radius, compiled=False)
            compiled_s, compiled_d, _, _ = one_cycle(radius, compiled=True)
            row = {"radius_mm": radius * 1e3, "disks": disks, "bonds": bonds,
                   "ms_per_step_numpy": 1e3 * numpy_s / STEPS_PER_CYCLE,
                   "ms_per_step_compiled": 1e3 * compiled_s / STEPS_PER_CYCLE, "s_per_cycle_numpy": numpy_s,
                   "s_per_cycle_compiled": compiled_s, "speedup": numpy_s / compiled_s,
                   "deflection_difference": abs(compiled_d - numpy_d) / abs(numpy_d)}
            writer.write(**row)
            rows.append(row)
        monotonic_rows = monotonic_study((5e-3,) if quick else (5e-3, 3.5e-3))
        step_rows = step_study(radii)
    finally:
        writer.close()
        fatigue_bonds.COMPILED_UPDATE = fatigue_bonds.COMPILED_RETURN = HAVE_NUMBA
    with CurveWriter(outdir / f"{NAME}_monotonic.csv", MONOTONIC_COLUMNS) as monotonic_csv:
        for r in monotonic_rows:
            monotonic_csv.write(**r)
    with CurveWriter(outdir / f"{NAME}_step.csv", STEP_COLUMNS) as step_csv:
        for r in step_rows:
            step_csv.write(**r)
    result = {"rows": rows, "monotonic": monotonic_rows, "step": step_rows, "load_N": LOAD,
              "steps_per_cycle": STEPS_PER_CYCLE, "quick": quick, "machine": platform.platform(), "numba": HAVE_NUMBA}
    write_json(outdir / f"{NAME}.json", result)
    fig, ax = plt.subplots(figsize=(6, 4))
    disks = [r["disks"] for r in rows]
    ax.loglog(disks, [r["ms_per_step_numpy"] for r in rows], "o-", label="NumPy bond update")
    ax.loglog(disks, [r["ms_per_step_compiled"] for r in rows], "s-", label="compiled bond update")
    lattice = [r for r in step_rows if r["beam"].startswith("lattice")]
    for key, marker, label in (("ms_per_step_numpy", "^--", "rockers, every piece NumPy"),
                               ("ms_per_step_compiled", "v--", "rockers, every piece compiled")):
        ax.loglog([r["disks"] for r in lattice], [r[key] for r in lattice], marker, label=label)
    ax.set(xlabel="disks", ylabel="wall time per step [ms]", title="fatigue beam: cost per step (one cycle = 2000)")
    ax.legend()
    save_figure(fig, outdir / f"{NAME}.png")
    result["summary"] = "\n".join(
        f"{r['radius_mm']:.2f} mm: {r['disks']} disks, {r['bonds']} bonds: {r['ms_per_step_numpy']:.3f} -> "
        f"{r['ms_per_step_compiled']:.3f} ms/step ({r['speedup']:.2f}x), {r['s_per_cycle_compiled']:.2f} s/cycle, "
        f"peak deflection {r['deflection_difference']:.1e} apart" for r in rows) + "\n" + "\n".join(
        f"monotonic {r['radius_mm']:.1f} mm, {r['path']}: {r['seconds']:.1f} s, {r['steps']} steps, "
        f"{r['ms_per_step']:.3f} ms/step, FS_max {r['FS_max'] / 1e3:.2f} kPa ({r['FS_max_deviation']:+.1e}), "
        f"load curve to the peak within {r['curve_deviation']:.1e}" for r in monotonic_rows) + "\n" + "\n".join(
        f"rockers, {r['beam']}: {r['disks']} disks, {r['ms_per_step_numpy']:.3f} -> {r['ms_per_step_compiled']:.3f} "
        f"ms/step ({r['speedup']:.2f}x), {r['s_per_8000_step_cycle']:.2f} s per 8000-step cycle" for r in step_rows)
    return result


if __name__ == "__main__":
    command_line(main, __doc__)
