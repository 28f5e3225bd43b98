"""Rigid rollers of a bending fixture: flat rocker pads, one-sided and frictionless, pivoting at exact positions.

A roller of the four-point bending fixture (seed 002, Sec. 5: "servo-controlled walls") is a rigid flat pad of length
``pad`` whose face pivots about a point at the roller's position x₀. Each pad

* pushes the particles that overlap its face along its normal, with a linear penalty k per particle: one-sided
  (a particle that leaves the face feels nothing; a pad never pulls), frictionless (no force along the face);
* turns about its pivot with the beam's slope (a rocker), so the resultant of its contact forces passes through
  x₀ whatever particles lie under it: the span of the test is the fixture's, not the particle layout's;
* moves vertically in one of three ways: ``"fixed"`` (a support), ``"prescribed"`` (a loading roller under
  displacement control: its pivot sinks at a prescribed speed) or ``"force"`` (a loading roller under force
  control: a rigid body of mass m carrying a prescribed force).

The same pads serve the monotonic test (displacement control) and the cyclic test (force control), so both
measure the same specimen. A particle's pad contact has the stiffness of a particle–particle contact, so the
time step of the particles stays valid; a pad's mass and rotational inertia are those of the particles it
covers, and its vertical motion is damped like the particles' (local damping α, seed 002 Eq. 5, 6). The pads
turn without inertia on a viscous pivot, ω = M / c, with c the critical damping of a contact at the face's end:
a pad turns towards moment equilibrium within about one period of that contact and stands still where no moment
acts (a pad resting on one particle at its pivot is in neutral equilibrium; with inertia it drifted, and a pad the
beam had left kept turning and was struck on its edge when the beam came back).

Geometry of pad k: pivot p_k = (x₀, y_k), angle θ_k, face tangent t = (cos θ, sin θ), normal n = side·(−sin θ,
cos θ) pointing into the beam (side = +1 below the beam, −1 above it). A particle of centre c and radius r at
s = (c − p)·t along the face and h = (c − p)·n above it overlaps the face by δ = r − h when |s| ≤ pad/2; its
force is k δ n. The pad feels the reactions −k δ n and, about its pivot, the moment −side Σ s k δ.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from abrakit.compiled import HAVE_NUMBA
from abrakit.validation import check_finite, check_option, check_positive, check_range

COMPILED_CONTACTS = HAVE_NUMBA
"""Whether :meth:`Rollers.contact_forces` runs the compiled loop (:mod:`abrakit.experiments._pad_kernel`; where
numba is installed) or the NumPy version; both give the same forces."""

MODES = ("fixed", "prescribed", "force")


@dataclass
class Rollers:
    """Pads at pivots ``x0`` (K,), ``y`` (K,) [m] with ``side`` (K,) +1 (below the beam, pushing up) or −1 (above,
    pushing down), ``mode`` (K,) of :data:`MODES`, face length ``pad`` [m], contact stiffness ``k`` [N/m] per
    particle, ``mass`` (K,) [kg] and local damping ``alpha``. ``force`` (K,) [N, positive along y] drives the pads in
    ``"force"`` mode, ``speed`` [m/s] (positive downward) the pads in ``"prescribed"`` mode."""

    x0: np.ndarray
    y: np.ndarray
    side: np.ndarray
    mode: tuple
    pad: float
    k: float
    mass: np.ndarray
    alpha: float = 0.7

    def __post_init__(self):
        self.x0, self.y = (np.array(check_finite(name, value), dtype=float) for name, value in (("x0", self.x0),
                                                                                                ("y", self.y)))
        self.side, self.mass = np.asarray(self.side, float), np.asarray(self.mass, float)
        if not (self.x0.shape == self.y.shape == self.side.shape == self.mass.shape == (len(self.mode),)):
            raise ValueError("x0, y, side, mass and mode must have one entry per roller")
        for m in self.mode:
            check_option("mode", m, MODES)
        if not np.all(np.abs(self.side) == 1.0):
            raise ValueError(f"side must be +1 (below the beam) or -1 (above it), got {self.side}")
        check_positive("pad", self.pad)
        check_positive("k", self.k)
        check_positive("mass", self.mass)
        check_range("alpha", self.alpha, 0.0, 1.0, high_open=True)
        n = len(self.mode)
        self.y0 = self.y.copy()
        self.theta, self.vy = np.zeros(n), np.zeros(n)
        inertia = self.mass * self.pad**2 / 12.0
        self.rotational_damping = 2.0 * np.sqrt(self.k * (0.5 * self.pad) ** 2 * inertia)
        self.force = np.zeros(n)
        self.speed = 0.0
        self.travel = 0.0
        self._contacts = None

    def seat(self, x, radius, faces) -> None:
        """Seat each pad on the beam: its face becomes the line that touches the particle edges under it on both
        sides of the pivot (the edge of the lower convex hull of the points (x, y − r) within the face that spans
        x₀, for a pad below the beam; of the upper hull of (x, y + r) above it; ``faces`` (K, N) bool, the
        particles of the beam's face each pad stands on), so that every pad starts in
        contact, at rest, and neither rocks nor has to travel through the beam's roughness before it carries load.
        The hull of the edge points gives the tilt θ; the pivot's height then follows from the disks themselves, so
        that the nearest disk touches the tilted face exactly (the edge points are off by r θ²/2, a micrometre at
        20 mrad: at the contact stiffness a load of tens of newtons)."""
        x, radius = np.asarray(x)[:, :2], np.asarray(radius)
        for k in range(len(self.mode)):
            under = np.flatnonzero(faces[k] & (np.abs(x[:, 0] - self.x0[k]) < 0.5 * self.pad))
            if not len(under):
                raise ValueError(f"no particle lies under the face of roller {k} at x = {self.x0[k]:g} m; widen pad")
            side = self.side[k]
            points = np.column_stack([x[under, 0], side * (x[under, 1] - side * radius[under])])  # lower hull
            slope = _hull_slope(points, self.x0[k])
            self.theta[k] = theta = np.arctan(side * slope)
            nx, ny = -side * np.sin(theta), side * np.cos(theta)           # the face's normal, into the beam
            lift = x[under, 1] + ((x[under, 0] - self.x0[k]) * nx - radius[under]) / ny   # exact: touch, no overlap
            self.y[k] = lift.min() if side > 0 else lift.max()
        self.y0 = self.y.copy()

    # ------------------------------------------------------------------ contact
    def contact_forces(self, x, radius, *, compiled: bool | None = None):
        """Forces of the pads on the particles, (N, 2) [N], and per pad the reaction (K, 2) and the moment about
        its pivot (K,). Stores the contacts (pad, particle, s, f) for :meth:`centre_of_pressure`. ``compiled``
        (default :data:`COMPILED_CONTACTS`) runs the same equations in one compiled loop."""
        if COMPILED_CONTACTS if compiled is None else compiled:
            from abrakit.experiments._pad_kernel import pad_contacts

            on_particles, reaction, moment, *contacts = pad_contacts(
                np.ascontiguousarray(x, dtype=float), np.asarray(radius, float), self.x0, self.y, self.theta,
                self.side, float(self.pad), float(self.k))
            self._contacts = tuple(contacts)
            return on_particles, reaction, moment
        x = np.asarray(x)[:, :2]
        c, s_ = np.cos(self.theta), np.sin(self.theta)
        t = np.column_stack([c, s_])                                     # (K, 2)
        n = self.side[:, None] * np.column_stack([-s_, c])               # (K, 2), into the beam
        rel = x[None, :, :] - np.column_stack([self.x0, self.y])[:, None, :]     # (K, N, 2)
        along = np.einsum("kni,ki->kn", rel, t)
        height = np.einsum("kni,ki->kn", rel, n)
        overlap = radius[None, :] - height
        touching = (np.abs(along) <= 0.5 * self.pad) & (overlap > 0.0) & (height > -radius[None, :])
        pad_index, particle = np.nonzero(touching)
        f = self.k * overlap[pad_index, particle]
        on_particles = np.zeros_like(x)
        np.add.at(on_particles, particle, f[:, None] * n[pad_index])
        reaction = np.zeros((len(self.mode), 2))
        np.add.at(reaction, pad_index, -f[:, None] * n[pad_index])
        moment = -self.side * np.bincount(pad_index, weights=along[pad_index, particle] * f,
                                          minlength=len(self.mode))
        self._contacts = (pad_index, particle, along[pad_index, particle], f)
        return on_particles, reaction, moment

    def centre_of_pressure(self) -> np.ndarray:
        """Per pad, the x of the resultant of its last contact forces [m] (NaN for a pad without contact)."""
        pad_index, _, along, f = self._contacts
        total = np.bincount(pad_index, weights=f, minlength=len(self.mode))
        arm = np.bincount(pad_index, weights=along * f, minlength=len(self.mode))
        with np.errstate(invalid="ignore", divide="ignore"):
            return self.x0 + np.cos(self.theta) * arm / total

    def contact_mean(self, values, pads) -> float:
        """The mean of the per-particle ``values`` (N,) over the last contacts of the ``pads`` (indices), weighted
        by their contact forces; NaN where those pads touch nothing."""
        pad_index, particle, _, f = self._contacts
        on = np.isin(pad_index, pads)
        return float(np.average(values[particle[on]], weights=f[on])) if on.any() else float("nan")

    def contact_counts(self) -> np.ndarray:
        """Per pad, the number of particles it touched at its last contact evaluation."""
        return np.bincount(self._contacts[0], minlength=len(self.mode))

    def contact_total(self) -> np.ndarray:
        """Per pad, the sum of its last contact forces' magnitudes [N] (never negative: the pads only push)."""
        pad_index, _, _, f = self._contacts
        return np.bincount(pad_index, weights=f, minlength=len(self.mode))

    # ------------------------------------------------------------------ motion
    def advance(self, reaction, moment, dt: float) -> None:
        """Move the pads over one step ``dt`` under the reactions of :meth:`contact_forces`: rotations always,
        vertical motion by mode (semi-implicit Euler, the particles' leap-frog, with local damping)."""
        self.theta += moment / self.rotational_damping * dt     # a massless rocker on a viscous pivot
        for k, mode in enumerate(self.mode):
            if mode == "fixed":
                continue
            if mode == "prescribed":
                self.y[k] = self.y0[k] - self.travel - self.speed * dt
                continue
            fy = self.force[k] + reaction[k, 1]
            fy -= self.alpha * abs(fy) * np.sign(self.vy[k])
            self.vy[k] += fy / self.mass[k] * dt
            self.y[k] += self.vy[k] * dt
        self.travel += self.speed * dt

    def state(self) -> dict:
        """What a checkpoint needs to continue the pads' motion exactly."""
        return {"y": self.y.copy(), "theta": self.theta.copy(), "vy": self.vy.copy(),
                "force": self.force.copy(), "speed": self.speed, "travel": self.travel}

    def restore(self, state: dict) -> None:
        for name, value in state.items():
            setattr(self, name, value.copy() if isinstance(value, np.ndarray) else value)


def _hull_slope(points: np.ndarray, x0: float) -> float:
    """Slope of the line that supports ``points`` (M, 2) from below at ``x0``: the edge of their lower convex hull
    above x₀; where a hull vertex lies at x₀, level if that supports them, else the nearer of the vertex's two
    edges; level where the hull does not span x₀ (one point)."""
    pts = points[np.lexsort((points[:, 1], points[:, 0]))]
    hull = []
    for q in pts:                                         # Andrew's monotone chain, lower half
        while len(hull) >= 2 and np.cross(hull[-1] - hull[-2], q - hull[-2]) <= 0.0:
            hull.pop()
        hull.append(q)
    hull = np.array(hull)
    tol = 1e-12 * max(1.0, abs(x0))
    if len(hull) == 1 or not hull[0, 0] - tol <= x0 <= hull[-1, 0] + tol:
        return 0.0
    slopes = np.diff(hull[:, 1]) / np.diff(hull[:, 0])
    at = np.flatnonzero(np.abs(hull[:, 0] - x0) <= tol)
    if at.size:
        v = int(at[0])
        low = slopes[v - 1] if v > 0 else -np.inf
        high = slopes[v] if v < len(slopes) else np.inf
        return float(np.clip(0.0, low, high))
    return float(slopes[int(np.searchsorted(hull[:, 0], x0)) - 1])
