"""Fatigue bonds in the DEM engine: the damage-plasticity bond of seed 002 between particle pairs.

Each bond is a rectangle of width L = 2 λ̄ min(r_A, r_B) and thickness t (area A = L t; t = 1 m for the paper's 2D
assemblies) in parallel with the ordinary contact, like a parallel bond but without moments (the paper's bond carries
normal and shear stress only). Its kinematics are incremental: the elastic normal opening e_n and shear vector e_s
grow by the relative velocity at the contact point times Δt, e_s turning with the contact plane. The constitutive
update is :func:`abrakit.fatigue.bond_law.plastic_return` with (e_n, |e_s|), vectorised over the bonds; the force
on particle j is −A (σ_n n + σ_s e_s/|e_s|).

Load cycles are the caller's: :meth:`FatigueBonds.onset_of_unloading` is called where the loading programme turns
from loading to unloading. It applies Paris' law to every bond that exceeded its fatigue criterion at its peak and
did not yield during the cycle (the shift factor E of Eq. 17), with the stress ranges seen since the previous call,
and optionally the cycle jump; the stress update of Eqs. (38, 39) follows from the new internal variables.

A bond whose damage reaches the failure damage D_fail = 1 − 10⁻⁶ (:data:`~abrakit.fatigue.bond_law.FAILURE_DAMAGE`)
is removed and logged as a crack (the ordinary contact keeps acting in compression).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, fields

import numpy as np

from abrakit.dem.bonds import _bond_kinematics, candidate_bond_pairs
from abrakit.dem.contact_laws import _cross, _dot, _turn_into_plane
from abrakit.dem.kernels import HAVE_NUMBA, fatigue_bond_finish, fatigue_bond_trial
from abrakit.fatigue._return_kernel import plastic_return_bonds
from abrakit.fatigue.bond_law import FAILURE_DAMAGE, MAX_HALVINGS, BondParameters, plastic_return
from abrakit.fatigue.paris import cycle_update, peak_failure_damage
from abrakit.validation import check_option, check_positive

BROKEN = FAILURE_DAMAGE
"""The damage at which a bond is removed (:data:`~abrakit.fatigue.bond_law.FAILURE_DAMAGE`)."""

COMPILED_UPDATE = HAVE_NUMBA
"""Whether :meth:`FatigueBonds.update` takes the compiled elastic trial by default (where numba is installed); set
it to False for the NumPy path (``benchmarks/bench_fatigue_bond_kernel.py`` compares the two)."""

COMPILED_RETURN = HAVE_NUMBA
"""Whether the compiled update returns its yielding bonds with the compiled return map
(:func:`abrakit.fatigue._return_kernel.plastic_return_bonds`, which also halves the steps where Newton fails;
the NumPy :func:`~abrakit.fatigue.bond_law.plastic_return` otherwise, and for a bond that fails at the deepest
split short of the failure damage, where it raises). ``benchmarks/bench_fatigue_bond_kernel.py`` measures the
saving and the agreement of the two."""


@dataclass
class FatigueBonds:
    """``B`` fatigue bonds between particles ``i`` and ``j``; per-bond state arrays, shared ``params``."""

    i: np.ndarray
    j: np.ndarray
    width: np.ndarray            # L [m]
    area: np.ndarray             # A = L t [m²]
    kn: np.ndarray               # k_n [Pa/m]
    ks: np.ndarray               # k_s [Pa/m]
    elastic_n: np.ndarray        # e_n = u_n − u_nᵖ − u_nᶠ [m], opening positive
    elastic_s: np.ndarray        # (3, B) e_s [m]
    damage: np.ndarray           # D
    plastic: np.ndarray          # (2, B) accumulated |Δuᵖ| normal, shear [m]
    fatigue: np.ndarray          # (2, B) accumulated |Δuᶠ| normal, shear [m]
    sigma: np.ndarray            # (2, B) current σ_n, σ_s = |σ_s| [Pa]
    peak: np.ndarray             # (2, B) largest σ_n, σ_s since the last cycle update
    low: np.ndarray              # (2, B) smallest σ_n, σ_s since the last cycle update
    ratchet: np.ndarray          # (2, B) |Δuᵖ| normal, shear since the last cycle update [m]
    params: BondParameters

    @classmethod
    def empty(cls, params: BondParameters | None = None) -> FatigueBonds:
        z = np.zeros(0)
        return cls(np.zeros(0, np.int64), np.zeros(0, np.int64), z, z, z, z, z, np.zeros((3, 0)), z, np.zeros((2, 0)),
                   np.zeros((2, 0)), np.zeros((2, 0)), np.zeros((2, 0)), np.zeros((2, 0)), np.zeros((2, 0)),
                   BondParameters() if params is None else params)

    def __len__(self) -> int:
        return len(self.i)

    @property
    def yielded(self) -> np.ndarray:
        """Bonds that yielded since the last cycle update (E = 0 in Eq. 17): those with plastic flow in
        :attr:`ratchet`."""
        return self.ratchet.sum(axis=0) > 0.0

    def take(self, index) -> FatigueBonds:
        value = lambda name: getattr(self, name) if name == "params" else getattr(self, name)[..., index]
        return FatigueBonds(**{f.name: value(f.name) for f in fields(self)})

    def energy(self) -> float:
        """Elastic energy stored in the bonds, ½ A σ·e summed [J]."""
        if not len(self):
            return 0.0
        return float(0.5 * np.sum(self.area * (self.sigma[0] * self.elastic_n
                                               + self.sigma[1] * np.sqrt(_dot(self.elastic_s, self.elastic_s)))))

    def update(self, x, v, w, radius, dt, *, compiled: bool | None = None):
        """One incremental step; returns ``(new_bonds, force_on_j, torque_on_i, torque_on_j, contact_point)``.

        ``compiled`` (default :data:`COMPILED_UPDATE`: where numba is installed) takes the kinematics, the elastic
        trial and the yield test in one compiled loop (:func:`abrakit.dem.kernels.fatigue_bond_trial`) and returns
        only the bonds that yield, in a second compiled loop (:data:`COMPILED_RETURN`); the NumPy path returns every
        bond through :func:`~abrakit.fatigue.bond_law.plastic_return`. Both give the same bonds to the return's
        tolerance (``tests/test_fatigue_dem.py``)."""
        if compiled is None:
            compiled = COMPILED_UPDATE
        if compiled:
            du_n, du_s, damage, sigma_n, sigma_s, trial_n, trial_s, size_s, n, arm_i, arm_j, point = \
                self._compiled_trial(x, v, w, radius, dt)
        else:
            n, arm_i, arm_j, v_rel, vn, point = _bond_kinematics(self.i, self.j, x, v, w, radius)
            start_n, start_s = self.elastic_n, _turn_into_plane(self.elastic_s, n)
            trial_n = start_n + vn * dt
            trial_s = start_s + (v_rel - vn * n) * dt
            size_s = np.sqrt(_dot(trial_s, trial_s))
            du_n, du_s, damage, sigma_n, sigma_s = plastic_return(
                trial_n, size_s, self.damage, self.params, start=(start_n, np.sqrt(_dot(start_s, start_s))),
                stiffness=(self.kn, self.ks))
        return *self._finish(trial_n, trial_s, size_s, du_n, du_s, damage, sigma_n, sigma_s, n, arm_i, arm_j,
                             compiled=compiled), point

    def _finish(self, trial_n, trial_s, size_s, du_n, du_s, damage, sigma_n, sigma_s, n, arm_i, arm_j, *,
                compiled: bool):
        """After the return: the new bonds (e_s shortened by its plastic part, the stress extremes and plastic flow
        of the cycle) and the force on j, −A (σ_n n + k_s (1 − D) e_s), with its torques on i and j. ``compiled``:
        the same operations in one loop (:func:`abrakit.dem.kernels.fatigue_bond_finish`), the same numbers to the
        last bit."""
        new = copy.copy(self)
        new.damage = damage
        if compiled:
            new.elastic_n, new.elastic_s, new.sigma, new.plastic, new.peak, new.low, new.ratchet, *loads = \
                fatigue_bond_finish(trial_n, trial_s, size_s, du_n, du_s, damage, sigma_n, sigma_s, n, arm_i, arm_j,
                                    self.area, self.ks, self.plastic, self.peak, self.low, self.ratchet)
            return new, *loads
        shrink = np.divide(size_s - du_s, size_s, out=np.ones_like(size_s), where=size_s > 0)
        new.elastic_n, new.elastic_s = trial_n - du_n, trial_s * shrink
        new.sigma = sigma = np.array([sigma_n, sigma_s])
        flow = np.abs([du_n, du_s])
        new.plastic, new.ratchet = self.plastic + flow, self.ratchet + flow
        new.peak, new.low = np.maximum(self.peak, sigma), np.minimum(self.low, sigma)
        force = -self.area * (sigma_n * n + self.ks * (1.0 - damage) * new.elastic_s)
        lever = _cross(n, force)
        return new, force, -arm_i * lever, -arm_j * lever

    def _compiled_trial(self, x, v, w, radius, dt):
        """The compiled elastic trial of every bond, then the plastic return of the bonds that yield."""
        p = self.params
        n, arm_i, arm_j, point, start_size, trial_n, trial_s, size_s, sigma_n, sigma_s, active = fatigue_bond_trial(
            self.i, self.j, np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(v, dtype=float),
            np.ascontiguousarray(w, dtype=float), radius, self.elastic_n, np.ascontiguousarray(self.elastic_s),
            self.damage, self.kn, self.ks, float(dt), p.cohesion, p.tensile_strength, p.tan_phi, p.alpha, 1e-12)
        du_n, du_s, damage = np.zeros_like(size_s), np.zeros_like(size_s), self.damage.copy()
        f = a = np.flatnonzero(active)
        if a.size and COMPILED_RETURN:
            du_n[a], du_s[a], damage[a], sigma_n[a], sigma_s[a], converged = plastic_return_bonds(
                trial_n[a], size_s[a], self.damage[a], self.kn[a], self.ks[a], p.un, p.us, p.cohesion,
                p.tensile_strength, p.tan_phi, p.tan_psi, p.alpha, 1e-12, 60, self.elastic_n[a], start_size[a],
                MAX_HALVINGS)
            f = a[~converged]                  # failed at the deepest split short of D_fail: the NumPy return raises
        if f.size:
            du_n[f], du_s[f], damage[f], sigma_n[f], sigma_s[f] = plastic_return(
                trial_n[f], size_s[f], self.damage[f], p, start=(self.elastic_n[f], start_size[f]),
                stiffness=(self.kn[f], self.ks[f]))
        return du_n, du_s, damage, sigma_n, sigma_s, trial_n, trial_s, size_s, n, arm_i, arm_j, point

    def onset_of_unloading(self, *, jump: float | None = None, max_cycles=None, hold_while_yielding=False,
                           plasticity: str = "frozen") -> int:
        """The fatigue update of one load cycle at the onset of its unloading (Sec. 3.2, Fig. 5), in place.

        Bonds that did not yield since the last call and whose peak stress exceeds the fatigue criterion (Eq. 23)
        gain ΔD_f by Paris' law (Eq. 27) with the ranges peak − low (mode I: tensile part only), and the fatigue
        displacements of Eqs. (35–37), which lower their stresses as Eqs. (38, 39) state. With ``jump`` = ΔD_jump
        the increments are extrapolated over N_jump cycles (Eqs. 40, 41).

        ``plasticity`` says what the jump does with bonds that yielded in the sampled cycle: "frozen" (the paper)
        gives them neither fatigue nor plastic damage during the jump; "extrapolated" repeats their plastic
        displacement increment of the sampled cycle in each skipped cycle (damage by Eq. 22, elastic displacements
        lowered like the fatigue displacements) and counts its damage rate in N_jump (decision "ratcheting in the
        cycle jump"). With ``hold_while_yielding`` no jump follows a cycle in which any bond yielded (a steadier but,
        where bonds ratchet every cycle, a jump-free run). A jump stops before the cycle in which a bond's damage
        would shrink its surface onto its peak stress (:meth:`_failure_limit`): that cycle, where the bond yields, is
        simulated. Returns the number of cycles this update stands for (1 without a jump); the stress record
        restarts from the current stresses."""
        check_option("plasticity", plasticity, ("frozen", "extrapolated"))
        count = 1
        if len(self):
            if hold_while_yielding and self.yielded.any():
                jump = None
            ratchet = self.ratchet if plasticity == "extrapolated" else None
            count, increment, du_n, du_s, skipped = cycle_update(
                self.damage, self.peak, self.low, self.params, width=self.width, eligible=~self.yielded, jump=jump,
                max_cycles=max_cycles, ratchet=ratchet, limit=None if jump is None else self._failure_limit())
            du_s = np.abs(du_s)                             # along e_s: the shear stress here is a magnitude
            size_s = np.sqrt(_dot(self.elastic_s, self.elastic_s))
            self.elastic_n = self.elastic_n - du_n - skipped[0]
            self.elastic_s = self.elastic_s * np.divide(np.maximum(size_s - du_s - skipped[1], 0.0), size_s,
                                                        out=np.ones_like(size_s), where=size_s > 0)
            self.damage = np.minimum(self.damage + increment, 1.0)
            self.fatigue = self.fatigue + np.array([du_n, du_s])
            self.plastic = self.plastic + skipped
            self.restart_cycle()
        return count

    def _failure_limit(self) -> np.ndarray:
        """The damage each bond's jump must stop short of (:func:`~abrakit.fatigue.paris.cycle_jump`'s ``limit``):
        the damage at which its surface shrinks onto its recorded peak (σ_n, σ_s) (:func:`~abrakit.fatigue.paris.
        peak_failure_damage`), so that the cycle in which a bond would yield is simulated, not jumped over; none
        (1) for a bond that yielded in the sampled cycle or whose componentwise peak already lies on or outside its
        surface (it is not fatigued, or the extremes of σ_n and σ_s came at different instants)."""
        failure = peak_failure_damage(self.damage, self.peak[0], self.peak[1], self.params)
        return np.where(self.yielded | (failure <= self.damage), 1.0, failure)

    def restart_cycle(self) -> None:
        """Forget the stress extremes and the plastic flow (hence the yield flags) recorded so far (e.g. after a
        monotonic pre-load)."""
        self.peak, self.low = self.sigma.copy(), self.sigma.copy()
        self.ratchet = np.zeros((2, len(self)))


def install_fatigue_bonds(sim, params: BondParameters, *, thickness=1.0, width_multiplier=1.0, gap=None,
                          pairs=None, modulus=None, stiffness_ratio=None) -> int:
    """Add fatigue bonds between all pairs with gap ≤ ``gap`` (or the given ``pairs`` (K, 2)); return how many.

    The width is L = 2 λ̄ min(r_A, r_B) with λ̄ = ``width_multiplier``; the area L × ``thickness`` (1 m for the
    paper's 2D assemblies). All bonds share ``params``; its ``width`` is ignored (each bond has its own L). With
    ``modulus`` = E_c and ``stiffness_ratio`` = k_n/k_s the stiffnesses follow the deformable method of Potyondy &
    Cundall (2004): k_n = E_c / (r_A + r_B), k_s = k_n / ratio (seed 002 Sec. 5.2); otherwise ``params.kn``,
    ``params.ks``. Bonds start stress-free (at their current gap) with D = D₀."""
    check_positive("thickness", thickness)
    check_positive("width_multiplier", width_multiplier)
    if not isinstance(params, BondParameters):
        raise TypeError(f"params must be a BondParameters, got {type(params).__name__}")
    i, j = candidate_bond_pairs(sim, gap, pairs, (sim.fatigue_bonds.i, sim.fatigue_bonds.j), "fatigue bonds")
    r = sim.particles.radius
    width = 2.0 * width_multiplier * np.minimum(r[i], r[j])
    b = len(i)
    if (modulus is None) != (stiffness_ratio is None):
        raise ValueError("give both modulus and stiffness_ratio (deformable method) or neither")
    if modulus is None:
        kn, ks = np.full(b, params.kn), np.full(b, params.ks)
    else:
        kn = check_positive("modulus", modulus) / (r[i] + r[j])
        ks = kn / check_positive("stiffness_ratio", stiffness_ratio)
    z2 = np.zeros((2, b))
    new = FatigueBonds(i, j, width, width * thickness, kn, ks, np.zeros(b), np.zeros((3, b)),
                       np.full(b, params.initial_damage), z2, z2.copy(), z2.copy(), z2.copy(), z2.copy(),
                       z2.copy(), params)
    old = sim.fatigue_bonds
    if len(old) and old.params != params:
        raise ValueError("all fatigue bonds of a simulation share one BondParameters")
    sim.fatigue_bonds = FatigueBonds(**{f.name: params if f.name == "params" else
                                        np.concatenate([getattr(old, f.name), getattr(new, f.name)], axis=-1)
                                        for f in fields(FatigueBonds)})
    sim.update_time_step()
    return b
