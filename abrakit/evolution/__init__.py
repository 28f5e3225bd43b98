"""Evolution laws from potentials: seed Ch. 2.6 (Eqs. 2.76-2.112) and the updates of Ch. 4 (Eqs. 4.47, 4.53).

A generalized standard material is two potentials: the Helmholtz free energy Ψ(ε, λ) and the dissipation
potential D(λ̇). The driving force is p = -∂Ψ/∂λ (Eq. 2.76); the principle of the minimum of the dissipation
potential (PMDP) picks the rate λ̇ that minimises L = Ψ̇ + D (Eq. 2.104). Over one time step the same principle
becomes the *incremental variational update*

    λ_{m+1} = argmin_λ  Ψ(ε_{m+1}, λ) + Δt · D((λ - λ_m) / Δt),

solved numerically here for any Ψ and D (:func:`variational_update`) and in closed form for two 1D models
(:class:`Damage1D`, :class:`Plasticity1D`) under every time discretisation listed after Eq. (2.110).

Units: any consistent set; the book uses MPa and s, so Ψ, p and r1 are in MPa, D in MPa/s, r2 in MPa·s,
λ̇ in 1/s and Δt in s.

Decisions (stated in the book's chapter on evolution laws): Eq. (2.112)'s switch "|p| > r2" is a misprint for
"|p| > r1"; Eq. (4.53) is read as λ^{m+1} = λ^m + Δt/r2 · [|p(ε^{m+1}, λ^m)| - r1]_+. For a driving force that
can change sign (plasticity) the rate carries sgn(p), which the seed omits because its damage driving force is never
negative.

The time discretisations and the stepping the two models share are in ``abrakit.evolution._schemes``, the minimiser
behind :func:`variational_update` in ``abrakit.evolution._search``.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import solve_ivp
from scipy.special import wrightomega

from abrakit.evolution._schemes import SCHEMES, _check_model, _check_state0, _Model1D
from abrakit.evolution._search import NonConvexWarning as NonConvexWarning  # raised here, filtered by users
from abrakit.evolution._search import _argmin_with_kink
from abrakit.validation import (
    broadcast_shapes,
    check_callable,
    check_finite,
    check_instance,
    check_integer,
    check_number_fields,
    check_option,
    check_positive,
    check_range,
    number_arguments,
)

__all__ = [
    "Plasticity1D", "PlasticState", "Damage1D", "Dissipation", "SCHEMES", "simulate", "rate_independent",
    "rate_dependent", "rate_dependent_update", "variational_update", "elasto_viscoplastic", "convergence_study"
]


def _plus(x):
    """Macaulay bracket [x]_+ = (x + |x|)/2 (after Eq. 2.111)."""
    return 0.5 * (x + np.abs(x))


# ----------------------------------------------------------------------------------------------------------
# Dissipation potentials, Eqs. (2.78)-(2.80), their conjugates and yield functions, Eqs. (2.105)-(2.111)
# ----------------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Dissipation:
    """Dissipation potential D(λ̇) = r1 |λ̇| + r2/2 λ̇², Eq. (2.80).

    ``r2 = 0`` is the rate-independent potential of Eq. (2.78), ``r1 = 0`` the rate-dependent one of
    Eq. (2.79). ``r1`` [MPa] ≥ 0 is the dissipation parameter (threshold), ``r2`` [MPa·s] ≥ 0 the viscosity.
    """

    r1: float = 0.0
    r2: float = 0.0

    def __post_init__(self):
        check_number_fields(self)
        object.__setattr__(self, "r1", check_positive("r1", self.r1, allow_zero=True))
        object.__setattr__(self, "r2", check_positive("r2", self.r2, allow_zero=True))

    @property
    def is_rate_independent(self) -> bool:
        """True for Eq. (2.78): no viscosity, the evolution follows from the yield condition alone."""
        return self.r2 == 0.0

    def value(self, rate):
        """D(λ̇) = r1 |λ̇| + r2/2 λ̇² [MPa/s], Eqs. (2.78)-(2.80)."""
        rate = np.asarray(rate, dtype=float)
        return self.r1 * np.abs(rate) + 0.5 * self.r2 * rate**2

    def subdifferential(self, rate):
        """∂D(λ̇) as an interval (lower, upper) [MPa]: r1 sgn λ̇ + r2 λ̇, and [-r1, r1] at λ̇ = 0."""
        rate = np.asarray(rate, dtype=float)
        lower = np.where(rate > 0, self.r1, -self.r1) + self.r2 * rate
        upper = np.where(rate < 0, -self.r1, self.r1) + self.r2 * rate
        return lower, upper

    def derivative(self, rate):
        """∂D/∂λ̇ = r1 sgn λ̇ + r2 λ̇ [MPa] (the dissipative force of Eq. 2.88 up to sign).

        At λ̇ = 0 the potential has a kink for r1 > 0; the element of the subdifferential of least modulus (0)
        is returned there.
        """
        rate = np.asarray(rate, dtype=float)
        return self.r1 * np.sign(rate) + self.r2 * rate

    def conjugate(self, p):
        """Legendre–Fenchel conjugate D*(p) = sup_λ̇ {p λ̇ - D(λ̇)} [MPa/s], Eq. (2.106).

        r2 > 0: D* = [|p| - r1]_+² / (2 r2). r2 = 0: the indicator of the elastic domain, 0 for |p| ≤ r1 and
        +inf outside (the supremum of Eq. 2.106 is unbounded there).
        """
        p = np.asarray(p, dtype=float)
        excess = _plus(np.abs(p) - self.r1)
        if self.is_rate_independent:
            return np.where(excess > 0, np.inf, 0.0)
        return excess**2 / (2.0 * self.r2)

    def yield_function(self, p, *, squared: bool = False):
        """Φ = |p| - r1 (Eq. 2.108) or Φ = p² - r1² (Eq. 2.107) [MPa or MPa²]; both ≤ 0 in the elastic domain."""
        p = np.asarray(p, dtype=float)
        return p**2 - self.r1**2 if squared else np.abs(p) - self.r1

    def require_rate_dependence(self) -> None:
        """Raise ``ValueError`` for r2 = 0, where no single rate exists."""
        if self.is_rate_independent:
            raise ValueError(
                "r2 must be > 0 for a rate law: with r2 = 0 (Eq. 2.78) λ̇ = Δρ p is fixed by the "
                "Kuhn–Tucker conditions (2.110), use a rate-independent update"
            )

    def rate(self, p):
        """Evolution law λ̇ = sgn(p) [|p| - r1]_+ / r2 [1/s], Eq. (2.111); λ̇ = ∂D*/∂p.

        The seed writes it without sgn(p) since its damage driving force is non-negative. For r2 = 0 the rate
        is set-valued (Eq. 2.105, λ̇ = Δρ p with an unknown consistency parameter) and this raises.
        """
        self.require_rate_dependence()
        p = np.asarray(p, dtype=float)
        return np.sign(p) * _plus(np.abs(p) - self.r1) / self.r2


def rate_independent(r1) -> Dissipation:
    """D = r1 |λ̇|, Eq. (2.78), r1 [MPa] ≥ 0."""
    return Dissipation(r1=r1, r2=0.0)


def rate_dependent(r2) -> Dissipation:
    """D = r2/2 λ̇², Eq. (2.79), r2 [MPa·s] > 0."""
    return Dissipation(r1=0.0, r2=check_positive("r2", r2))


def elasto_viscoplastic(r1, r2) -> Dissipation:
    """D = r1 |λ̇| + r2/2 λ̇², Eq. (2.80), r1 [MPa] ≥ 0 and r2 [MPa·s] > 0."""
    return Dissipation(r1=r1, r2=check_positive("r2", r2))


@number_arguments
def rate_dependent_update(lam_m: ArrayLike, p: ArrayLike, dt: float, dissipation: Dissipation):
    """λ^{m+1} = λ^m + Δt/r2 · sgn(p) [|p| - r1]_+, Eq. (2.112) read with the switch |p| > r1, and Eq. (4.53).

    ``p`` [MPa] is the driving force at whichever time levels the scheme chooses (Eq. 4.53: p(ε^{m+1}, λ^m)).
    The printed Eq. (2.112) switches on |p| > r2, which compares a stress with a viscosity (MPa vs MPa·s) and
    lets λ decrease for r2 < |p| < r1; the printed Eq. (4.53) lacks the bracket, so p = 0 would still change λ.
    """
    check_finite("lam_m", lam_m)
    check_finite("p", p)
    broadcast_shapes(lam_m=lam_m, p=p)
    dt = check_positive("dt", dt)
    check_instance("dissipation", dissipation, Dissipation)
    return np.asarray(lam_m, dtype=float) + dt * dissipation.rate(p)


# ----------------------------------------------------------------------------------------------------------
# Incremental variational update, solved numerically for any Ψ and D
# ----------------------------------------------------------------------------------------------------------


def variational_update(
    free_energy,
    dissipation: Dissipation,
    eps,
    lam_m,
    dt,
    *,
    args=(),
    width=1.0,
    bounds=(-np.inf, np.inf),
    grid: int = 41,
    on_nonconvex: str = "warn",
    max_expansions: int = 60,
):
    """``λ_{m+1} = argmin_λ Ψ(ε_{m+1}, λ, *args) + Δt D((λ - λ_m)/Δt)``, the time-discrete PMDP (Eq. 2.104).

    ``free_energy(eps, lam, *args)`` is any Ψ [MPa] vectorised in ``lam``; ``eps``, ``lam_m``, ``args`` and
    ``width`` broadcast together (one scalar λ per material point). Per point the search:

    1. scans a grid of ``grid`` points on [λ_m - w, λ_m + w] (λ_m itself included, where r1|·| has its kink),
       doubling w while the lowest value sits on an end of the interval (``bounds`` are hard limits), and
       widening it to any of the probe points λ_m ± 2^k w (k = 1…8) that is lower still;
    2. refines every grid basin by bounded Brent minimisation on each side of the kink separately, where the
       incremental potential is smooth, then polishes by Newton steps on a 4th-order finite-difference
       derivative (Brent alone locates a minimum only to about √(machine ε));
    3. returns the lowest candidate. More than one basin means Ψ is non-convex: a :class:`NonConvexWarning`
       (``on_nonconvex="warn"``), a ``RuntimeError`` (``"raise"``) or nothing (``"ignore"``). The answer is then
       the global minimum over the searched interval, resolved to the grid spacing; a well narrower than the
       grid spacing, or beyond every probe point, can be missed (no finite search can rule that out).

    A potential that keeps decreasing through ``max_expansions`` doublings raises ``RuntimeError``.
    """
    check_callable("free_energy", free_energy)
    check_instance("dissipation", dissipation, Dissipation)
    dt = check_positive("dt", dt)
    eps, lam_m = check_finite("eps", eps), check_finite("lam_m", lam_m)
    check_option("on_nonconvex", on_nonconvex, ("warn", "raise", "ignore"))
    grid = check_integer("grid", grid, 5)
    max_expansions = check_integer("max_expansions", max_expansions, 1)
    try:
        lo, hi = (float(b) for b in bounds)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"bounds must be a pair (lower, upper) of numbers, got {bounds!r}") from exc
    if not lo < hi:
        raise ValueError(f"bounds must satisfy lower < upper, got {bounds!r}")
    args = check_instance("args", args, (tuple, list))
    for k, a in enumerate(args):
        check_finite(f"args[{k}]", a)
    check_finite("width", width)
    broadcast_shapes(eps=eps, lam_m=lam_m, width=width, **{f"args[{k}]": a for k, a in enumerate(args)})
    arrays = np.broadcast_arrays(
        np.asarray(eps, dtype=float), np.asarray(lam_m, dtype=float), np.asarray(width, dtype=float),
        *(np.asarray(a, dtype=float) for a in args),
    )
    eps_b, lam_b, width_b, args_b = arrays[0], arrays[1], arrays[2], arrays[3:]
    check_positive("width", width_b)
    if np.any(lam_b < lo) or np.any(lam_b > hi):
        raise ValueError(f"lam_m must lie within bounds {bounds!r}")
    out = np.empty(lam_b.shape)
    for idx in np.ndindex(lam_b.shape):
        point_args = tuple(a[idx] for a in args_b)
        lam_old = lam_b[idx]

        def incremental_potential(lam, e=eps_b[idx], a=point_args, l0=lam_old):
            return free_energy(e, lam, *a) + dt * dissipation.value((lam - l0) / dt)

        out[idx] = _argmin_with_kink(
            incremental_potential, lam_old, width_b[idx], lo, hi, int(grid), on_nonconvex, max_expansions
        )
    return out[()] if out.ndim == 0 else out


# ----------------------------------------------------------------------------------------------------------
# Two 1D models with closed-form updates
# ----------------------------------------------------------------------------------------------------------


class _DamageFields(NamedTuple):
    d: np.ndarray


class DamageState(_DamageFields):
    """State of :class:`Damage1D`: the damage d ≥ 0 [-] of each point (a number or an array).

    The models build their states with ``DamageState._make`` (unchecked); a state built by hand is checked.
    """

    __slots__ = ()

    def __new__(cls, d):
        check_range("d", d, 0.0)
        return super().__new__(cls, d)


@dataclass(frozen=True)
class Damage1D(_Model1D):
    """1D damage: Ψ = f(d) ½ E ε² with f = e^{-d} (``"exp"``, Model I) or (1 - d)² (``"quadratic"``, Model II).

    ``E`` [MPa]. Driving force p = -∂Ψ/∂d = -f'(d) ½ E ε² ≥ 0 (Eq. 2.76), so damage never heals.
    """

    E: float
    damage_function: str = "exp"

    def __post_init__(self):
        check_number_fields(self)
        object.__setattr__(self, "E", check_positive("E", self.E))
        check_option("damage_function", self.damage_function, ("exp", "quadratic"))

    def initial_state(self, shape=()) -> DamageState:
        return DamageState._make((np.zeros(shape),))

    def f(self, d):
        d = np.asarray(d, dtype=float)
        return np.exp(-d) if self.damage_function == "exp" else (1.0 - d) ** 2

    def df(self, d):
        d = np.asarray(d, dtype=float)
        return -np.exp(-d) if self.damage_function == "exp" else -2.0 * (1.0 - d)

    def undamaged_energy(self, eps):
        """ψ0 = ½ E ε² [MPa]."""
        return 0.5 * self.E * np.asarray(eps, dtype=float) ** 2

    def free_energy(self, eps, state: DamageState):
        """Ψ = f(d) ψ0 [MPa]."""
        return self.f(state.d) * self.undamaged_energy(eps)

    def stress(self, eps, state: DamageState):
        """σ = ∂Ψ/∂ε = f(d) E ε [MPa] (Eq. 2.72)."""
        return self.f(state.d) * self.E * np.asarray(eps, dtype=float)

    def driving_force(self, eps, state: DamageState):
        """p = -∂Ψ/∂d = -f'(d) ψ0 [MPa], Eq. (2.76)."""
        return -self.df(state.d) * self.undamaged_energy(eps)

    def yield_function(self, eps, state: DamageState, dissipation: Dissipation):
        """Φ = |p| - r1 [MPa], Eq. (2.108)."""
        return dissipation.yield_function(self.driving_force(eps, state))

    def state_rate(self, eps, state: DamageState, dissipation: Dissipation):
        """ḋ = [p - r1]_+ / r2 [1/s], Eq. (2.111)."""
        return DamageState._make((dissipation.rate(self.driving_force(eps, state)),))

    def backward_step(self, eps, state_m: DamageState, dt, dissipation: Dissipation) -> DamageState:
        """d^{m+1} with p(ε, d^{m+1}) in closed form (Eqs. 2.109, 2.111 backward in d).

        Rate-independent (r2 = 0): consistency f'(d)ψ0 = -r1, so d = max(d^m, ln(ψ0/r1)) for ``"exp"`` and
        max(d^m, 1 - r1/(2ψ0)) for ``"quadratic"``. Rate-dependent: d = d^m + a (p(d) - r1) with a = Δt/r2,
        solved by the Wright ω function (Lambert W of e^z) for ``"exp"`` and linearly for ``"quadratic"``.
        """
        d_m = np.asarray(state_m.d, dtype=float)
        psi0 = self.undamaged_energy(eps)
        r1, r2 = dissipation.r1, dissipation.r2
        active = self.driving_force(eps, state_m) > r1  # trial: Φ(ε, d^m) > 0
        if dissipation.is_rate_independent and r1 == 0.0 and np.any(active & (psi0 > 0)):
            raise ValueError("r1 must be > 0 for rate-independent damage: with no threshold d grows without bound")
        psi0 = np.where(active, psi0, 1.0)  # keeps log/ratio finite off the active set
        if self.damage_function == "exp":
            if dissipation.is_rate_independent:
                d_new = np.log(psi0 / max(r1, 1e-300))
            else:
                a = dt / r2
                # y = d - d^m + a r1 solves y e^y = a ψ0 e^{a r1 - d^m}: y = ω(ln(a ψ0) + a r1 - d^m)
                d_new = d_m - a * r1 + wrightomega(np.log(a * psi0) + a * r1 - d_m).real
                for _ in range(2):  # Newton polish of the well-scaled residual (r2/Δt)(d - d^m) - (p - r1)
                    g = (d_new - d_m) / a - (psi0 * np.exp(-d_new) - r1)
                    d_new = d_new - g / (1.0 / a + psi0 * np.exp(-d_new))
        else:
            if dissipation.is_rate_independent:
                d_new = 1.0 - r1 / (2.0 * psi0)
            else:
                a = dt / r2
                d_new = (d_m + a * (2.0 * psi0 - r1)) / (1.0 + 2.0 * a * psi0)
        return DamageState._make((np.where(active, np.maximum(d_new, d_m), d_m),))

    def forward_step(self, eps, state_m: DamageState, dt, dissipation: Dissipation) -> DamageState:
        new = super().forward_step(eps, state_m, dt, dissipation)
        if self.damage_function == "quadratic" and np.any(new.d > 1.0):
            raise RuntimeError("forward step pushed d above 1 (f = (1 - d)² would grow again); reduce dt")
        return new

    def incremental_free_energy(self, state_m: DamageState):
        """(Ψ(ε, d), args) for :func:`variational_update`."""
        def psi(eps, d):
            return self.f(d) * self.undamaged_energy(eps)

        return psi, ()

    def variational_step(self, eps, state_m: DamageState, dt, dissipation: Dissipation, **kw) -> DamageState:
        """d^{m+1} by numerical minimisation of Ψ(ε, d) + Δt D((d - d^m)/Δt)."""
        psi, args = self.incremental_free_energy(state_m)
        bounds = (0.0, 1.0) if self.damage_function == "quadratic" else (0.0, np.inf)
        kw = {"width": 1.0, "bounds": bounds} | kw
        return DamageState._make((variational_update(psi, dissipation, eps, state_m.d, dt, args=args, **kw),))


class _PlasticFields(NamedTuple):
    eps_p: np.ndarray
    alpha: np.ndarray


class PlasticState(_PlasticFields):
    """State of :class:`Plasticity1D`: plastic strain εp [-] and accumulated plastic strain α = ∫|ε̇p| dt ≥ 0 [-]
    of each point (numbers or arrays that broadcast together).

    The models build their states with ``PlasticState._make`` (unchecked); a state built by hand is checked.
    """

    __slots__ = ()

    def __new__(cls, eps_p, alpha):
        check_finite("eps_p", eps_p)
        check_range("alpha", alpha, 0.0)
        broadcast_shapes(eps_p=eps_p, alpha=alpha)
        return super().__new__(cls, eps_p, alpha)


@dataclass(frozen=True)
class Plasticity1D(_Model1D):
    """1D plasticity with linear isotropic hardening: Ψ = ½ E (ε - εp)² + ½ K α², α̇ = |ε̇p|.

    ``E``, ``K`` [MPa]. Driving force p = -∂Ψ/∂εp = E (ε - εp) = σ (Eq. 2.76); the hardening force -∂Ψ/∂α = -Kα
    raises the threshold, Φ = |p| - (r1 + K α) (Eq. 2.108; compare Φp of Table 6.1, read with "+": see
    :mod:`abrakit.materials.plasticity`).
    """

    E: float
    K: float = 0.0

    def __post_init__(self):
        check_number_fields(self)
        object.__setattr__(self, "E", check_positive("E", self.E))
        object.__setattr__(self, "K", check_positive("K", self.K, allow_zero=True))

    def initial_state(self, shape=()) -> PlasticState:
        return PlasticState._make((np.zeros(shape), np.zeros(shape)))

    def free_energy(self, eps, state: PlasticState):
        """Ψ = ½ E (ε - εp)² + ½ K α² [MPa]."""
        return 0.5 * self.E * (np.asarray(eps, float) - state.eps_p) ** 2 + 0.5 * self.K * state.alpha**2

    def stress(self, eps, state: PlasticState):
        """σ = E (ε - εp) [MPa] (Eq. 2.72)."""
        return self.E * (np.asarray(eps, dtype=float) - state.eps_p)

    def driving_force(self, eps, state: PlasticState):
        """p = -∂Ψ/∂εp = E (ε - εp) [MPa], Eq. (2.76)."""
        return self.stress(eps, state)

    def yield_function(self, eps, state: PlasticState, dissipation: Dissipation):
        """Φ = |p| - (r1 + K α) [MPa], Eq. (2.108) with hardening."""
        return np.abs(self.driving_force(eps, state)) - (dissipation.r1 + self.K * np.asarray(state.alpha))

    def state_rate(self, eps, state: PlasticState, dissipation: Dissipation):
        """ε̇p = sgn(p) [Φ]_+ / r2, α̇ = |ε̇p| [1/s], Eq. (2.111) with the hardened threshold."""
        dissipation.require_rate_dependence()
        flow = _plus(self.yield_function(eps, state, dissipation)) / dissipation.r2
        return PlasticState._make((np.sign(self.driving_force(eps, state)) * flow, flow))

    def backward_step(self, eps, state_m: PlasticState, dt, dissipation: Dissipation) -> PlasticState:
        """Return mapping with p(ε, λ^{m+1}): Δα = [Φ_trial]_+ / (E + K + r2/Δt), Δεp = sgn(p_trial) Δα.

        r2 = 0 is the rate-independent update (2.109) with the consistency condition Φ(ε, λ^{m+1}) = 0 (2.110).
        """
        p_trial = self.driving_force(eps, state_m)
        step = _plus(self.yield_function(eps, state_m, dissipation)) / (self.E + self.K + dissipation.r2 / dt)
        return PlasticState._make((state_m.eps_p + np.sign(p_trial) * step, state_m.alpha + step))

    def incremental_free_energy(self, state_m: PlasticState):
        """(Ψ(ε, εp, εp^m, α^m), args) with α = α^m + |εp - εp^m| eliminated, for :func:`variational_update`."""
        def psi(eps, eps_p, eps_p_m, alpha_m):
            alpha = alpha_m + np.abs(eps_p - eps_p_m)
            return 0.5 * self.E * (eps - eps_p) ** 2 + 0.5 * self.K * alpha**2

        return psi, (state_m.eps_p, state_m.alpha)

    def variational_step(self, eps, state_m: PlasticState, dt, dissipation: Dissipation, **kw) -> PlasticState:
        """εp^{m+1} by numerical minimisation of Ψ(ε, εp) + Δt D((εp - εp^m)/Δt); α follows from α̇ = |ε̇p|."""
        psi, args = self.incremental_free_energy(state_m)
        gap = np.abs(np.asarray(eps, float) - state_m.eps_p)  # the minimiser lies between εp^m and ε
        kw = {"width": np.where(gap > 0, gap, 1.0)} | kw
        eps_p = variational_update(psi, dissipation, eps, state_m.eps_p, dt, args=args, **kw)
        return PlasticState._make((eps_p, state_m.alpha + np.abs(eps_p - state_m.eps_p)))


# ----------------------------------------------------------------------------------------------------------
# Driving a material point, reference solutions and convergence in Δt
# ----------------------------------------------------------------------------------------------------------


def simulate(model, strain, time, dissipation: Dissipation, scheme: str = "implicit", state0=None, **kw):
    """Drive material point(s) along ``strain[m]`` at ``time[m]`` (leading axis = time); returns a dict of
    arrays ``time``, ``strain``, ``stress`` and one entry per state field (e.g. ``d`` or ``eps_p``, ``alpha``).

    ``**kw`` are options of :func:`variational_update` (``scheme="variational"`` only).
    """
    _check_model(model)
    time = np.asarray(check_finite("time", time))
    strain = np.asarray(check_finite("strain", strain))
    if time.ndim != 1 or time.size < 1:
        raise ValueError(f"time must be a 1D array of at least one instant, got shape {time.shape}")
    if strain.shape[:1] != time.shape:
        raise ValueError(f"strain must have the time axis first: time {time.shape}, strain {strain.shape}")
    if np.any(np.diff(time) <= 0):
        raise ValueError("time must increase strictly (dt > 0)")
    check_instance("dissipation", dissipation, Dissipation)
    check_option("scheme", scheme, (*SCHEMES, "variational"))
    if kw and scheme != "variational":
        raise TypeError(f"options {sorted(kw)} are options of scheme='variational', not of scheme={scheme!r}")
    state0 = _check_state0(model, state0, strain.shape[1:])
    state = model.initial_state(strain.shape[1:]) if state0 is None else state0
    states = [state]
    for m in range(time.size - 1):
        state = model.update(state, strain[m], strain[m + 1], time[m + 1] - time[m], dissipation, scheme, **kw)
        states.append(state)
    history = {name: np.array([np.broadcast_to(s[i], strain.shape[1:]) for s in states])
               for i, name in enumerate(state._fields)}
    stress = np.array([model.stress(e, s) for e, s in zip(strain, states, strict=True)])
    return {"time": time, "strain": strain, "stress": stress} | history


def reference_solution(model, strain_fn, time, dissipation: Dissipation, state0=None, rtol=1e-12, atol=1e-15):
    """State history at ``time`` from the rate law λ̇ = λ̇(ε(t), λ) (Eq. 2.111) integrated by an adaptive
    8th-order Runge–Kutta method (DOP853): an independent reference for the time-stepping schemes.
    Needs r2 > 0; ``strain_fn(t)`` returns the (scalar) strain.
    """
    check_instance("dissipation", dissipation, Dissipation).require_rate_dependence()
    time = check_finite("time", time)                    # a NaN time or tolerance made the integrator hang
    if np.ndim(time) != 1 or len(time) < 2 or np.any(np.diff(time) <= 0):
        raise ValueError("time must be an increasing 1D array of at least two instants")
    check_range("rtol", rtol, 0.0, 1.0, low_open=True, high_open=True)
    check_positive("atol", atol)
    _check_model(model)
    check_callable("strain_fn", strain_fn)
    state0 = _check_state0(model, state0)
    state = model.initial_state() if state0 is None else state0
    fields = type(state)

    def rhs(t, y):
        return np.array(model.state_rate(strain_fn(t), fields._make(y), dissipation), dtype=float)

    sol = solve_ivp(rhs, (time[0], time[-1]), np.array(state, dtype=float), method="DOP853", t_eval=time,
                    rtol=rtol, atol=atol)
    if not sol.success:
        raise RuntimeError(f"reference integration failed: {sol.message}")
    return {name: sol.y[i] for i, name in enumerate(fields._fields)}


@number_arguments
def observed_order(dt: ArrayLike, error: ArrayLike, last: int = 3) -> float:
    """Slope of log(error) over log(Δt) through the ``last`` smallest steps (least squares); Δt > 0 and
    error > 0 are 1D arrays of one length, ``last`` ≥ 2."""
    check_positive("dt", dt)
    check_positive("error", error)
    last = check_integer("last", last, 2)
    if np.ndim(dt) != 1 or np.shape(error) != np.shape(dt):
        raise ValueError(f"dt and error must be 1D arrays of one length, got {np.shape(dt)} and {np.shape(error)}")
    dt, error = np.asarray(dt, float), np.asarray(error, float)
    if np.unique(dt[np.argsort(dt)[:last]]).size < 2:
        raise ValueError(f"dt must hold at least two distinct steps among its {last} smallest, got {dt!r}")
    keep = np.argsort(dt)[:last]
    return float(np.polyfit(np.log(dt[keep]), np.log(error[keep]), 1)[0])


def convergence_study(model, dissipation: Dissipation, strain_fn, t_end, n_steps=(16, 32, 64, 128, 256),
                      schemes=(*SCHEMES, "variational"), repeats: int = 1, reference_kw=None, on_result=None):
    """Error of each scheme against :func:`reference_solution` over Δt = t_end/n, with runtimes [s].

    The error is max over the steps of |λ_m - λ_ref(t_m)| for the model's first internal variable; the runtime
    is the best of ``repeats`` runs of :func:`simulate`. ``on_result(scheme=, n_steps=, dt=, error=, runtime=)``
    is called after each run (to stream results to disk). Returns
    ``{scheme: {"n_steps", "dt", "error", "runtime"}, "orders": {scheme: observed order}}``.
    """
    _check_model(model)
    check_instance("dissipation", dissipation, Dissipation).require_rate_dependence()
    check_callable("strain_fn", strain_fn)
    t_end = check_positive("t_end", t_end)
    check_instance("n_steps", n_steps, (tuple, list, np.ndarray))
    n_steps = [check_integer("n_steps", n, 1) for n in np.ravel(n_steps)]
    if len(set(n_steps)) < 2:
        raise ValueError(f"n_steps must hold at least two distinct numbers of steps (an order needs two), "
                         f"got {n_steps!r}")
    if isinstance(schemes, str) or not isinstance(schemes, tuple | list) or not schemes:
        raise TypeError(f"schemes must be a non-empty tuple of scheme names, got {schemes!r}")
    for scheme in schemes:
        check_option("scheme", scheme, (*SCHEMES, "variational"))
    repeats = check_integer("repeats", repeats, 1)
    check_instance("reference_kw", reference_kw, dict, optional=True)
    check_callable("on_result", on_result, optional=True)
    field = model.initial_state()._fields[0]
    result = {scheme: {"n_steps": [], "dt": [], "error": [], "runtime": []} for scheme in schemes}
    for n in n_steps:
        time = np.linspace(0.0, t_end, int(n) + 1)
        reference = reference_solution(model, strain_fn, time, dissipation, **(reference_kw or {}))[field]
        strain = np.array([strain_fn(t) for t in time])
        for scheme in schemes:
            runtime = np.inf
            for _ in range(repeats):
                tic = _time.perf_counter()
                history = simulate(model, strain, time, dissipation, scheme)
                runtime = min(runtime, _time.perf_counter() - tic)
            row = {"n_steps": int(n), "dt": t_end / int(n), "runtime": runtime,
                   "error": float(np.max(np.abs(history[field] - reference)))}
            for key, value in row.items():
                result[scheme][key].append(value)
            if on_result is not None:
                on_result(scheme=scheme, **row)
    result = {scheme: {k: np.array(v) for k, v in rows.items()} for scheme, rows in result.items()}
    for scheme in schemes:
        if np.any(result[scheme]["error"] == 0.0):
            raise ValueError(f"strain_fn gives scheme {scheme!r} an error of exactly 0 at some Δt (a path on which "
                             "the state does not evolve?): its order is undefined")
    result["orders"] = {s: observed_order(result[s]["dt"], result[s]["error"]) for s in schemes}
    return result

