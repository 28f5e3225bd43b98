"""Contact bonds and parallel bonds (Ch. 4.1.2, Fig. 4.3; Potyondy & Cundall 2004), and the crack record.

*Contact bond*: glue at the contact point. While intact, the linear contact carries tension,
F^n = K^n (U + g₀), and does not slip; it breaks when the tensile force reaches the normal strength f^{n,c} or the
shear force the shear strength f^{t,c} (both forces [N], as in Eq. 5.26). The state lives in the contact's history
(:class:`~abrakit.dem.state.ContactSet`), the failure test in
:func:`~abrakit.dem.contact_laws.force_displacement`.

*Parallel bond*: a disk of cement of radius R̄ = λ̄ min(r_A, r_B) in the contact plane, in parallel with the
contact. With area A = πR̄², I = πR̄⁴/4, J = πR̄⁴/2 and normal/shear stiffness per area k̄^n, k̄^s [Pa/m]:

    ΔF̄^n = k̄^n A ΔU^n,   ΔF̄^s = −k̄^s A ΔU^s,   ΔM̄^n = −k̄^s J Δθ^n,   ΔM̄^s = −k̄^n I Δθ^s,
    σ_max = −F̄^n/A + |M̄^s| R̄/I ≥ σ̄_c → tension crack,   τ_max = |F̄^s|/A + |M̄^n| R̄/J ≥ τ̄_c → shear crack.

Each broken bond is appended to a :class:`CrackLog` with time, position (the contact point), mode and kind.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np

from abrakit.dem.contact_laws import _cross, _dot, _turn_into_plane
from abrakit.dem.state import pair_keys
from abrakit.validation import check_positive


class CrackLog:
    """Broken bonds in the order they broke: ``time`` [s], ``position`` (K, 3) [m], ``i``, ``j``, ``mode``
    ("tension" or "shear") and ``kind`` ("contact", "parallel" or "fatigue")."""

    def __init__(self):
        self._chunks = []

    def record(self, time, position, i, j, mode: str, kind: str) -> None:
        if len(i):
            self._chunks.append((np.full(len(i), float(time)), np.asarray(position, float).reshape(-1, 3),
                                 np.asarray(i), np.asarray(j), np.full(len(i), mode), np.full(len(i), kind)))

    def __len__(self) -> int:
        return sum(len(c[0]) for c in self._chunks)

    def as_arrays(self) -> dict:
        names = ("time", "position", "i", "j", "mode", "kind")
        if not self._chunks:
            empty = (np.zeros(0), np.zeros((0, 3)), np.zeros(0, int), np.zeros(0, int), np.zeros(0, "<U7"),
                     np.zeros(0, "<U8"))
            return dict(zip(names, empty, strict=True))
        return {name: np.concatenate([c[k] for c in self._chunks]) for k, name in enumerate(names)}


def _pair_geometry(sim, i, j):
    d = sim.branch(i, j)
    dist = np.linalg.norm(d, axis=1)
    return d, dist, sim.particles.radius[i] + sim.particles.radius[j] - dist


def install_contact_bonds(sim, normal_strength, shear_strength, *, gap=None, pairs=None) -> int:
    """Bond every particle pair whose gap is at most ``gap`` [m] (or only the given ``pairs`` (K, 2)).

    The default ``gap`` is a round-off tolerance, 10⁻⁹ × the mean radius, so that touching spheres placed on
    a lattice are bonded although their computed overlap may be −10⁻¹⁸ m.

    Strengths are forces f^{n,c}, f^{t,c} [N], scalars or one value per bonded contact (in the order of the
    simulation's contact list restricted to the bonded pairs). Needs a bondable law (linear). Returns the number
    of new bonds.
    """
    if not sim.law.bondable:
        raise ValueError(f"{type(sim.law).__name__} contacts cannot be bonded (the Hertz model has no tension)")
    gap = 1e-9 * float(np.mean(sim.particles.radius)) if gap is None else check_positive("gap", gap, allow_zero=True)
    extra = None if pairs is None else np.sort(np.asarray(pairs, np.int64).reshape(-1, 2), axis=1)
    sim.rebuild(extra_pairs=extra, skin=max(sim.skin, gap))
    c = sim.contacts
    _, _, overlap = _pair_geometry(sim, c.i, c.j)
    new = (overlap >= -gap) & ~c.bonded
    if extra is not None:
        new &= np.isin(c.keys, pair_keys(extra[:, 0], extra[:, 1], len(sim.particles)))
    k = int(new.sum())
    c.bonded[new] = True
    c.bond_gap[new] = np.maximum(-overlap[new], 0.0)
    c.bond_normal_strength[new] = check_positive("normal_strength", np.broadcast_to(normal_strength, (k,)))
    c.bond_shear_strength[new] = check_positive("shear_strength", np.broadcast_to(shear_strength, (k,)))
    c.ft[:, new] = 0.0
    return k


@dataclass
class ParallelBonds:
    """``B`` parallel bonds between particles ``i`` and ``j`` with their forces and moments (state on body j)."""

    i: np.ndarray
    j: np.ndarray
    radius: np.ndarray            # R̄ [m]
    kn: np.ndarray                # k̄^n [Pa/m]
    ks: np.ndarray                # k̄^s [Pa/m]
    tensile_strength: np.ndarray  # σ̄_c [Pa]
    shear_strength: np.ndarray    # τ̄_c [Pa]
    fn: np.ndarray                # F̄^n, compression positive [N]
    fs: np.ndarray                # (3, B) F̄^s [N]
    mn: np.ndarray                # M̄^n twisting moment about n [N m]
    ms: np.ndarray                # (3, B) M̄^s bending moment [N m]

    @classmethod
    def empty(cls) -> ParallelBonds:
        z = np.zeros(0)
        return cls(np.zeros(0, np.int64), np.zeros(0, np.int64), z, z, z, z, z, z, np.zeros((3, 0)), z,
                   np.zeros((3, 0)))

    def __len__(self) -> int:
        return len(self.i)

    @property
    def area(self):
        return np.pi * self.radius**2

    @property
    def inertia(self):
        return 0.25 * np.pi * self.radius**4

    @property
    def polar(self):
        return 0.5 * np.pi * self.radius**4

    def take(self, index) -> ParallelBonds:
        return ParallelBonds(**{f.name: getattr(self, f.name)[..., index] for f in fields(self)})

    def stresses(self):
        """Largest tensile and shear stress on the bond periphery (σ_max, τ_max) [Pa]."""
        sigma = -self.fn / self.area + np.sqrt(_dot(self.ms, self.ms)) * self.radius / self.inertia
        tau = np.sqrt(_dot(self.fs, self.fs)) / self.area + np.abs(self.mn) * self.radius / self.polar
        return sigma, tau

    def energy(self) -> float:
        """Elastic energy stored in the bonds [J]."""
        if not len(self):
            return 0.0
        A, I, J = self.area, self.inertia, self.polar
        return float(np.sum(0.5 * (self.fn**2 / (self.kn * A) + _dot(self.fs, self.fs) / (self.ks * A)
                                   + self.mn**2 / (self.ks * J) + _dot(self.ms, self.ms) / (self.kn * I))))


def candidate_bond_pairs(sim, gap, pairs, existing, kind: str):
    """The pairs ``(i, j)`` to bond: all pairs with gap ≤ ``gap`` (default: a round-off tolerance, as in
    :func:`install_contact_bonds`) or the given ``pairs`` (K, 2), without those already in ``existing`` = (i, j).
    ``kind`` names the bonds in the error raised in a periodic cell (their updates have no minimum image)."""
    p = sim.particles
    if getattr(sim, "periodic", None) is not None:
        raise ValueError(f"{kind} are not supported in a periodic cell (their update has no minimum image)")
    gap = 1e-9 * float(np.mean(p.radius)) if gap is None else check_positive("gap", gap, allow_zero=True)
    if pairs is None:
        sim.rebuild(skin=max(sim.skin, gap))
        i, j = sim.contacts.i, sim.contacts.j
        _, _, overlap = _pair_geometry(sim, i, j)
        keep = overlap >= -gap
        i, j = i[keep], j[keep]
    else:
        pairs = np.sort(np.asarray(pairs, np.int64).reshape(-1, 2), axis=1)
        i, j = pairs[:, 0], pairs[:, 1]
    fresh = ~np.isin(pair_keys(i, j, len(p)), pair_keys(*existing, len(p)))
    return i[fresh], j[fresh]


def install_parallel_bonds(sim, *, kn, ks, tensile_strength, shear_strength, radius_multiplier=1.0, gap=None,
                           pairs=None) -> int:
    """Add parallel bonds between all pairs with gap ≤ ``gap`` (or the given ``pairs``); return how many.

    ``kn``/``ks`` are stiffnesses per area [Pa/m], strengths are stresses [Pa]; R̄ = λ̄ min(r_A, r_B) with
    λ̄ = ``radius_multiplier``. Bonds start stress-free. ``gap`` defaults to a round-off tolerance as in
    :func:`install_contact_bonds`.
    """
    p = sim.particles
    check_positive("radius_multiplier", radius_multiplier)
    i, j = candidate_bond_pairs(sim, gap, pairs, (sim.parallel_bonds.i, sim.parallel_bonds.j), "parallel bonds")
    b = len(i)
    value = lambda name, v: check_positive(name, np.broadcast_to(np.asarray(v, float), (b,)).copy())
    new = ParallelBonds(i, j, radius_multiplier * np.minimum(p.radius[i], p.radius[j]), value("kn", kn),
                        value("ks", ks), value("tensile_strength", tensile_strength),
                        value("shear_strength", shear_strength), np.zeros(b), np.zeros((3, b)), np.zeros(b),
                        np.zeros((3, b)))
    old = sim.parallel_bonds
    sim.parallel_bonds = ParallelBonds(**{f.name: np.concatenate([getattr(old, f.name), getattr(new, f.name)],
                                                                 axis=-1) for f in fields(ParallelBonds)})
    sim.update_time_step()
    return b


def _bond_kinematics(i, j, x, v, w, radius):
    """Geometry and relative motion of bonded pairs ``i``–``j`` (body j relative to body i, Eq. 4.4): unit normal
    ``n`` (3, B) from i to j, lever arms to the contact point, relative velocity at the contact point ``v_rel``
    (3, B), its normal component ``vn`` and the contact point; shared by the parallel and the fatigue bonds."""
    take = lambda a, idx: np.take(a.T, idx, axis=1)
    d = take(x, j) - take(x, i)
    dist = np.sqrt(_dot(d, d))
    n = d / dist
    overlap = radius[i] + radius[j] - dist
    arm_i = radius[i] - 0.5 * overlap                  # centre of A to the contact point, Eq. (4.4)
    arm_j = radius[j] - 0.5 * overlap
    v_rel = take(v, j) - take(v, i) - _cross(arm_i * take(w, i) + arm_j * take(w, j), n)
    return n, arm_i, arm_j, v_rel, _dot(v_rel, n), take(x, i) + arm_i * n


def _parallel_bond_update(bonds: ParallelBonds, x, v, w, radius, dt):
    """One incremental update of all parallel bonds; a pure function of the old bond state.

    Returns ``(new_bonds, force_on_j, torque_on_i, torque_on_j, tension, shear, contact_point)`` (vectors (3, B))
    where the masks mark bonds whose σ_max ≥ σ̄_c (tension) or τ_max ≥ τ̄_c (shear) after the update.
    """
    i, j = bonds.i, bonds.j
    n, arm_i, arm_j, v_rel, vn, point = _bond_kinematics(i, j, x, v, w, radius)
    w_rel = np.take(w.T, j, axis=1) - np.take(w.T, i, axis=1)
    twist = _dot(w_rel, n)
    A, I, J = bonds.area, bonds.inertia, bonds.polar

    fn = bonds.fn - bonds.kn * A * vn * dt              # ΔF̄^n = k̄^n A ΔU^n (ΔU^n = −V^n Δt)
    fs = _turn_into_plane(bonds.fs, n) - bonds.ks * A * dt * (v_rel - vn * n)
    mn = bonds.mn - bonds.ks * J * twist * dt
    ms = _turn_into_plane(bonds.ms, n) - bonds.kn * I * dt * (w_rel - twist * n)
    new = replace(bonds, fn=fn, fs=fs, mn=mn, ms=ms)

    force = fn * n + fs
    moment = mn * n + ms
    lever = _cross(n, force)
    torque_i = -arm_i * lever - moment
    torque_j = -arm_j * lever + moment
    sigma, tau = new.stresses()
    tension = sigma >= bonds.tensile_strength
    shear = ~tension & (tau >= bonds.shear_strength)
    return new, force, torque_i, torque_j, tension, shear, point
