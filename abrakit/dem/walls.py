"""Planar walls: frictionless or frictional, moved by a prescribed velocity or by a servo holding a stress.

Walls are infinite planes ``(x - point)·normal = 0`` whose ``normal`` points into the domain. A particle touches
a wall when its signed distance ``s`` is below its radius: the overlap is ``U = r - s`` and the contact normal is
the wall normal (the wall is body A, the particle body B, as in :mod:`abrakit.dem.contact_laws`).
``force[k]`` is the force the particles exert on wall ``k`` (updated every step).

Servo (PFC's rule): the wall speed is ``G (σ - σ_target)`` outward, with gain ``G = α A / (ΣK^n Δt)`` from the
stiffness of the wall's contacts, so that one step moves the wall by the fraction α of the displacement that
would remove the stress error.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from abrakit.validation import check_finite, check_number_fields, check_positive, check_range


class Walls:
    """A set of ``W`` planar walls as arrays (``point``, ``normal``, ``velocity``, ``kn``, ``kt``, ``friction``).

    Wall stiffnesses act in series with the particle's (Eq. 4.11, 4.12); the default ``kn = inf`` is a rigid
    wall, so the contact stiffness is the particle's own. Friction μ = min(μ_wall, μ_particle).
    """

    def __init__(self):
        self.point = np.zeros((0, 3))
        self.normal = np.zeros((0, 3))
        self.velocity = np.zeros((0, 3))
        self.kn = np.zeros(0)
        self.kt = np.zeros(0)
        self.friction = np.zeros(0)
        self.force = np.zeros((0, 3))
        self.names: list[str] = []
        self.servos: list[Servo] = []
        self.box_axes: dict[str, tuple[int, int]] = {}

    def __len__(self) -> int:
        return len(self.names)

    def add(self, point, normal, *, velocity=(0.0, 0.0, 0.0), kn=np.inf, kt=None, friction=0.0,
            name: str | None = None) -> int:
        """Add a wall through ``point`` with inward ``normal`` (normalised here); return its index."""
        normal = np.asarray(check_finite("normal", normal), float)
        length = np.linalg.norm(normal)
        if length == 0.0:
            raise ValueError("normal must be a non-zero vector, got (0, 0, 0)")
        kn = float(kn)
        if not kn > 0.0:
            raise ValueError(f"kn must lie in (0, inf], got {kn!r}")
        kt = kn if kt is None else float(kt)
        if not kt >= 0.0:
            raise ValueError(f"kt must lie in [0, inf], got {kt!r}")
        self.point = np.vstack([self.point, check_finite("point", point)])
        self.normal = np.vstack([self.normal, normal / length])
        self.velocity = np.vstack([self.velocity, check_finite("velocity", velocity)])
        self.kn = np.append(self.kn, kn)
        self.kt = np.append(self.kt, kt)
        self.friction = np.append(self.friction, check_range("friction", friction, 0.0, None))
        self.force = np.vstack([self.force, np.zeros(3)])
        self.names.append(name or f"wall{len(self.names)}")
        return len(self.names) - 1

    @classmethod
    def box(cls, lower, upper, **kwargs) -> Walls:
        """Six walls bounding the box ``lower``–``upper``, named ``xmin, xmax, ymin, ymax, zmin, zmax``."""
        walls = cls()
        lower = np.asarray(check_finite("lower", lower), float)
        upper = np.asarray(check_finite("upper", upper), float)
        if np.any(upper <= lower):
            raise ValueError(f"upper must exceed lower on every axis, got lower={lower}, upper={upper}")
        for axis, label in enumerate("xyz"):
            e = np.eye(3)[axis]
            lo = walls.add(lower, e, name=f"{label}min", **kwargs)
            hi = walls.add(upper, -e, name=f"{label}max", **kwargs)
            walls.box_axes[label] = (lo, hi)
        return walls

    def index(self, name: str) -> int:
        return self.names.index(name)

    def normal_force(self, k) -> np.ndarray:
        """Compressive normal force on wall(s) ``k`` [N] (positive when particles push the wall outward)."""
        return -np.einsum("...i,...i->...", self.force[k], self.normal[k])

    def box_lengths(self) -> np.ndarray:
        """Current edge lengths (x, y, z) of a :meth:`box` [m]."""
        return np.array([np.dot(self.point[hi] - self.point[lo], self.normal[lo])
                         for lo, hi in (self.box_axes[a] for a in "xyz")])

    def box_area(self, axis: str) -> float:
        """Area of the walls normal to ``axis`` of a :meth:`box` [m²]."""
        lengths = self.box_lengths()
        return float(np.prod(np.delete(lengths, "xyz".index(axis))))

    def box_volume(self) -> float:
        return float(np.prod(self.box_lengths()))

    def box_stress(self) -> np.ndarray:
        """Mean compressive wall stress per axis (x, y, z) of a :meth:`box` [Pa]."""
        out = np.zeros(3)
        for a, axis in enumerate("xyz"):
            lo, hi = self.box_axes[axis]
            out[a] = 0.5 * (self.normal_force(lo) + self.normal_force(hi)) / self.box_area(axis)
        return out

    def move(self, dt: float) -> None:
        self.point += self.velocity * dt

    def add_servo(self, wall: int | str, target_stress: float, area, **kwargs) -> Servo:
        """Let ``wall`` be driven by a :class:`Servo` to ``target_stress`` (compression positive) [Pa]."""
        k = self.index(wall) if isinstance(wall, str) else int(wall)
        servo = Servo(k, target_stress, area, **kwargs)
        self.servos = [s for s in self.servos if s.wall != k] + [servo]
        return servo


@dataclass
class Servo:
    """Stress-controlled wall: ``v = -G (σ - σ_target) n`` with ``G = α A/(ΣK^n Δt)``, capped at ``max_speed``.

    ``area`` is a number [m²] or a callable ``area(walls)`` (for boxes: ``lambda w: w.box_area("z")``).
    ``stiffness_floor`` [N/m] is used for the gain while the wall touches nothing yet.
    """

    wall: int
    target_stress: float
    area: float | Callable
    relaxation: float = 0.5
    max_speed: float = np.inf
    stiffness_floor: float | None = None

    def __post_init__(self):
        check_number_fields(self)
        check_finite("target_stress", self.target_stress)
        if not callable(self.area):
            check_positive("area", self.area)
        check_range("relaxation", self.relaxation, 0.0, 1.0, low_open=True)
        if self.max_speed != np.inf:                              # +inf: no limit; any other value must be > 0
            check_positive("max_speed", self.max_speed)

    def current_area(self, walls) -> float:
        return float(self.area(walls) if callable(self.area) else self.area)

    def update(self, walls: Walls, contact_stiffness: float, dt: float) -> float:
        """Set the wall's velocity from the current stress; return the stress [Pa]."""
        area = self.current_area(walls)
        stress = float(walls.normal_force(self.wall)) / area
        stiffness = contact_stiffness if contact_stiffness > 0.0 else (self.stiffness_floor or 0.0)
        if stiffness > 0.0:
            speed = self.relaxation * area / (stiffness * dt) * (stress - self.target_stress)
        else:
            speed = -np.inf if stress < self.target_stress else 0.0
        speed = float(np.clip(speed, -self.max_speed, self.max_speed))
        if not np.isfinite(speed):
            raise ValueError("Servo needs max_speed or stiffness_floor while its wall touches no particle")
        walls.velocity[self.wall] = -speed * walls.normal[self.wall]
        return stress
