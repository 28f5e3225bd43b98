"""Model I at a material point: gradient-enhanced damage coupled with plasticity, Eq. (6.22)-(6.80), Algorithm 1.

Free energy ``Psi = f(d) Psi0 + 1/2 K_H alpha_p^2 + beta/2 |grad f|^2`` (6.22)-(6.24) with ``f = exp(-d)`` (6.11),
stress ``sigma = f E : (eps - eps_p)`` (6.40). Per load step (operator split of the seed):

1. plasticity at every point with the damage function of the old step, ``f^m`` (6.59)-(6.61), stress
   ``f^m E : (eps^{m+1} - eps_p^{m+1})`` (6.62) and the constant tangent ``f^m E`` (6.63);
2. after the displacement field has converged, the damage function is updated from the indicator
   ``Phi_d = f Psibar0+ - beta f Lambda_f - r_d <= 0`` (6.64, 6.76) with the tension-only energy Psi0+ (6.56).

The nonlocal part enters only through ``Lambda_f`` (the Laplacian of f, Eq. 6.74) and its derivative
``D Lambda_f`` with respect to the element's own f (6.75), both computed by the finite element level from the
field ``f^m``; at a material point ``beta = 0`` or a given ``Lambda_f``. With Lambda_f linearised about f^m,
``Lambda_f(f) = Lambda_f + D Lambda_f (f - f^m)``, the indicator is a quadratic in f; we take its root in
``(0, f^m)``, the converged limit of the Newton update (6.77). The seed's Algorithm 1 takes one Newton step;
for beta = 0 the indicator is linear in f and one step *is* the root.

Range of d (the seed writes ``d in [0, 1)`` for Model I, but with ``f = exp(-d)`` that would keep at least
``exp(-1) = 37 %`` of the stiffness, while the Ch. 7 force-displacement curves drop to zero): we take
``d in [0, inf)`` as for Eq. (6.11) and stop at ``f >= f_min = 1e-6`` (``d <= 13.8``), the same residual
stiffness as Model II's cap ``d <= 0.999``, so that the tangent stays positive definite.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..validation import check_number_fields, check_option, check_poisson, check_positive, check_range, number_arguments
from .base import IsotropicElasticity, MaterialResponse, check_strain
from .plasticity import INTEGRATIONS, plastic_step

TANGENTS = ("operator_split", "consistent")
DAMAGE_ENERGIES = ("tension", "full")


@number_arguments
def damage_function(d: ArrayLike):
    """``f(d) = exp(-d)``, Eq. (6.11); ``f' = -f``."""
    return np.exp(-np.asarray(d, dtype=float))


@number_arguments
def damage_indicator(f: ArrayLike, psi0_bar: ArrayLike, laplacian: ArrayLike, beta: float, r_d: float):
    """``Phi_d = f Psibar0 - beta f Lambda_f - r_d`` (MPa), Eq. (6.64)/(6.76)."""
    return f * psi0_bar - beta * f * laplacian - r_d


@number_arguments
def damage_function_update(f_old: ArrayLike, psi0_bar: ArrayLike, laplacian: ArrayLike,
                           laplacian_derivative: ArrayLike, beta: float, r_d: float, f_min: float):
    """New damage function of Eq. (6.76)/(6.77): the root of ``Phi_d(f) = 0`` in ``(0, f^m)`` where ``Phi_d(f^m) > 0``.

    With ``Lambda_f(f) = Lambda_f + D Lambda_f (f - f^m)`` (6.74, 6.75) the indicator is
    ``a f^2 + b f - r_d`` with ``a = -beta D Lambda_f`` and ``b = Psibar0 - beta Lambda_f + beta D Lambda_f f^m``;
    its root in ``(0, f^m)`` is ``2 r_d / (b + sqrt(b^2 + 4 a r_d))`` in every case (``Phi_d(0) = -r_d < 0``).
    Elsewhere ``f = f^m`` (no healing); the result is kept in ``[f_min, f^m]``.
    """
    check_positive("r_d", r_d)
    check_positive("beta", beta, allow_zero=True)
    check_range("f_min", f_min, 0.0, 1.0, low_open=True)
    f_old, psi0_bar, laplacian, laplacian_derivative = np.broadcast_arrays(
        np.asarray(f_old, dtype=float), psi0_bar, laplacian, laplacian_derivative
    )
    active = damage_indicator(f_old, psi0_bar, laplacian, beta, r_d) > 0.0
    a = -beta * laplacian_derivative
    b = psi0_bar - beta * laplacian + beta * laplacian_derivative * f_old
    denominator = b + np.sqrt(np.maximum(b * b + 4.0 * a * r_d, 0.0))
    root = 2.0 * r_d / np.where(active, denominator, 1.0)
    return np.where(active, np.clip(root, f_min, f_old), f_old)


@dataclass(frozen=True)
class ModelIDamage(IsotropicElasticity):
    """Local part of Model I: ``E``, ``nu``, ``r_d``, optional plasticity ``r_p``, ``K_H`` (MPa), ``beta`` (MPa mm^2).

    State: ``eps``, ``eps_p``, ``alpha_p``, ``d`` (``f = exp(-d)``), ``psi0`` (the driving energy Psi0+ of the
    last update, MPa) and ``dissipation`` (``sum r_p |d eps_p| + r_d d d``, MPa).

    ``update(state, eps, dt=1.0, *, psi0_bar=None, laplacian=0.0, laplacian_derivative=0.0, damage=True)``:
    plastic step and stress with ``f^m``; then, if ``damage``, :meth:`update_damage` with the element-averaged
    driving energy ``psi0_bar`` (default: the point's own Psi0+) and the nonlocal terms ``laplacian``
    (``Lambda_f``, 1/mm^2) and ``laplacian_derivative`` (``D Lambda_f``, 1/mm^2). A finite element loop can
    call ``update(..., damage=False)`` during the Newton iterations and :meth:`update_damage` once the step
    has converged (Algorithm 1); the stress of the step does not depend on the new f.

    ``tangent="operator_split"`` returns exactly ``f^m E`` (6.63); ``"consistent"`` returns the derivative of
    the stress update at frozen ``f^m`` (differs from 6.63 only while plastic flow is active).
    ``damage_energy="tension"`` drives damage by Psi0+ (6.56); ``"full"`` by Psi0.
    """

    E: float
    nu: float
    r_d: float
    r_p: float | None = None
    K_H: float = 0.0
    beta: float = 0.0
    integration: str = "explicit"
    tangent: str = "operator_split"
    damage_energy: str = "tension"
    f_min: float = 1e-6

    def __post_init__(self):
        check_number_fields(self)
        object.__setattr__(self, "E", check_positive("E", self.E))
        object.__setattr__(self, "nu", check_poisson("nu", self.nu))
        object.__setattr__(self, "r_d", check_positive("r_d", self.r_d))
        if self.r_p is not None:
            object.__setattr__(self, "r_p", check_positive("r_p", self.r_p))
        object.__setattr__(self, "K_H", check_positive("K_H", self.K_H, allow_zero=True))
        object.__setattr__(self, "beta", check_positive("beta", self.beta, allow_zero=True))
        object.__setattr__(self, "f_min", check_range("f_min", self.f_min, 0.0, 1.0, low_open=True, high_open=True))
        check_option("integration", self.integration, INTEGRATIONS)
        check_option("tangent", self.tangent, TANGENTS)
        check_option("damage_energy", self.damage_energy, DAMAGE_ENERGIES)
        self._init_elasticity()

    @property
    def d_max(self) -> float:
        """Largest damage variable, ``-ln f_min``."""
        return float(-np.log(self.f_min))

    def initial_state(self, shape: tuple[int, ...]) -> dict[str, np.ndarray]:
        return {
            "eps": np.zeros((*shape, 6)),
            "eps_p": np.zeros((*shape, 6)),
            "alpha_p": np.zeros(shape),
            "d": np.zeros(shape),
            "psi0": np.zeros(shape),
            "dissipation": np.zeros(shape),
        }

    def update(
        self, state, eps, dt: float = 1.0, *, psi0_bar=None, laplacian=0.0, laplacian_derivative=0.0, damage=True
    ) -> MaterialResponse:
        """One load step of Algorithm 1 at every point; see the class docstring for the arguments."""
        eps = check_strain(eps)
        f_old = damage_function(state["d"])
        step = plastic_step(eps, state["eps_p"], state["alpha_p"], f_old * self.mu, self.r_p, self.K_H,
                            self.integration)
        eps_e = eps - step.eps_p
        stress = f_old[..., None] * (eps_e @ self.stiffness)  # Eq. (6.62), read as (6.40) with f^m
        tangent = f_old[..., None, None] * self.stiffness  # Eq. (6.63)
        if self.tangent == "consistent":
            tangent = tangent - step.softening
        r_p = 0.0 if self.r_p is None else self.r_p
        new_state = {
            "eps": eps.copy(),
            "eps_p": step.eps_p,
            "alpha_p": step.alpha_p,
            "d": np.broadcast_to(state["d"], step.alpha_p.shape).copy(),
            "psi0": self.driving_energy(eps_e, self.damage_energy),
            "dissipation": state["dissipation"] + r_p * step.plastic_increment,
        }
        if damage:
            new_state = self.update_damage(new_state, psi0_bar, laplacian, laplacian_derivative)
        return MaterialResponse(stress, tangent, new_state)

    def update_damage(self, state, psi0_bar=None, laplacian=0.0, laplacian_derivative=0.0) -> dict:
        """Damage step of Algorithm 1, Eq. (6.76)/(6.77), on a state whose plastic part is already updated.

        ``psi0_bar``: driving energy (MPa), default ``state["psi0"]``; the finite element level passes the
        element average of Psi0+ at the Gauss points. Returns a new state with ``d`` and ``dissipation`` updated.
        """
        psi0_bar = state["psi0"] if psi0_bar is None else np.asarray(psi0_bar, dtype=float)
        f_old = damage_function(state["d"])
        f_new = damage_function_update(f_old, psi0_bar, laplacian, laplacian_derivative, self.beta, self.r_d,
                                       self.f_min)
        d_new = np.where(f_new < f_old, np.maximum(-np.log(f_new), state["d"]), state["d"])  # never heals
        new_state = dict(state)
        new_state["d"] = d_new
        new_state["dissipation"] = state["dissipation"] + self.r_d * (d_new - state["d"])
        return new_state

    def stored_energy(self, state) -> np.ndarray:
        """``f Psi0 + 1/2 K_H alpha_p^2`` (MPa), Eq. (6.23), with the new f; the gradient energy is the FE level's."""
        eps_e = state["eps"] - state["eps_p"]
        return damage_function(state["d"]) * self.elastic_energy(eps_e) + 0.5 * self.K_H * state["alpha_p"] ** 2

    def dissipation(self, state) -> np.ndarray:
        """Accumulated ``sum r_p |d eps_p| + r_d d d``, Eq. (6.25) (MPa)."""
        return state["dissipation"]
