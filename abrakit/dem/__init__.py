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

from abrakit.dem.bonds import install_contact_bonds
from abrakit.dem.clumps import clump_particles, dyad
from abrakit.dem.contact_laws import (
    HertzMindlin,
    Linear,
    force_displacement,
    hertz_normal_coefficient,
    series_stiffness,
)
from abrakit.dem.fatigue_specimen import bonded_bar, cyclic_bar, history_deviation
from abrakit.dem.measure import (
    contact_counts,
    coordination_number,
    energy_balance,
    porosity,
    relax,
    unbalanced_force_ratio,
)
from abrakit.dem.network import network_stiffness
from abrakit.dem.periodic import Periodic, elastic_probe
from abrakit.dem.scenes import (
    bonded_chain_wave,
    bonded_pair,
    dense_packing,
    rolling_sphere,
    settling,
    two_sphere_impact,
)
from abrakit.dem.simulation import Simulation, TimeStepError
from abrakit.dem.state import Particles
from abrakit.dem.walls import Walls

__all__ = [
    # the engine
    "Simulation", "Particles", "Walls", "Periodic", "Linear", "HertzMindlin", "install_contact_bonds", "TimeStepError",
    # grains of several spheres
    "clump_particles", "dyad",
    # contact laws, Eq. (4.6)-(4.14)
    "force_displacement", "series_stiffness", "hertz_normal_coefficient",
    # measurements
    "coordination_number", "contact_counts", "porosity", "energy_balance", "relax",
    "unbalanced_force_ratio", "elastic_probe", "network_stiffness",
    # verification scenes with analytic answers
    "two_sphere_impact", "rolling_sphere", "bonded_chain_wave", "bonded_pair", "settling", "dense_packing",
    # the fatigue bar of seed 002
    "bonded_bar", "cyclic_bar", "history_deviation",
]
