"""Model II at a material point: relaxation-based damage with an emulated RVE, Eq. (6.81)-(6.105), Algorithm 2.

Each point carries an ERVE of ``n`` sub-domains of equal volume with damage ``d_i`` and ``f(d_i) = (1 - d_i)^2``
(6.12). Relaxing the sub-domain strains gives

    f_bar = n / sum_i 1/f(d_i)                   (6.87)    eps_i = f_bar / f(d_i) eps      (6.88)
    Psi_rel = f_bar Psi0                         (6.89)    sigma = f_bar E : (eps - eps_p)  (6.99)
    p_d,i = -f_bar^2 f'(d_i) / (n f(d_i)^2) Psi0 (6.94)

A sub-domain whose driving force exceeds ``r_d / n`` grows by the rate limit ``alpha l_ext dt`` (6.95, 6.98,
6.103), capped at ``d_i <= 0.999``; the sub-domains are visited in order and ``f_bar`` is refreshed after each
one (Algorithm 2), so that with equal initial damage the ERVE localises into a few sub-domains.

Plasticity uses ``f_bar`` of the old step (explicit Euler as in Model I, Algorithm 2).

Deviations (recorded in the book):

- the stress is Eq. (6.99) evaluated at the new state, ``f_bar(d^{m+1}) E : (eps^{m+1} - eps_p^{m+1})``,
  not its first-order Taylor expansion (6.102), which can turn negative for large damage jumps;
- ``d f_bar / d d_j = f_bar^2 f'(d_j) / (n f(d_j)^2)``: Eq. (6.102)/(6.105) print ``f_bar`` instead of
  ``f_bar^2``; the square is consistent with (6.94) and is used here.

Tangents: ``"consistent"`` (default) is the derivative of this update; the damage rule is piecewise constant in
the strain (a sub-domain grows by the fixed increment or not at all), so ``d d / d eps = 0`` almost everywhere
and the tangent is ``f_bar^{m+1}/f_bar^m`` times the elastoplastic one. ``"seed"`` is Eq. (6.105) as printed,
``f_bar(d^m) E`` plus the rank-one term with the finite-difference derivative ``d d / d Psi0`` (6.104,
``tol = 1e-8``), which vanishes unless a threshold lies within ``tol`` of Psi0, where it is huge.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..validation import (
    check_finite,
    check_number_fields,
    check_option,
    check_poisson,
    check_positive,
    check_range,
    number_arguments,
)
from .base import IsotropicElasticity, MaterialResponse, _outer, check_strain
from .plasticity import INTEGRATIONS, plastic_step

TANGENTS = ("consistent", "seed")
DAMAGE_ENERGIES = ("full", "tension")


@number_arguments
def damage_function(d: ArrayLike):
    """``f(d) = (1 - d)^2``, Eq. (6.12)."""
    return (1.0 - np.asarray(d, dtype=float)) ** 2


@number_arguments
def effective_damage_function(f_i: ArrayLike):
    """``f_bar = n / sum_i 1/f_i`` over the last axis (the n sub-domains), Eq. (6.87)."""
    f_i = np.asarray(f_i, dtype=float)
    return f_i.shape[-1] / np.sum(1.0 / f_i, axis=-1)


@number_arguments
def erve_strains(eps: ArrayLike, f_i: ArrayLike):
    """Sub-domain strains of the emulated RVE, Eq. (6.88): ``eps_i = f_bar / f(d_i) eps``, shape ``(..., n, 6)``.

    ``f_i`` lies in (0, 1]: a sub-domain with f = 0 (d = 1) would carry an infinite strain; the model caps the
    damage below 1 (``d_max``)."""
    f_i = check_range("f_i", f_i, 0.0, 1.0, low_open=True)
    f_bar = effective_damage_function(f_i)
    return (f_bar[..., None] / f_i)[..., None] * np.asarray(eps)[..., None, :]


@number_arguments
def driving_forces(d: ArrayLike, psi0: ArrayLike):
    """``p_d,i = -f_bar^2 f'(d_i) / (n f(d_i)^2) Psi0 = 2 f_bar^2 Psi0 / (n (1 - d_i)^3)`` (MPa), Eq. (6.94)."""
    d = np.asarray(d, dtype=float)
    f_bar = effective_damage_function(damage_function(d))
    return 2.0 * (f_bar**2 * np.asarray(psi0))[..., None] / (d.shape[-1] * (1.0 - d) ** 3)


@number_arguments
def damage_sweep(d_old: ArrayLike, psi0: ArrayLike, increment: ArrayLike, r_d: float, d_max: float = 0.999):
    """New sub-domain damage of Algorithm 2: rule (6.95) with the rate limit (6.103) and the cap ``d_max``.

    Sub-domain i grows by ``increment`` (= ``alpha l_ext dt``) where ``p_d,i > r_d / n``, visiting i = 1..n in
    order and refreshing ``f_bar`` after each; vectorised over the batch (the loop runs over the n sub-domains).
    During a sweep ``f_bar`` only falls, and with it every driving force not yet visited, so points where no
    sub-domain exceeds the threshold at the start keep their damage and are skipped.
    """
    psi0 = np.asarray(psi0, dtype=float)
    d = np.array(np.broadcast_to(d_old, np.broadcast_shapes(np.shape(d_old), (*psi0.shape, 1))), dtype=float)
    n = d.shape[-1]
    psi0 = np.broadcast_to(psi0, d.shape[:-1])
    candidates = np.any(driving_forces(d, psi0) > r_d / n, axis=-1)
    if not np.any(candidates):
        return d
    sub, psi0, increment = d[candidates], psi0[candidates], np.broadcast_to(increment, d.shape[:-1])[candidates]
    inverse_f = 1.0 / damage_function(sub)
    total = inverse_f.sum(axis=-1)
    for i in range(n):
        f_bar = n / total
        p_i = 2.0 * f_bar**2 * psi0 / (n * (1.0 - sub[:, i]) ** 3)  # Eq. (6.94)
        d_i = np.where(p_i > r_d / n, np.minimum(sub[:, i] + increment, d_max), sub[:, i])  # (6.95), (6.103)
        new_inverse = 1.0 / damage_function(d_i)
        total = total + new_inverse - inverse_f[:, i]
        sub[:, i] = d_i
    d[candidates] = sub
    return d


@dataclass(frozen=True)
class ModelIIDamage(IsotropicElasticity):
    """Model II ERVE damage, optionally with plasticity: Table 7.2 parameters by default for ``n``, ``alpha``, ``dt``.

    ``E``, ``nu``, ``r_d`` (MPa), ``n`` sub-domains, ``alpha`` (1/(N mm)), ``dt`` (s, used when ``update`` gets
    no ``dt``), ``r_p``, ``K_H`` (MPa; ``r_p=None``: no plasticity).

    State: ``eps``, ``eps_p``, ``alpha_p``, ``d`` (shape ``(..., n)``), ``psi0`` (driving energy, MPa) and
    ``dissipation`` (``sum r_p |d eps_p| + r_d/n sum_i d d_i``, Eq. 6.90, MPa).

    ``update(state, eps, dt=None, *, external_power=None, external_work=None)``: the rate limit of a step is
    ``alpha * external_power * dt`` (6.98, 6.103; ``l_ext`` in N mm/s, Eq. 6.97) or ``alpha * external_work``
    (``Delta u . sum f*``, N mm); one of the two is required. Negative values mean no damage growth.
    """

    E: float
    nu: float
    r_d: float
    n: int = 20
    alpha: float = 0.05
    dt: float = 1.0
    r_p: float | None = None
    K_H: float = 0.0
    integration: str = "explicit"
    tangent: str = "consistent"
    damage_energy: str = "full"
    d_max: float = 0.999
    fd_tolerance: float = 1e-8

    def __post_init__(self):
        check_number_fields(self)
        object.__setattr__(self, "E", check_positive("E", self.E))
        object.__setattr__(self, "nu", check_poisson("nu", self.nu))
        object.__setattr__(self, "r_d", check_positive("r_d", self.r_d))
        if isinstance(self.n, bool) or not isinstance(self.n, int | np.integer) or self.n < 1:
            raise ValueError(f"n (number of ERVE sub-domains) must be an integer >= 1, got {self.n!r}")
        object.__setattr__(self, "alpha", check_positive("alpha", self.alpha))
        object.__setattr__(self, "dt", check_positive("dt", self.dt))
        if self.r_p is not None:
            object.__setattr__(self, "r_p", check_positive("r_p", self.r_p))
        object.__setattr__(self, "K_H", check_positive("K_H", self.K_H, allow_zero=True))
        object.__setattr__(self, "d_max", check_range("d_max", self.d_max, 0.0, 1.0, low_open=True, high_open=True))
        object.__setattr__(self, "fd_tolerance", check_positive("fd_tolerance", self.fd_tolerance))
        check_option("integration", self.integration, INTEGRATIONS)
        check_option("tangent", self.tangent, TANGENTS)
        check_option("damage_energy", self.damage_energy, DAMAGE_ENERGIES)
        self._init_elasticity()

    def initial_state(self, shape: tuple[int, ...]) -> dict[str, np.ndarray]:
        return {
            "eps": np.zeros((*shape, 6)),
            "eps_p": np.zeros((*shape, 6)),
            "alpha_p": np.zeros(shape),
            "d": np.zeros((*shape, self.n)),
            "psi0": np.zeros(shape),
            "dissipation": np.zeros(shape),
        }

    def damage_increment(self, dt=None, external_power=None, external_work=None):
        """Rate limit of one step, ``alpha l_ext dt`` (6.98, 6.103) or ``alpha Delta W_ext``, never negative."""
        if external_work is not None:
            work = check_finite("external_work", external_work)
        elif external_power is not None:
            dt = self.dt if dt is None else check_positive("dt", dt)
            work = check_finite("external_power", external_power) * dt
        else:
            raise ValueError(
                "ModelIIDamage.update needs the rate limit: external_power (l_ext, N mm/s, Eq. 6.97) "
                "or external_work (N mm)"
            )
        return np.maximum(self.alpha * np.asarray(work), 0.0)

    def update(self, state, eps, dt=None, *, external_power=None, external_work=None) -> MaterialResponse:
        """One step of Algorithm 2 at every point: plasticity with ``f_bar^m``, damage sweep, stress (6.99)."""
        eps = check_strain(eps)
        increment = self.damage_increment(dt, external_power, external_work)
        f_bar_old = effective_damage_function(damage_function(state["d"]))
        step = plastic_step(eps, state["eps_p"], state["alpha_p"], f_bar_old * self.mu, self.r_p, self.K_H,
                            self.integration)
        eps_e = eps - step.eps_p
        psi0 = self.driving_energy(eps_e, self.damage_energy)
        d_new = damage_sweep(state["d"], psi0, increment, self.r_d, self.d_max)
        f_bar = effective_damage_function(damage_function(d_new))
        stress = f_bar[..., None] * (eps_e @ self.stiffness)  # Eq. (6.99) at the new state
        if self.tangent == "consistent":
            tangent = f_bar[..., None, None] * self.stiffness - (f_bar / f_bar_old)[..., None, None] * step.softening
        else:
            tangent = self._seed_tangent(state, eps, psi0, increment, d_new, f_bar_old)
        r_p = 0.0 if self.r_p is None else self.r_p
        new_state = {
            "eps": eps.copy(),
            "eps_p": step.eps_p,
            "alpha_p": step.alpha_p,
            "d": d_new,
            "psi0": psi0,
            "dissipation": state["dissipation"]
            + r_p * step.plastic_increment
            + self.r_d / self.n * np.sum(d_new - state["d"], axis=-1),
        }
        return MaterialResponse(stress, tangent, new_state)

    def _seed_tangent(self, state, eps, psi0, increment, d_new, f_bar_old):
        """Eq. (6.105) with the finite-difference damage derivative (6.104) and ``d f_bar/d d_j`` with ``f_bar^2``."""
        tol = self.fd_tolerance
        d_old = state["d"]
        dd_dpsi = (damage_sweep(d_old, psi0 + tol, increment, self.r_d, self.d_max) - d_new) / tol  # (6.104)
        df_bar_dd = -2.0 * f_bar_old[..., None] ** 2 / (self.n * (1.0 - d_old) ** 3)
        sigma0_old = (state["eps"] - state["eps_p"]) @ self.stiffness  # E : (eps^m - eps_p^m)
        dpsi_deps = self.driving_energy_gradient(eps - state["eps_p"], self.damage_energy)  # E : (eps^{m+1} - eps_p^m)
        rank_one = _outer(sigma0_old, np.sum(df_bar_dd * dd_dpsi, axis=-1)[..., None] * dpsi_deps)
        return f_bar_old[..., None, None] * self.stiffness + rank_one

    def effective_damage(self, state) -> np.ndarray:
        """Scalar damage ``1 - sqrt(f_bar)`` with ``f_bar = (1 - d_eff)^2``: the ERVE seen as one domain."""
        return 1.0 - np.sqrt(effective_damage_function(damage_function(state["d"])))

    def stored_energy(self, state) -> np.ndarray:
        """Relaxed energy ``f_bar Psi0 + 1/2 K_H alpha_p^2`` (MPa), Eq. (6.89)."""
        f_bar = effective_damage_function(damage_function(state["d"]))
        eps_e = state["eps"] - state["eps_p"]
        return f_bar * self.elastic_energy(eps_e) + 0.5 * self.K_H * state["alpha_p"] ** 2

    def dissipation(self, state) -> np.ndarray:
        """Accumulated ``sum r_p |d eps_p| + r_d/n sum_i d d_i``, Eq. (6.82), (6.90) (MPa)."""
        return state["dissipation"]
