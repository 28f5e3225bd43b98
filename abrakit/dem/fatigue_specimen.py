"""A small bonded DEM specimen under cyclic load: the multi-bond check of the fatigue bond and its cycle jump.

:func:`bonded_bar` lays ``rows`` rows of ``columns`` disks on a hexagonal lattice (2D, unit thickness, as the paper's
PFC2D assemblies) and bonds every touching pair with :func:`~abrakit.dem.fatigue_bonds.install_fatigue_bonds`:
bonds along the rows are loaded in tension, the inclined ones in mixed mode. The left end is held, the right end
carries an applied force.

:func:`cyclic_bar` cycles that force between two levels, quasi-statically (local damping α = 0.7, Δt = C_s Δt_crit,
seed 002 Eq. 5–12), calls the fatigue update at each onset of unloading, and records the damage after every
simulated cycle, optionally writing each row to a CSV file as it is computed.
"""

from __future__ import annotations

import time

import numpy as np

from abrakit.dem.fatigue_bonds import install_fatigue_bonds
from abrakit.dem.simulation import Simulation
from abrakit.dem.state import Particles
from abrakit.fatigue.bond_law import BondParameters
from abrakit.io import RunRecord
from abrakit.validation import check_finite, check_integer, check_positive, check_range, number_arguments


@number_arguments
def bonded_bar(params: BondParameters | None = None, *, columns: int = 5, rows: int = 2, radius: float = 0.05,
               density: float = 2650.0, local_damping: float = 0.7, safety: float = 0.8, track_energy: bool = False):
    """A hexagonal bar of ``rows`` × ``columns`` disks of radius ``radius`` [m] with fatigue bonds of width 2r.

    Returns ``(sim, held, loaded)``: the simulation and the indices of the held (left) and loaded (right) disks.
    The energy account is off by default (a third of the step's time on this small assembly)."""
    params = BondParameters() if params is None else params
    if int(columns) < 2 or int(rows) < 1:
        raise ValueError(f"columns must be ≥ 2 and rows ≥ 1, got columns={columns}, rows={rows}")
    check_positive("radius", radius)
    row, col = np.divmod(np.arange(int(rows) * int(columns)), int(columns))
    xy = np.column_stack([2 * radius * (col + 0.5 * (row % 2)), np.sqrt(3) * radius * row])
    particles = Particles.disks(xy, radius, density, thickness=1.0, kn=params.kn * 2 * radius)
    held = np.flatnonzero(col == 0)
    loaded = np.flatnonzero(col == columns - 1)
    particles.fixed[held] = True
    sim = Simulation(particles, planar=True, local_damping=local_damping, safety=safety, skin=0.2 * radius,
                     track_energy=track_energy)
    install_fatigue_bonds(sim, params)
    sim.applied_force = np.zeros((len(particles), 3))
    return sim, held, loaded


def cyclic_bar(sim: Simulation, loaded, stress_min: float, stress_max: float, *, target_damage: float = 0.4,
               jump: float | None = None, ramp_steps: int = 400, max_cycles: int = 100_000, csv=None,
               time_limit: float | None = None) -> dict:
    """Cycle the nominal stress on the loaded disks between ``stress_min`` and ``stress_max`` [Pa] (force per disk =
    stress × 2r × 1 m) until the largest bond damage reaches ``target_damage``.

    Each cycle ramps up over ``ramp_steps`` steps, updates fatigue (with the cycle jump ``jump`` if given), and ramps
    down. Returns per simulated cycle the cycles represented (``cycles``), the largest and the mean damage and
    the extension of the loaded end at the peak, plus ``simulated_cycles``, ``steps`` and ``seconds``. With
    ``csv`` every row is written as soon as it is computed. Stops early (``"stopped"``: the reason) when a bond
    breaks, at ``max_cycles`` or after ``time_limit`` seconds."""
    check_range("stress_min", stress_min, 0.0, check_finite("stress_max", stress_max), high_open=True)
    check_range("target_damage", target_damage, 0.0, 1.0, low_open=True, high_open=True)
    if jump is not None:
        check_positive("jump", jump)
    check_integer("ramp_steps", ramp_steps, 1)
    check_integer("max_cycles", max_cycles, 1)
    if time_limit is not None:
        check_positive("time_limit", time_limit)
    loaded = np.asarray(loaded)
    p = sim.particles
    area = 2.0 * p.radius[loaded]
    start_x = p.x[loaded, 0].mean()
    record = RunRecord(("cycles", "max_damage", "mean_damage", "extension"), csv)
    clock, steps, cycles, stopped = time.perf_counter(), 0, 0, "target"

    def ramp(a, b):
        nonlocal steps
        for level in np.linspace(a, b, int(ramp_steps) + 1)[1:]:
            sim.applied_force[loaded, 0] = level * area
            sim.step()
        steps += int(ramp_steps)

    ramp(0.0, stress_min)
    sim.fatigue_bonds.restart_cycle()
    while sim.fatigue_bonds.damage.max(initial=0.0) < target_damage:
        ramp(stress_min, stress_max)
        extension = float(p.x[loaded, 0].mean() - start_x)
        cycles += sim.fatigue_bonds.onset_of_unloading(jump=jump, max_cycles=max_cycles - cycles)
        ramp(stress_max, stress_min)
        d = sim.fatigue_bonds.damage
        record.add(cycles=cycles, max_damage=float(d.max()) if len(d) else 1.0,
                   mean_damage=float(d.mean()) if len(d) else 1.0, extension=extension)
        if len(sim.cracks):
            stopped = "bond broken"
            break
        if cycles >= max_cycles:
            stopped = "max_cycles"
            break
        if time_limit is not None and time.perf_counter() - clock > time_limit:
            stopped = "time_limit"
            break
    record.close()
    result = record.arrays()
    result.update(simulated_cycles=len(record), steps=steps, seconds=time.perf_counter() - clock,
                  stopped=stopped)
    return result


@number_arguments
def history_deviation(run: dict, reference: dict, key: str = "max_damage", start: float | None = None) -> float:
    """Largest relative deviation of ``run[key]`` from ``reference[key]`` interpolated at the run's cycles (both
    :func:`cyclic_bar` results, or any dicts with ``"cycles"`` and ``key``); the reference starts at cycle 0 with
    ``start`` (default: its first value). Cycles beyond the reference's last are ignored."""
    if start is not None:
        check_finite("start", start)
    cycles = np.concatenate([[0.0], np.asarray(reference["cycles"], float)])
    values = np.asarray(reference[key], float)
    values = np.concatenate([[values[0] if start is None else start], values])
    n, v = np.asarray(run["cycles"], float), np.asarray(run[key], float)
    inside = n <= cycles[-1]
    if not inside.any():
        return float("nan")
    return float(np.max(np.abs(v[inside] / np.interp(n[inside], cycles, values) - 1.0)))
