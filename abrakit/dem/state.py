"""Particles and contacts as structure-of-arrays (Ch. 4.1.1): no objects per particle, one array per quantity.

Units are SI: m, kg, s, N. A :class:`Particles` holds ``N`` rigid spheres (PFC restriction 1 and 5 of Ch. 4.1.1);
a :class:`ContactSet` holds ``M`` candidate contacts as index pairs ``(i, j)`` with their history (tangential
spring force, contact-bond state). Both are plain dataclasses of numpy arrays, so a step of the engine is a handful
of vectorised expressions over these arrays.

Conventions used everywhere in :mod:`abrakit.dem`:

- the contact normal ``n`` points from body A = ``i`` to body B = ``j`` (Eq. 4.1), the overlap is
  ``U = r_A + r_B - d`` (Eq. 4.3), and a contact force ``F`` is the force that A exerts on B (B receives ``+F``,
  A receives ``-F``);
- per-contact vectors (normal, tangential force, contact force) are component-major arrays of shape (3, M),
  so each component is contiguous and formulas broadcast without ``[:, None]``;
- velocities are stored at half steps (leap-frog, seed 002 Eq. 7–10): after a step, ``x`` is at ``t`` and
  ``v``, ``w`` are at ``t - dt/2``.

2D disks are supported as spheres constrained to the x–y plane (:meth:`Particles.disks` plus
``Simulation(planar=True)``): mass and inertia are those of disks of a given thickness.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields

import numpy as np
from numpy.typing import ArrayLike

from abrakit.validation import check_finite, check_positive, check_range, check_shape, number_arguments


@number_arguments
def sphere_mass(radius: ArrayLike, density: ArrayLike):
    """Mass of a solid sphere, m = 4/3 π r³ ρ [kg]."""
    return 4.0 / 3.0 * np.pi * np.asarray(radius, float) ** 3 * density


@number_arguments
def sphere_inertia(mass: ArrayLike, radius: ArrayLike):
    """Moment of inertia of a solid sphere about its centre, I = 2/5 m r² [kg m²]."""
    return 0.4 * np.asarray(mass, float) * np.asarray(radius, float) ** 2


def _per_particle(name, value, n, *, low=None, allow_zero=True):
    arr = np.broadcast_to(np.asarray(check_finite(name, value), float), (n,)).copy()
    if low is not None:
        check_range(name, arr, low, None, low_open=not allow_zero)
    return arr


@dataclass
class Particles:
    """``N`` spheres as arrays. Create with :meth:`spheres` (or :meth:`disks`), which checks the input.

    Material arrays are per particle, as in PFC: the contact law combines them per contact (Eq. 4.11–4.14).
    ``fixed`` particles keep their velocities (a prescribed motion); ``clump`` is the clump id or -1.
    """

    x: np.ndarray            # (N, 3) centre positions [m]
    v: np.ndarray            # (N, 3) velocities [m/s]
    w: np.ndarray            # (N, 3) angular velocities [rad/s]
    radius: np.ndarray       # (N,) [m]
    mass: np.ndarray         # (N,) [kg]
    inertia: np.ndarray      # (N,) [kg m²]
    kn: np.ndarray           # (N,) particle normal stiffness k_n [N/m] (linear law, Eq. 4.11)
    kt: np.ndarray           # (N,) particle shear stiffness k_t [N/m] (Eq. 4.12)
    friction: np.ndarray     # (N,) friction coefficient μ (Eq. 4.8)
    shear_modulus: np.ndarray  # (N,) G [Pa] (Hertz, Eq. 4.13)
    poisson: np.ndarray      # (N,) ν (Hertz)
    fixed: np.ndarray        # (N,) bool: velocities prescribed, not integrated
    clump: np.ndarray        # (N,) int clump id, -1 for a free sphere

    @classmethod
    def spheres(cls, x, radius, density=2650.0, *, v=None, w=None, kn=1e6, kt=None, friction=0.5,
                shear_modulus=30e9, poisson=0.25, fixed=False) -> Particles:
        """Spheres at ``x`` (N, 3) with radii [m] and density [kg/m³]; scalars broadcast to all particles.

        ``kt`` defaults to ``kn`` (PFC's common choice k_n/k_t = 1). Raises ``ValueError`` for a zero or
        negative radius or density, non-finite positions, or negative stiffness or friction.
        """
        x = np.array(check_finite("x", x), dtype=float, ndmin=2)
        check_shape("x", x, (None, 3))
        n = len(x)
        radius = _per_particle("radius", radius, n, low=0.0, allow_zero=False)
        density = _per_particle("density", density, n, low=0.0, allow_zero=False)
        mass = sphere_mass(radius, density)
        return cls._make(x, radius, mass, sphere_inertia(mass, radius), v, w, kn, kt, friction,
                         shear_modulus, poisson, fixed)

    @classmethod
    def disks(cls, xy, radius, density=2650.0, *, thickness=None, **kwargs) -> Particles:
        """2D disks in the x–y plane (use with ``Simulation(planar=True)``).

        Mass m = ρ π r² t and inertia I = ½ m r² of a disk of thickness ``t`` (default: the mean diameter, so
        the contact stiffness keeps its 3D meaning per particle).
        """
        xy = np.array(check_finite("xy", xy), dtype=float, ndmin=2)
        check_shape("xy", xy, (None, 2))
        n = len(xy)
        radius = _per_particle("radius", radius, n, low=0.0, allow_zero=False)
        density = _per_particle("density", density, n, low=0.0, allow_zero=False)
        thickness = 2.0 * radius.mean() if thickness is None else check_positive("thickness", thickness)
        mass = density * np.pi * radius**2 * thickness
        x = np.column_stack([xy, np.zeros(n)])
        return cls._make(x, radius, mass, 0.5 * mass * radius**2, kwargs.pop("v", None), kwargs.pop("w", None),
                         kwargs.pop("kn", 1e6), kwargs.pop("kt", None), kwargs.pop("friction", 0.5),
                         kwargs.pop("shear_modulus", 30e9), kwargs.pop("poisson", 0.25),
                         kwargs.pop("fixed", False))

    @classmethod
    def _make(cls, x, radius, mass, inertia, v, w, kn, kt, friction, shear_modulus, poisson, fixed):
        n = len(x)
        mass = _per_particle("mass", mass, n, low=0.0, allow_zero=False)
        inertia = _per_particle("inertia", inertia, n, low=0.0, allow_zero=False)
        vec = lambda name, a: (np.zeros((n, 3)) if a is None
                               else np.array(np.broadcast_to(check_finite(name, a), (n, 3)), dtype=float))
        kn = _per_particle("kn", kn, n, low=0.0, allow_zero=False)
        kt = kn.copy() if kt is None else _per_particle("kt", kt, n, low=0.0)
        return cls(
            x=x.copy(), v=vec("v", v), w=vec("w", w), radius=radius, mass=mass, inertia=inertia,
            kn=kn, kt=kt, friction=_per_particle("friction", friction, n, low=0.0),
            shear_modulus=_per_particle("shear_modulus", shear_modulus, n, low=0.0, allow_zero=False),
            poisson=_per_particle("poisson", check_range("poisson", poisson, -1.0, 0.5, low_open=True,
                                                         high_open=True), n),
            fixed=np.broadcast_to(np.asarray(fixed, bool), (n,)).copy(),
            clump=np.full(n, -1, dtype=np.int64),
        )

    def __len__(self) -> int:
        return len(self.radius)

    def take(self, index) -> Particles:
        """A new :class:`Particles` with the rows ``index`` (copies)."""
        return Particles(**{f.name: getattr(self, f.name)[index].copy() for f in fields(self)})

    @staticmethod
    def concatenate(*parts: Particles) -> Particles:
        """Join particle sets; clump ids of later parts are shifted so they stay distinct."""
        out, shift = {}, 0
        clumps = []
        for p in parts:
            clumps.append(np.where(p.clump >= 0, p.clump + shift, -1))
            shift += int(p.clump.max()) + 1 if len(p) and p.clump.max() >= 0 else 0
        for f in fields(Particles):
            out[f.name] = np.concatenate([getattr(p, f.name) for p in parts])
        out["clump"] = np.concatenate(clumps)
        return Particles(**out)


def pair_keys(i, j, n: int) -> np.ndarray:
    """One int64 key per contact, ``i·n + j``; sorted keys let history be matched with ``np.searchsorted``."""
    return np.asarray(i, np.int64) * np.int64(n) + np.asarray(j, np.int64)


def _last_result(name: str, doc: str) -> property:
    """A result of the last force evaluation kept in ``ContactSet._results``: built on first read if deferred."""
    return property(lambda self: self._result(name), lambda self, value: self._results.__setitem__(name, value),
                    doc=doc)


@dataclass
class ContactSet:
    """``M`` candidate contacts (from the Verlet list) between body ``i`` and particle ``j``.

    For particle–particle contacts ``i < j`` are particle indices; for wall contacts ``i`` is the wall index.
    ``keys`` are sorted, so history can be transferred across neighbour-list rebuilds. Fields after ``keys`` are
    the contact's history and survive rebuilds (:data:`HISTORY`); ``prm`` holds the per-contact parameters the
    contact law derived from the two bodies (stiffness, friction, effective mass), recomputed at each rebuild.
    """

    i: np.ndarray
    j: np.ndarray
    keys: np.ndarray
    ft: np.ndarray                 # (3, M) tangential spring force, Eq. (4.7) [N]
    bonded: np.ndarray             # (M,) contact bond intact
    bond_gap: np.ndarray           # (M,) gap (>= 0) at bond installation [m]
    bond_normal_strength: np.ndarray  # (M,) f^{n,c} [N]
    bond_shear_strength: np.ndarray   # (M,) f^{t,c} [N]
    prm: dict = field(default_factory=dict)
    # results of the last force evaluation (read by measure.py; not history)
    overlap: np.ndarray | None = None   # (M,) U [m]
    _results: dict = field(default_factory=dict, repr=False)   # normal, fn, force: arrays or deferred makers

    HISTORY = ("ft", "bonded", "bond_gap", "bond_normal_strength", "bond_shear_strength")

    def defer(self, **makers) -> None:
        """Results that are built only when read: ``name=callable`` (``normal``, ``fn``, ``force``).

        The NumPy force loop works on the live contacts only; spreading its results over the whole candidate list
        costs a tenth of a step, and most steps nobody reads them (a measurement or an output does)."""
        self._results.update(makers)

    def _result(self, name):
        value = self._results.get(name)
        if callable(value):
            value = self._results[name] = value()
        return value

    def __getstate__(self) -> dict:
        """Pickles and copies hold the results themselves, not the makers (closures cannot be pickled)."""
        for name in list(self._results):
            self._result(name)
        return self.__dict__.copy()

    def __setstate__(self, state: dict) -> None:
        """Also reads pickles written before the results were deferred (``normal``, ``fn``, ``force`` as fields)."""
        state = dict(state)
        results = state.pop("_results", None)
        if results is None:
            results = {name: state.pop(name) for name in ("normal", "fn", "force") if name in state}
        self.__dict__.update(state)
        self._results = results

    normal = _last_result("normal", "(3, M) unit normal n from A to B, Eq. (4.1), of the last force evaluation")
    fn = _last_result("fn", "(M,) normal spring force [N] of the last force evaluation")
    force = _last_result("force", "(3, M) total contact force on B [N] of the last force evaluation")

    @classmethod
    def empty_history(cls, i, j, n_keys: int) -> ContactSet:
        i = np.asarray(i, np.int64)
        j = np.asarray(j, np.int64)
        m = len(i)
        return cls(i=i, j=j, keys=pair_keys(i, j, n_keys), ft=np.zeros((3, m)), bonded=np.zeros(m, bool),
                   bond_gap=np.zeros(m), bond_normal_strength=np.zeros(m), bond_shear_strength=np.zeros(m))

    def __len__(self) -> int:
        return len(self.i)

    @property
    def touching(self) -> np.ndarray:
        """Contacts that carry force: overlapping, or held by an intact contact bond."""
        if self.overlap is None:
            return np.zeros(len(self), bool)
        return (self.overlap > 0.0) | self.bonded
