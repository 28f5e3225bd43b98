"""DEM engine speed: particle-steps and contact-steps per second for dense packings of 10³, 10⁴ and 5·10⁴ spheres,
for the NumPy kernel and the optional numba kernel, and how the cost per step grows with N; plus speed against
error on the impact test (contact duration error vs run time as the step shrinks).

Run: ``python benchmarks/bench_dem.py [--quick]`` → ``benchmarks/results/dem.{csv,json,png}``.

Protocol per size: a jittered polydisperse FCC packing in a box of walls (:func:`abrakit.dem.dense_packing`) is
relaxed with local damping α = 0.7 until quiet; then each kernel runs the same quasi-static compression (top wall
moving in at 1 mm/s, α = 0.7, energy tracking off) and is timed over ``steps`` steps, neighbour-list rebuilds
included. Both wall-clock and CPU time are recorded (the machine may be shared); rates use the CPU time.
"""

from __future__ import annotations

import json
import pathlib
import time

import numpy as np
from _common import command_line, save_figure

from abrakit.dem import Simulation, Walls, dense_packing, two_sphere_impact
from abrakit.dem.kernels import HAVE_NUMBA
from abrakit.io import CurveWriter, write_json

SIZES = (1_000, 10_000, 50_000)
TARGET = 3e5          # required NumPy particle-steps/s on 10⁴ particles


def relaxed_packing(n: int, seed: int = 0):
    """Relax a dense packing (numba kernel if available: it only prepares the specimen)."""
    kernel = "numba" if HAVE_NUMBA else "numpy"
    sim = dense_packing(n, seed=seed, agitation=0.0, local_damping=0.7, kernel=kernel)
    for _ in range(20):
        builds = sim.neighbours.builds
        sim.run(100, progress=False)
        if sim.neighbours.builds - builds <= 2:
            break
    return sim


def clone(sim: Simulation, kernel: str) -> Simulation:
    """A fresh simulation on a copy of the relaxed state (same walls, same law) with the chosen kernel."""
    p = sim.particles.take(np.arange(len(sim.particles)))
    walls = Walls()
    for k in range(len(sim.walls)):
        walls.add(sim.walls.point[k], sim.walls.normal[k], kn=sim.walls.kn[k], kt=sim.walls.kt[k],
                  friction=sim.walls.friction[k], name=sim.walls.names[k])
    walls.box_axes = dict(sim.walls.box_axes)
    walls.velocity[walls.index("zmax")] = (0.0, 0.0, -1e-3)
    return Simulation(p, law=sim.law, walls=walls, local_damping=0.7, track_energy=False, kernel=kernel,
                      dt=sim.dt)


def time_kernel(base: Simulation, kernel: str, steps: int) -> dict:
    sim = clone(base, kernel)
    sim.run(5, progress=False)                                   # compile (numba) and first rebuild
    builds0 = sim.neighbours.builds
    touching = []
    wall0, cpu0 = time.perf_counter(), time.process_time()
    for _ in range(steps):
        sim.step()
        touching.append(int(np.count_nonzero(sim.contacts.overlap > 0)))
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    n = len(sim.particles)
    contacts = float(np.mean(touching))
    return {"study": "throughput", "kernel": kernel, "particles": n, "contacts": contacts,
            "candidates": len(sim.contacts), "steps": steps, "wall_s": wall, "cpu_s": cpu,
            "particle_steps_per_s": n * steps / cpu, "contact_steps_per_s": contacts * steps / cpu,
            "particle_steps_per_s_wall": n * steps / wall, "ms_per_step": 1e3 * cpu / steps,
            "rebuilds": sim.neighbours.builds - builds0, "coordination": 2 * contacts / n,
            "error": np.nan, "steps_per_contact": np.nan}


def impact_study(quick: bool) -> list[dict]:
    """Speed against error: contact duration and restitution of a damped impact (ζ = 0.3) vs run time."""
    rows = []
    for spc in (25, 50, 100, 200, 400) + (() if quick else (800, 1600)):
        cpu0 = time.process_time()
        r = two_sphere_impact(0.01, 2650.0, 1e5, 0.3, 1.0, steps_per_contact=spc)
        cpu = time.process_time() - cpu0
        rows.append({"study": "impact", "kernel": "numpy", "particles": 2, "contacts": 1.0, "candidates": 1,
                     "steps": int(2.5 * spc), "wall_s": np.nan, "cpu_s": cpu, "particle_steps_per_s": np.nan,
                     "contact_steps_per_s": np.nan, "particle_steps_per_s_wall": np.nan, "ms_per_step": np.nan,
                     "rebuilds": 0, "coordination": np.nan, "steps_per_contact": spc,
                     "error": abs(r["duration"] / r["duration_analytic"] - 1)})
    return rows


def plot(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    fig, (a, b, c) = plt.subplots(1, 3, figsize=(14, 4))
    for kernel, marker, color in (("numpy", "o", "C0"), ("numba", "s", "C3")):
        sel = [r for r in rows if r["study"] == "throughput" and r["kernel"] == kernel]
        if not sel:
            continue
        n = np.array([r["particles"] for r in sel])
        a.loglog(n, [r["particle_steps_per_s"] for r in sel], marker + "-", color=color,
                 label=f"{kernel}: particle-steps/s")
        a.loglog(n, [r["contact_steps_per_s"] for r in sel], marker + "--", color=color, mfc="none",
                 label=f"{kernel}: contact-steps/s")
        b.loglog(n, [r["ms_per_step"] for r in sel], marker + "-", color=color, label=kernel)
    a.axhline(TARGET, color="k", lw=0.8, ls=":", label="target 3·10⁵ (NumPy, N = 10⁴)")
    a.set_xlabel("particles N")
    a.set_ylabel("per second (CPU time)")
    a.legend(fontsize=7)
    a.set_title("throughput, dense packing")
    n_ref = np.array([1e3, 5e4])
    b.loglog(n_ref, 1e-3 * n_ref, "k:", lw=0.8, label="∝ N")
    b.set_xlabel("particles N")
    b.set_ylabel("ms per step")
    b.legend(fontsize=7)
    b.set_title("cost per step grows like N")
    sel = [r for r in rows if r["study"] == "impact"]
    c.loglog([r["cpu_s"] for r in sel], [r["error"] for r in sel], "o-")
    for r in sel:
        c.annotate(str(r["steps_per_contact"]), (r["cpu_s"], r["error"]), fontsize=7)
    c.xaxis.set_minor_formatter(NullFormatter())
    c.set_xlabel("run time [s]")
    c.set_ylabel("|duration error| (ζ = 0.3)")
    c.set_title("impact: error vs time (labels: steps/contact)")
    save_figure(fig, path)


def main(outdir: pathlib.Path = pathlib.Path(__file__).parent / "results", quick: bool = False) -> dict:
    outdir = pathlib.Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    sizes = SIZES[:2] if quick else SIZES
    steps = 50 if quick else 200
    kernels = ("numpy", "numba") if HAVE_NUMBA else ("numpy",)
    columns = ["study", "kernel", "particles", "contacts", "candidates", "steps", "wall_s", "cpu_s",
               "particle_steps_per_s", "contact_steps_per_s", "particle_steps_per_s_wall", "ms_per_step",
               "rebuilds", "coordination", "steps_per_contact", "error"]
    rows = []
    with CurveWriter(outdir / "dem.csv", columns) as out:
        for n in sizes:
            base = relaxed_packing(n)
            for kernel in kernels:
                row = time_kernel(base, kernel, steps)
                rows.append(row)
                out.write(**row)
                print(f"N = {row['particles']:6d} {kernel:5s}: {row['particle_steps_per_s']:.3g} particle-steps/s, "
                      f"{row['contact_steps_per_s']:.3g} contact-steps/s, {row['ms_per_step']:.2f} ms/step "
                      f"(wall {row['particle_steps_per_s_wall']:.3g}/s), {row['rebuilds']} rebuilds, "
                      f"Z = {row['coordination']:.2f}", flush=True)
        for row in impact_study(quick):
            rows.append(row)
            out.write(**row)
    summary = {"target_numpy_particle_steps_per_s_at_1e4": TARGET, "sizes": list(sizes), "steps": steps}
    for kernel in kernels:
        sel = [r for r in rows if r["study"] == "throughput" and r["kernel"] == kernel]
        n = np.array([r["particles"] for r in sel], float)
        cost = np.array([r["ms_per_step"] for r in sel])
        summary[kernel] = {str(r["particles"]): {k: r[k] for k in ("particle_steps_per_s", "contact_steps_per_s",
                                                                 "ms_per_step", "rebuilds", "coordination")}
                           for r in sel}
        summary[kernel]["cost_exponent"] = float(np.polyfit(np.log(n), np.log(cost), 1)[0])
    at_1e4 = [r for r in rows if r["study"] == "throughput" and r["kernel"] == "numpy" and r["particles"] == 10_000]
    summary["numpy_at_1e4"] = at_1e4[0]["particle_steps_per_s"] if at_1e4 else None
    summary["target_met"] = bool(at_1e4 and at_1e4[0]["particle_steps_per_s"] >= TARGET)
    summary["impact_error_vs_time"] = [(r["steps_per_contact"], r["cpu_s"], r["error"]) for r in rows
                                       if r["study"] == "impact"]
    write_json(outdir / "dem.json", summary)
    plot(rows, outdir / "dem.png")
    print(json.dumps({k: summary[k] for k in ("numpy_at_1e4", "target_met")}))
    return summary


if __name__ == "__main__":
    command_line(main, __doc__, quick_help="10³ and 10⁴ particles, fewer steps")
