"""A periodic cell for the DEM and the elastic probe that measures E and ν of a packing in it.

Walls bias the elastic constants of a small specimen: the particles next to a flat wall are packed and loaded
differently from those inside. LAMMPS, YADE and LIGGGHTS users therefore measure them in a *periodic cell*: no
boundary at all, the packing repeats itself, and a homogeneous strain is applied to the cell and to every particle
position (affinely) before the packing relaxes.

:class:`Periodic` is an orthogonal cell ``[lower, lower + lengths)``, periodic in x, y and z. Branch vectors follow
the minimum-image convention, d = x_j − x_i − L round((x_j − x_i)/L) per axis, and the candidate pairs come from
``scipy.spatial.cKDTree(boxsize=L)``; positions are wrapped into the cell whenever the Verlet list is rebuilt.
Normal strains of the cell (``Periodic.strain``) are enough for an isotropic packing: no shear of the cell, so no
Lees–Edwards boundary.

:func:`elastic_probe` applies ε_aa = +δ along each axis in turn, relaxes, and reads the change of the Love–Weber stress:
C11 = Δσ_aa/δ and C12 = mean of the two lateral Δσ/δ, averaged over the three axes; for an isotropic packing

    E = (C11 − C12)(C11 + 2 C12)/(C11 + C12),        ν = C12/(C11 + C12).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from abrakit.validation import check_positive

__all__ = ["ElasticConstants", "Periodic", "elastic_probe"]


@dataclass
class Periodic:
    """Orthogonal periodic cell ``[lower, lower + lengths)`` [m], periodic along x, y and z."""

    lengths: np.ndarray
    lower: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        self.lengths = np.array(self.lengths, dtype=float).reshape(-1)
        self.lower = np.array(self.lower, dtype=float).reshape(-1)
        if self.lengths.shape != (3,) or self.lower.shape != (3,):
            raise ValueError(f"lengths and lower must have 3 entries (x, y, z), got {self.lengths.shape} and "
                             f"{self.lower.shape}")
        if not np.all(np.isfinite(self.lengths)) or np.any(self.lengths <= 0):
            raise ValueError(f"lengths must be finite and positive, got {self.lengths.tolist()}")

    @property
    def volume(self) -> float:
        return float(np.prod(self.lengths))

    def wrap(self, x: np.ndarray) -> None:
        """Move positions ``(N, 3)`` into the cell, in place."""
        x[:] = self.lower + np.mod(x - self.lower, self.lengths)
        x[:] = np.where(x >= self.lower + self.lengths, self.lower, x)   # mod may round up to L

    def minimum_image(self, d: np.ndarray, axis: int = -1) -> np.ndarray:
        """Branch vectors reduced to their nearest periodic image; components along ``axis`` (``(K, 3)`` by
        default, ``axis=0`` for the simulation's ``(3, K)`` contact arrays)."""
        L = self.lengths if axis in (-1, d.ndim - 1) else self.lengths.reshape((3,) + (1,) * (d.ndim - 1 - axis))
        return d - L * np.round(d / L)

    def check_range(self, interaction: float) -> None:
        """The minimum image is unique only if every interaction is shorter than half the cell."""
        if np.any(self.lengths <= 2.0 * interaction):
            raise ValueError(f"the periodic cell {self.lengths.tolist()} m must be longer than twice the largest "
                             f"interaction distance (2 r_max + skin = {interaction:.4g} m) along every axis")

    def strain(self, x: np.ndarray, strain) -> None:
        """Homogeneous normal strain ``(ε_xx, ε_yy, ε_zz)`` of the cell, applied affinely to the positions."""
        eps = np.broadcast_to(np.asarray(strain, dtype=float), (3,))
        if np.any(eps <= -1.0):
            raise ValueError(f"strain must be above -1 along every axis, got {eps.tolist()}")
        x[:] = self.lower + (x - self.lower) * (1.0 + eps)
        self.lengths = self.lengths * (1.0 + eps)


class ElasticConstants(NamedTuple):
    """Elastic constants of a packing from :func:`elastic_probe` [Pa] (ν dimensionless)."""

    E: float
    nu: float
    C11: float
    C12: float
    C11_axes: np.ndarray      # (3,) the probe along x, y, z: their spread measures the anisotropy
    C12_axes: np.ndarray


def elastic_probe(sim, strain: float = 1e-6, *, max_steps: int = 20_000, tol: float = 1e-6) -> ElasticConstants:
    """E and ν of the packing in ``sim`` (periodic, equilibrated) by small normal strains of its cell.

    For each axis a: relax, read σ⁰, strain the cell by ε_aa = ``strain`` (affinely), relax again (at most
    ``max_steps`` steps, until the unbalanced-force ratio (:func:`~abrakit.dem.measure.unbalanced_force_ratio`)
    is below ``tol``; use local damping), read σ¹, and go back to the starting state. C11 = (σ¹ − σ⁰)_aa/ε,
    C12 = mean of the lateral (σ¹ − σ⁰)/ε; the returned E and ν are from the axis means (module doc). Stresses
    are the Love–Weber averages
    over the cell, tension positive.
    """
    from abrakit.dem.measure import love_weber_stress, relax

    if sim.periodic is None:
        raise ValueError("elastic_probe needs a periodic simulation (Simulation(..., periodic=Periodic(...)))")
    check_positive("strain", strain)
    C11, C12 = np.zeros(3), np.zeros(3)
    for axis in range(3):
        snapshot = sim.snapshot()
        relax(sim, tolerance=tol, min_steps=0, max_steps=max_steps, check_every=50)
        sigma0 = love_weber_stress(sim, sim.periodic.volume, include_walls=False)
        eps = np.zeros(3)
        eps[axis] = strain
        sim.strain_cell(eps)
        relax(sim, tolerance=tol, min_steps=0, max_steps=max_steps, check_every=50)
        d_sigma = (love_weber_stress(sim, sim.periodic.volume, include_walls=False) - sigma0) / strain
        lateral = [b for b in range(3) if b != axis]
        C11[axis], C12[axis] = d_sigma[axis, axis], np.mean(d_sigma[lateral, lateral])
        sim.restore(snapshot)
    c11, c12 = float(C11.mean()), float(C12.mean())
    E = (c11 - c12) * (c11 + 2.0 * c12) / (c11 + c12)
    return ElasticConstants(E, c12 / (c11 + c12), c11, c12, C11, C12)
