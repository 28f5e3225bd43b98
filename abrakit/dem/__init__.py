"""A readable discrete element engine (Ch. 4.1): spheres, contact laws, bonds, walls, clumps, leap-frog.

The calculation cycle of Fig. 4.1 is :meth:`Simulation.step`; every stage is a small module:

========================  =====================================================================
:mod:`.state`             particles and contacts as structure-of-arrays
:mod:`.neighbours`        Verlet list from ``cKDTree``, history kept across rebuilds
:mod:`.contact_laws`      linear and Hertz–Mindlin laws, slip, dashpots (Eq. 4.6–4.14)
:mod:`.bonds`             contact and parallel bonds, crack records
:mod:`.fatigue_bonds`     the damage-plasticity fatigue bond of seed 002 (law in :mod:`abrakit.fatigue`)
:mod:`.fatigue_specimen`  a small bonded bar under cyclic load, with the cycle jump
:mod:`.walls`             planar walls, prescribed velocity, servo
:mod:`.integrate`         leap-frog, local damping, critical time step (seed 002 Eq. 5–12)
:mod:`.clumps`            rigid multi-sphere grains
:mod:`.measure`           wall and Love–Weber stress, strain, coordination, energy balance
:mod:`.output`            VTU snapshots and CSV histories
:mod:`.scenes`            verification scenes with analytic answers
:mod:`.simulation`        the cycle itself: :class:`Simulation` and its ``step``
:mod:`.kernels`           optional numba loop for the linear law (``Simulation(kernel="numba")``)
========================  =====================================================================
"""

from __future__ import annotations

from abrakit.dem.bonds import (
    CrackLog,
    ParallelBonds,
    install_contact_bonds,
    install_parallel_bonds,
)
from abrakit.dem.clumps import Clumps, clump_particles, dyad, make_clumps, peanut
from abrakit.dem.contact_laws import (
    ContactForces,
    HertzMindlin,
    Linear,
    force_displacement,
    hertz_normal_coefficient,
    hertz_shear_coefficient,
    series_stiffness,
)
from abrakit.dem.fatigue_bonds import FatigueBonds, install_fatigue_bonds
from abrakit.dem.fatigue_specimen import bonded_bar, cyclic_bar
from abrakit.dem.integrate import critical_time_step, local_damping
from abrakit.dem.measure import (
    box_strain,
    contact_density,
    coordination_number,
    energy_balance,
    kinetic_energy,
    love_weber_stress,
    porosity,
    relax,
    unbalanced_force_ratio,
    wall_stress,
)
from abrakit.dem.neighbours import VerletList, candidate_pairs
from abrakit.dem.network import affine_stiffness, network_stiffness
from abrakit.dem.output import HistoryWriter, VtuWriter, callbacks
from abrakit.dem.periodic import ElasticConstants, Periodic, elastic_probe
from abrakit.dem.scenes import (
    bonded_chain_wave,
    bonded_pair,
    dense_packing,
    impact_analytic,
    rolling_sphere,
    settling,
    sphere_wall_impact,
    two_sphere_impact,
)
from abrakit.dem.simulation import EnergyAccount, ParticleEscapeError, Simulation, TimeStepError
from abrakit.dem.state import ContactSet, Particles
from abrakit.dem.walls import Servo, Walls

__all__ = [
    "Clumps", "ContactForces", "ContactSet", "CrackLog", "ElasticConstants", "EnergyAccount", "FatigueBonds",
    "HertzMindlin", "HistoryWriter", "Linear", "ParallelBonds", "ParticleEscapeError", "Particles", "Periodic", "Servo",
    "Simulation", "TimeStepError", "VerletList", "VtuWriter", "Walls", "affine_stiffness", "bonded_bar",
    "bonded_chain_wave", "bonded_pair", "box_strain", "callbacks", "candidate_pairs", "clump_particles",
    "contact_density", "coordination_number", "critical_time_step", "cyclic_bar", "demo", "dense_packing", "dyad",
    "elastic_probe", "energy_balance", "force_displacement", "hertz_normal_coefficient", "hertz_shear_coefficient",
    "impact_analytic", "install_contact_bonds", "install_fatigue_bonds", "install_parallel_bonds", "kinetic_energy",
    "local_damping", "love_weber_stress", "make_clumps", "network_stiffness",
    "peanut", "porosity", "relax", "rolling_sphere", "series_stiffness", "settling", "sphere_wall_impact",
    "two_sphere_impact", "unbalanced_force_ratio", "wall_stress"
]


def demo() -> str:
    """Impact, rolling and wave tests against their closed forms, and the speed on a small dense packing."""
    import time

    lines = ["A readable DEM (Ch. 4.1): verification scenes vs closed form"]
    for label, kw in (("dashpot zeta=0.2", {"damping_ratio": 0.2}), ("local damping alpha=0.3",
                                                                     {"local_damping": 0.3})):
        r = two_sphere_impact(0.01, 2650.0, 1e5, velocity=1.0, **kw)
        lines.append(f"two-sphere impact, {label}: duration {r['duration'] * 1e3:.4f} ms "
                     f"(analytic {r['duration_analytic'] * 1e3:.4f}), restitution {r['restitution']:.4f} "
                     f"(analytic {r['restitution_analytic']:.4f})")
    roll = rolling_sphere()
    lines.append(f"rolling sphere: t* = {roll['t_star'] * 1e3:.2f} ms (2v0/(7 mu g) = "
                 f"{roll['t_star_analytic'] * 1e3:.2f}), v* = {roll['v_star']:.4f} m/s (5v0/7 = "
                 f"{roll['v_star_analytic']:.4f})")
    wave = bonded_chain_wave(120, width=10.0)
    lines.append(f"bonded chain: wave speed {wave['speed']:.3f} m/s (l sqrt(k/m) = {wave['speed_analytic']:.3f})")
    sim = dense_packing(2000, seed=0, agitation=0.0, local_damping=0.7)
    sim.run(20, progress=False)
    start = time.process_time()
    sim.run(50, progress=False)
    rate = 50 * len(sim.particles) / (time.process_time() - start)
    lines.append(f"dense packing of {len(sim.particles)} spheres: {rate:.3g} particle-steps/s (NumPy kernel), "
                 f"coordination {coordination_number(sim):.2f}")
    return "\n".join(lines)
