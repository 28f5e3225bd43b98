"""Poly-disperse disk packings for bonded 2D specimens: an aggregate grading, radius expansion in a box, and a
packing brought to a small confining stress before it is bonded.

The grading is Fuller's curve, the classical maximum-density grading of concrete and asphalt aggregates: the area
(2D mass) fraction of particles finer than r is P(r) = (r/r_max)^q with q = 1/2. Truncated to [r_min, r_max] it
reads P(r) = (r^q − r_min^q)/(r_max^q − r_min^q), and the number density of the radii is ∝ r^(q−3), which
:func:`fuller_radii` samples by inversion.

:func:`disk_packing` is the genesis of PFC-style specimens (seed 002 Sec. 5.1: "randomly distributed in the
sample domain and allowed to rearrange until reaching an equilibrium condition"): the disks are placed at half
size without overlaps in a box of frictionless walls, grown in stages to a solid fraction above jamming, relaxed,
and shrunk together until the mean wall stress falls to the requested small ``stress``. Bonds installed on this
packing (gaps below a tolerance) then start from a nearly stress-free, jammed skeleton.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from abrakit.dem.measure import relax
from abrakit.dem.simulation import Simulation
from abrakit.dem.state import Particles
from abrakit.dem.walls import Walls
from abrakit.experiments.specimen import random_placement
from abrakit.validation import check_positive, check_range, number_arguments


def _check_grading(smallest, largest, exponent):
    check_positive("smallest", smallest)
    check_range("largest", largest, smallest, None, low_open=True)
    return check_range("exponent", exponent, 0.0, 2.0, low_open=True, high_open=True)


@number_arguments
def fuller_passing(radius: ArrayLike, smallest: float, largest: float, exponent: float = 0.5):
    """Area fraction of the grading finer than ``radius``: (r^q − r_min^q)/(r_max^q − r_min^q), clipped to [0, 1]."""
    q = _check_grading(smallest, largest, exponent)
    r = np.clip(np.asarray(radius, float), smallest, largest)
    return (r**q - smallest**q) / (largest**q - smallest**q)


def fuller_radii(rng, smallest: float, largest: float, area: float, *, exponent: float = 0.5) -> np.ndarray:
    """Radii drawn from the truncated Fuller grading (number density ∝ r^(q−3) on [``smallest``, ``largest``]) until
    their disks' total area π Σ r² first reaches ``area`` [m²]."""
    q = _check_grading(smallest, largest, exponent)
    check_positive("area", area)
    a, b = smallest ** (q - 2.0), largest ** (q - 2.0)
    mean_area = np.pi * (largest**q - smallest**q) / q / ((b - a) / (q - 2.0))
    radii = np.zeros(0)
    while np.pi * np.sum(radii**2) < area:
        u = rng.random(int(1.2 * area / mean_area) + 16)
        radii = np.concatenate([radii, (a + u * (b - a)) ** (1.0 / (q - 2.0))])
    return radii[: int(np.searchsorted(np.cumsum(np.pi * radii**2), area)) + 1]


def wall_stress(sim: Simulation, thickness: float) -> float:
    """Mean compressive stress on the four in-plane walls of a planar box [Pa]: force per edge length ×
    ``thickness``."""
    check_positive("thickness", thickness)
    lengths = sim.walls.box_lengths()
    stress = [sim.walls.normal_force(k) / (lengths[1 - a] * thickness)
              for a, axis in enumerate("xy") for k in sim.walls.box_axes[axis]]
    return float(np.mean(stress))


def disk_packing(size, radii, rng, *, modulus: float, thickness: float, stress: float, density: float = 2400.0,
                 solid_fraction: float = 0.87, expansion_steps: int = 4, tolerance: float = 0.2,
                 max_rounds: int = 40) -> dict:
    """A jammed packing of disks ``radii`` in the box [0, size[0]] × [0, size[1]] at mean wall stress ≈ ``stress``.

    The radii are first scaled so that their area is ``solid_fraction`` of the box (above jamming), placed at half
    that size, grown in ``expansion_steps`` stages and relaxed with frictionless contacts of stiffness
    ``modulus`` × ``thickness`` (the deformable method's contact, the bonds' modulus); the disks are then shrunk
    together, by the overlap the excess stress implies (Δr/r ≈ (σ − σ₀)/E), until the wall stress is within
    ``tolerance`` (relative) of ``stress``. Returns ``xy``, ``radius``, the final ``stress``, ``solid_fraction``,
    ``rounds`` and ``steps``."""
    size = np.asarray(size, float)
    if size.shape != (2,):
        raise ValueError(f"size must be (length, height), got shape {size.shape}")
    for name, value in (("modulus", modulus), ("thickness", thickness), ("stress", stress), ("density", density)):
        check_positive(name, value)
    check_range("solid_fraction", solid_fraction, 0.0, 0.95, low_open=True)
    radii = np.asarray(radii, float) * np.sqrt(solid_fraction * np.prod(size) / (np.pi * np.sum(radii**2)))
    xy = random_placement(rng, 0.5 * radii, size)
    particles = Particles.disks(xy, 0.5 * radii, density, thickness=thickness, kn=modulus * thickness, friction=0.0)
    sim = Simulation(particles, planar=True, walls=Walls.box((0.0, 0.0, -1.0), (size[0], size[1], 1.0)),
                     local_damping=0.7, track_energy=False)
    steps = 0
    for _ in range(int(expansion_steps)):
        sim.scale_radii(2.0 ** (1.0 / expansion_steps))
        steps += relax(sim, min_steps=500, max_steps=5000)["steps"]
    rounds, slope, previous = 0, 2.0 * modulus, None      # slope: dσ/d(ln r), first guessed, then secant
    while True:
        steps += relax(sim, tolerance=1e-3, min_steps=500, max_steps=20_000)["steps"]
        current = wall_stress(sim, thickness)
        if abs(current - stress) <= tolerance * stress or rounds >= max_rounds:
            break
        if previous is not None and previous[0] != current:
            slope = max((previous[0] - current) / previous[1], 1e-3 * modulus)
        shrink = min((current - stress) / slope, 0.01)          # at most 1 % per round
        previous, rounds = (current, shrink), rounds + 1
        sim.scale_radii(np.exp(-shrink))
    p = sim.particles
    if abs(current - stress) > tolerance * stress:
        raise RuntimeError(f"the packing did not settle at {stress:g} Pa in {max_rounds} rounds (now {current:g} Pa)")
    return {"xy": p.x[:, :2].copy(), "radius": p.radius.copy(), "stress": current, "rounds": rounds, "steps": steps,
            "solid_fraction": float(np.pi * np.sum(p.radius**2) / np.prod(size))}
