"""A periodic cell for the DEM and the elastic probe that measures the stiffness of a packing in it.

Walls bias the elastic constants of a small specimen: the particles next to a flat wall are packed and loaded
differently from those inside. LAMMPS, YADE and LIGGGHTS users therefore measure them in a *periodic cell*: no
boundary at all, the packing repeats itself, and a homogeneous strain is applied to the cell and to every particle
position (affinely) before the packing relaxes.

:class:`Periodic` is a parallelepiped cell: its matrix h = diag(``lengths``) + ``tilt`` has the three cell vectors
as columns (``tilt`` holds the off-diagonal part, zero for an orthogonal box). Branch vectors follow the
minimum-image convention in fractional coordinates, d − h round(s) with s = h⁻¹ d for d = x_j − x_i, which is the
orthogonal d − L round(d/L) when there is no tilt; a tilted cell is LAMMPS's triclinic box, the Lees–Edwards
image shift of a sheared packing. Candidate pairs come from ``scipy.spatial.cKDTree(boxsize=L)`` on the
fractional coordinates scaled by the lengths; positions are wrapped into the cell whenever the Verlet list is
rebuilt.

**Straining the cell.** :meth:`Periodic.strain` maps the cell and every position by F = I + ε (a normal strain
``(ε_xx, ε_yy, ε_zz)`` or a symmetric 3×3 tensor). The normal springs of the contacts are computed from positions
and follow the jump. The tangential springs do not: they are *incremental* (Eq. 4.7, ΔF^t = −K^t V^t Δt), so a
jump of positions without velocity never reaches them, and a probe that only moves the positions measures a
network without tangential springs (ν → 1/4 for an affine normal-spring network, E far too low).
:meth:`~abrakit.dem.simulation.Simulation.strain_cell` therefore adds to every touching contact's spring the
increment its affine relative displacement ε·l would have produced, ΔF^t = −K^t (ε l)_t (``l`` the branch vector,
``( )_t`` its part in the contact plane). For the infinitesimal strains of a probe this is exactly what a cell
deformed by a velocity gradient over many steps accumulates (no contact slides on the way); it needs no image
velocities in the contact laws. A test checks the stress change right after the jump against the closed-form
affine stiffness with both springs.

:func:`elastic_probe` applies the six strains of Voigt notation in turn (three normal, three shear), relaxes, and
reads the change of the Love–Weber stress: the 6 × 6 stiffness C of the cell.
:meth:`ElasticConstants.from_stiffness` turns any such C into E and ν of its isotropic projection (bulk
K = C_iijj/9, shear G = (C_ijij − C_iijj/3)/10), C11 and C12 of its normal block, and an anisotropy measure;
the exact network response of :mod:`abrakit.dem.network` gives the same quantities without dynamics.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from abrakit.validation import check_finite, check_option, check_positive, number_arguments

VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))
"""Index pairs of Voigt notation: σ = (σ_xx, σ_yy, σ_zz, σ_yz, σ_xz, σ_xy), ε with engineering shears γ = 2ε_ab."""


@number_arguments
def strain_tensor(strain: ArrayLike) -> np.ndarray:
    """A symmetric (3, 3) strain from ``(ε_xx, ε_yy, ε_zz)``, a scalar (isotropic) or a (3, 3) tensor."""
    eps = np.asarray(strain, dtype=float)
    if eps.shape == (3, 3):
        if not np.allclose(eps, eps.T, rtol=0.0, atol=1e-15 + 1e-12 * np.abs(eps).max()):
            raise ValueError(f"strain must be a symmetric tensor, got {eps.tolist()}")
        return 0.5 * (eps + eps.T)
    if eps.shape not in ((), (3,)):
        raise ValueError(f"strain must be a scalar, (ε_xx, ε_yy, ε_zz) or a symmetric (3, 3) tensor, got shape "
                         f"{eps.shape}")
    return np.diag(np.broadcast_to(eps, (3,)))


@dataclass
class Periodic:
    """Periodic cell with matrix h = diag(``lengths``) + ``tilt`` [m] (cell vectors as columns), lower corner
    ``lower``; ``tilt`` is the off-diagonal part (zeros: an orthogonal box ``[lower, lower + lengths)``)."""

    lengths: np.ndarray
    lower: np.ndarray = field(default_factory=lambda: np.zeros(3))
    tilt: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))

    def __post_init__(self):
        self.lengths = np.array(self.lengths, dtype=float).reshape(-1)
        self.lower = np.array(check_finite("lower", self.lower), dtype=float).reshape(-1)
        self.tilt = np.array(self.tilt, dtype=float)
        if self.lengths.shape != (3,) or self.lower.shape != (3,):
            raise ValueError(f"lengths and lower must have 3 entries (x, y, z), got {self.lengths.shape} and "
                             f"{self.lower.shape}")
        if not np.all(np.isfinite(self.lengths)) or np.any(self.lengths <= 0):
            raise ValueError(f"lengths must be finite and positive, got {self.lengths.tolist()}")
        if self.tilt.shape != (3, 3) or not np.all(np.isfinite(self.tilt)) or np.any(np.diag(self.tilt) != 0):
            raise ValueError(f"tilt must be a finite (3, 3) array with a zero diagonal, got {self.tilt.tolist()}")
        self._sync()

    def _sync(self) -> None:
        """Cache the cell matrix, its inverse and whether it is tilted (after any change of the cell)."""
        self.matrix = np.diag(self.lengths) + self.tilt
        self.inverse = np.linalg.inv(self.matrix)
        self.tilted = bool(np.any(self.tilt != 0.0))

    @property
    def volume(self) -> float:
        return float(abs(np.linalg.det(self.matrix)))

    @property
    def widths(self) -> np.ndarray:
        """Distances between the cell's opposite faces (the lengths of an orthogonal box) [m]."""
        h = self.matrix
        areas = [np.linalg.norm(np.cross(h[:, (a + 1) % 3], h[:, (a + 2) % 3])) for a in range(3)]
        return self.volume / np.array(areas)

    def fractional(self, x: np.ndarray) -> np.ndarray:
        """Fractional coordinates s = h⁻¹ (x − lower) of positions ``(N, 3)``."""
        return (x - self.lower) @ self.inverse.T

    def _wrapped_fractional(self, x: np.ndarray) -> np.ndarray:
        """Fractional coordinates of positions ``(N, 3)`` brought into [0, 1) (mod may round up to 1)."""
        s = np.mod(self.fractional(x), 1.0)
        return np.where(s >= 1.0, 0.0, s)

    def wrap(self, x: np.ndarray) -> None:
        """Move positions ``(N, 3)`` into the cell, in place."""
        if not self.tilted:
            x[:] = self.lower + np.mod(x - self.lower, self.lengths)
            x[:] = np.where(x >= self.lower + self.lengths, self.lower, x)   # mod may round up to L
            return
        x[:] = self.lower + self._wrapped_fractional(x) @ self.matrix.T

    def search_coordinates(self, x: np.ndarray) -> tuple[np.ndarray, float]:
        """Positions for a toroidal ``cKDTree(boxsize=lengths)`` and the factor by which a search radius must
        grow there: the fractional coordinates scaled by the lengths (the positions themselves without tilt)."""
        if not self.tilted:
            return np.minimum(x - self.lower, np.nextafter(self.lengths, 0)), 1.0
        scaled = np.minimum(self._wrapped_fractional(x) * self.lengths, np.nextafter(self.lengths, 0))
        return scaled, float(np.linalg.norm(np.diag(self.lengths) @ self.inverse, 2))

    def minimum_image(self, d: np.ndarray, axis: int = -1) -> np.ndarray:
        """Branch vectors reduced to their nearest periodic image; components along ``axis`` (``(K, 3)`` by
        default, ``axis=0`` for the simulation's ``(3, K)`` contact arrays)."""
        rows = axis in (-1, d.ndim - 1)
        if not self.tilted:
            L = self.lengths if rows else self.lengths.reshape((3,) + (1,) * (d.ndim - 1 - axis))
            return d - L * np.round(d / L)
        if rows:                                   # d − h round(h⁻¹ d): a pair inside the cell keeps d exactly
            return d - np.round(d @ self.inverse.T) @ self.matrix.T
        shift = np.tensordot(self.matrix, np.round(np.tensordot(self.inverse, d, axes=(1, axis))), axes=(1, 0))
        return d - np.moveaxis(shift, 0, axis)

    def check_range(self, interaction: float) -> None:
        """The minimum image is unique only if every interaction is shorter than half the cell."""
        if np.any(self.widths <= 2.0 * interaction):
            raise ValueError(f"the periodic cell {self.widths.tolist()} m (face to face) must be longer than twice "
                             f"the largest interaction distance (2 r_max + skin = {interaction:.4g} m) along every "
                             "axis")

    def strain(self, x: np.ndarray, strain) -> np.ndarray:
        """Homogeneous strain of the cell (``(ε_xx, ε_yy, ε_zz)`` or a symmetric (3, 3) tensor), applied affinely
        to the positions ``x`` (N, 3) in place: x ← lower + F (x − lower), h ← F h with F = I + ε. Returns ε."""
        eps = strain_tensor(strain)
        F = np.eye(3) + eps
        if np.any(np.diag(eps) <= -1.0) or np.linalg.det(F) <= 0.0:
            raise ValueError(f"strain must be above -1 along every axis and keep the cell's orientation, got "
                             f"{eps.tolist()}")
        x[:] = self.lower + (x - self.lower) @ F.T
        h = F @ self.matrix
        self.lengths, self.tilt = np.diag(h).copy(), h - np.diag(np.diag(h))
        self._sync()
        return eps


class ElasticConstants(NamedTuple):
    """Elastic constants of a packing [Pa] (ν and the anisotropy dimensionless): :meth:`from_stiffness`."""

    E: float                  # Young's modulus of the isotropic projection
    nu: float                 # Poisson's ratio of the isotropic projection
    C11: float                # mean of C_xx,xx, C_yy,yy, C_zz,zz
    C12: float                # mean of the six off-diagonal entries of the normal block
    C11_axes: np.ndarray      # (3,) the normal stiffness along x, y, z
    C12_axes: np.ndarray      # (3,) per axis, the mean lateral response to a strain along it
    C: np.ndarray             # (6, 6) Voigt stiffness (engineering shears), symmetrised
    bulk: float               # K = C_iijj / 9
    shear: float              # G = (C_ijij − C_iijj/3) / 10
    anisotropy: float         # |C − C_iso| / |C| in Mandel notation (0 for an isotropic C)

    @classmethod
    def from_stiffness(cls, C) -> ElasticConstants:
        """E, ν and the rest of :class:`ElasticConstants` from a (6, 6) Voigt stiffness ``C`` (engineering shears).

        The isotropic projection is :func:`abrakit.identification.isotropic_part` (the closest isotropic tensor in
        the Mandel norm: K = C_iijj/9, G = (C_ijij − C_iijj/3)/10), so the DEM's numbers and the closed forms of
        Eq. (5.20) are compared by one definition.
        """
        from abrakit.identification import isotropic_part

        C = np.asarray(C, dtype=float)
        if C.shape != (6, 6) or not np.all(np.isfinite(C)):
            raise ValueError(f"C must be a finite (6, 6) Voigt stiffness, got shape {C.shape}")
        C = 0.5 * (C + C.T)
        E, nu, anisotropy = (float(v) for v in isotropic_part(C))
        normal = C[:3, :3]
        lateral = np.array([np.mean([normal[b, a] for b in range(3) if b != a]) for a in range(3)])
        return cls(E, nu, float(np.mean(np.diag(normal))), float(normal[~np.eye(3, dtype=bool)].mean()),
                   np.diag(normal).copy(), lateral, C, E / (3.0 * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu)), anisotropy)


def voigt_strain(k: int, strain: float) -> np.ndarray:
    """The (3, 3) strain of Voigt component ``k`` with value ``strain`` (a shear: γ = ``strain``)."""
    check_option("k", k, range(6))
    strain = check_finite("strain", strain)
    a, b = VOIGT[k]
    eps = np.zeros((3, 3))
    eps[a, b] = eps[b, a] = strain if a == b else 0.5 * strain
    return eps


def elastic_probe(sim, strain: float = 1e-8, *, max_steps: int = 20_000, tol: float = 1e-6,
                  shift_springs: bool = True) -> ElasticConstants:
    """The 6 × 6 stiffness of the packing in ``sim`` (periodic, equilibrated) by six small strains of its cell.

    For each Voigt component k (three normal strains, three shears γ): relax, read σ⁰, strain the cell by
    ``strain`` in component k (affinely, the tangential springs with it: module doc), relax again (at most
    ``max_steps`` steps, until the unbalanced-force ratio (:func:`~abrakit.dem.measure.unbalanced_force_ratio`)
    is below ``tol``; use local damping), read σ¹, and go back to the starting state. Column k of C is
    (σ¹ − σ⁰)/``strain`` in Voigt order; E and ν are those of its isotropic projection
    (:meth:`ElasticConstants.from_stiffness`). Stresses are the Love–Weber averages over the cell, tension
    positive.
    Warns when a relaxation stops above ``tol``.

    The default strain, 10⁻⁸, is small enough that no contact opens or slides: the probe then measures the
    tangent (linear) stiffness and meets the exact network response to 10⁻⁵. At 10⁻⁶ a packing at 1 MPa reads E
    1–3 % low (contacts with overlaps of a few nm open, contacts near the Coulomb limit slide), at 10⁻⁵ 20–35 %
    (``benchmarks/bench_dem_periodic.py``, amplitude study). ``shift_springs=False`` repeats the positions-only
    jump that misses the tangential springs (:meth:`~abrakit.dem.simulation.Simulation.strain_cell`), to show the trap.
    """
    from abrakit.dem.measure import love_weber_stress, relax

    if sim.periodic is None:
        raise ValueError("elastic_probe needs a periodic simulation (Simulation(..., periodic=Periodic(...)))")
    check_positive("strain", strain)
    C = np.zeros((6, 6))
    rows = tuple(zip(*VOIGT, strict=True))
    for k in range(6):
        snapshot = sim.snapshot()
        states = [relax(sim, tolerance=tol, min_steps=0, max_steps=max_steps, check_every=50)]
        sigma0 = love_weber_stress(sim, sim.periodic.volume, include_walls=False)
        sim.strain_cell(voigt_strain(k, strain), shift_springs=shift_springs)
        states.append(relax(sim, tolerance=tol, min_steps=0, max_steps=max_steps, check_every=50))
        sigma1 = love_weber_stress(sim, sim.periodic.volume, include_walls=False)
        C[:, k] = (sigma1 - sigma0)[rows] / strain
        sim.restore(snapshot)
        if not all(s["converged"] for s in states):
            worst = max(s["ratio"] for s in states)
            warnings.warn(f"elastic_probe: relaxation of Voigt component {k} stopped at an unbalanced-force ratio "
                          f"{worst:.2g} > tol = {tol:g} after max_steps = {max_steps}", RuntimeWarning,
                          stacklevel=2)
    return ElasticConstants.from_stiffness(C)
