"""Von Mises plasticity with linear isotropic hardening, Table 6.1 and Eq. (6.49)-(6.61).

Free energy ``Psi = 1/2 (eps - eps_p) : E : (eps - eps_p) + 1/2 K_H alpha_p^2`` (6.2), deviatoric plastic strain,
``alpha_p' = |eps_p'|`` (6.7) and the yield function

    Phi_p = |dev sigma| - (r_p + K_H alpha_p) <= 0          (6.51)-(6.53)

with "+ K_H alpha_p" (Table 6.1 prints "r_p - K_H alpha_p"; hardening with K_H > 0 needs "+", as in 6.53 and
6.61). Hence the uniaxial yield stress is ``sqrt(3/2) r_p`` and the uniaxial hardening modulus ``1.5 K_H``.

Two integrations of the flow rule ``eps_p' = rho dev sigma`` (6.53) over a step:

- ``"explicit"`` (the seed, Eq. 6.59): ``eps_p^{m+1} = eps_p^m + d_rho dev sigma_trial``,
  ``alpha_p^{m+1} = alpha_p^m + d_rho (r_p + K_H alpha_p^m)``, with ``d_rho`` from the consistency condition
  (6.61) at the new step. Eq. (6.61) is *linear* in ``d_rho`` (the seed suggests Newton's method; one Newton
  step is the closed form used here). Because ``alpha_p`` grows with the old yield stress while
  ``|d eps_p|`` grows with the trial stress, the discrete ``alpha_p`` lags ``sum |d eps_p|``: a first-order
  error in the step size, zero for perfect plasticity (``K_H = 0``).
- ``"implicit"`` (the default): classical radial return (backward Euler), exact on radial paths for any step size.

Both return the algorithmic (consistent) tangent. The default is the implicit return: with hardening the seed's
explicit update carries a first-order error in the step size (``benchmarks/bench_plasticity.py`` measures both
against a converged reference), and a user who does not choose should get the scheme without it;
``integration="explicit"`` reproduces the seed. The damage
models (Model I, Model II) keep the seed's explicit scheme as their default: their chapters reproduce the seed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..compiled import HAVE_NUMBA, njit
from ..validation import (
    check_finite,
    check_number_fields,
    check_option,
    check_poisson,
    check_positive,
    check_shape,
    number_arguments,
)
from .base import DEVIATORIC, IsotropicElasticity, MaterialResponse, _deviator, _outer, check_strain

INTEGRATIONS = ("explicit", "implicit")


@dataclass(frozen=True)
class PlasticStep:
    """Outcome of the plastic update at every point of a batch.

    ``eps_p`` (..., 6) and ``alpha_p`` (...): new internal variables; ``plastic_increment``: ``|d eps_p|``;
    ``softening`` (..., 6, 6): the algorithmic tangent is ``f E - softening`` (zero where elastic);
    ``active``: where the step was plastic.
    """

    eps_p: np.ndarray
    alpha_p: np.ndarray
    plastic_increment: np.ndarray
    softening: np.ndarray
    active: np.ndarray


@number_arguments
def plastic_step(eps, eps_p: ArrayLike, alpha_p: ArrayLike, shear_modulus: ArrayLike, r_p: float | None, K_H: float,
                 integration: str) -> PlasticStep:
    """Return map of the von Mises model for stresses ``f E : (eps - eps_p)``, Eq. (6.59)-(6.61).

    ``shear_modulus`` is the effective ``G = f mu`` (MPa; scalar or batch array) with the damage function
    frozen at the old step, as both damage models do (operator split). ``integration``: ``"explicit"``
    (seed, 6.59/6.61) or ``"implicit"`` (radial return). ``r_p=None`` means no plasticity (elastic step).
    """
    check_shape("eps_p", check_finite("eps_p", eps_p), (..., 6))
    check_positive("alpha_p", alpha_p, allow_zero=True)
    check_positive("shear_modulus", shear_modulus, allow_zero=True)
    if r_p is not None:
        check_positive("r_p", r_p)
    check_finite("K_H", K_H)
    check_option("integration", integration, INTEGRATIONS)
    return _return_map(check_strain(eps), eps_p, alpha_p, shear_modulus, r_p, K_H, integration)


def _batch_copy(value, shape) -> np.ndarray:
    """A float copy of ``value`` with ``shape`` (broadcast only where it is not already of that shape)."""
    value = np.asarray(value, dtype=float)
    return value.copy() if value.shape == shape else np.array(np.broadcast_to(value, shape))


def _return_map(eps, eps_p, alpha_p, shear_modulus, r_p, K_H, integration) -> PlasticStep:
    """:func:`plastic_step` for a checked strain ``eps``."""
    batch = np.broadcast_shapes(np.shape(eps)[:-1], np.shape(alpha_p), np.shape(shear_modulus))
    new_eps_p = _batch_copy(eps_p, (*batch, 6))
    new_alpha_p = _batch_copy(alpha_p, batch)
    plastic_increment = np.zeros(batch)
    softening = np.zeros((*batch, 6, 6))
    if r_p is None:
        return PlasticStep(new_eps_p, new_alpha_p, plastic_increment, softening, np.zeros(batch, bool))
    two_G = 2.0 * np.asarray(shear_modulus, dtype=float)
    s_trial = two_G[..., None] * _deviator(eps - new_eps_p)   # dev f E : (eps^{m+1} - eps_p^m)
    q = np.sqrt(np.einsum("...i,...i->...", s_trial, s_trial))
    yield_stress = r_p + K_H * new_alpha_p
    active = q > yield_stress  # Phi_p > 0, Eq. (6.60)
    if not np.any(active):
        return PlasticStep(new_eps_p, new_alpha_p, plastic_increment, softening, active)
    two_G = np.broadcast_to(two_G, batch)[active]
    # only the plastic points are worked on (plastic zones are usually small)
    s_trial, q, y = s_trial[active], q[active], yield_stress[active]
    normal = s_trial / q[:, None]
    # the softening is a n (x) n + b P_dev with per-point a, b (four (n, 6, 6) temporaries fewer than its factored
    # forms below)
    if integration == "explicit":
        denominator = two_G * q + K_H * y
        d_rho = (q - y) / denominator  # Eq. (6.61), linear in d_rho
        new_eps_p[active] += d_rho[:, None] * s_trial  # Eq. (6.59)
        new_alpha_p[active] += d_rho * y  # Eq. (6.59)
        plastic_increment[active] = d_rho * q
        d_rho_dq = y * (two_G + K_H) / denominator**2
        # (2G)^2 (d_rho P_dev + q d_rho/dq n (x) n)
        a, b = two_G**2 * q * d_rho_dq, two_G**2 * d_rho
    else:
        d_gamma = (q - y) / (two_G + K_H)  # radial return: q - 2G dg = r_p + K_H (alpha_p + dg)
        new_eps_p[active] += d_gamma[:, None] * normal
        new_alpha_p[active] += d_gamma
        plastic_increment[active] = d_gamma
        # (2G)^2 (n (x) n / (2G + K_H) + dg/q (P_dev - n (x) n))
        b = two_G**2 * d_gamma / q
        a = two_G**2 / (two_G + K_H) - b
    softening[active] = a[:, None, None] * _outer(normal, normal) + b[:, None, None] * DEVIATORIC
    return PlasticStep(new_eps_p, new_alpha_p, plastic_increment, softening, active)


def _flat(value, batch, tail) -> np.ndarray:
    """``value`` as a contiguous float array of shape (points, *tail) for the batch ``batch``."""
    shape = (*batch, *tail)
    if not (isinstance(value, np.ndarray) and value.shape == shape and value.dtype == float):
        value = np.broadcast_to(np.asarray(value, dtype=float), shape)
    return np.ascontiguousarray(value).reshape(-1, *tail)


@njit(cache=True)
def _update_compiled(eps, eps_p, alpha_p, dissipation, stiffness, two_G, r_p, K_H, explicit, out_stress,
                     out_tangent, out_eps_p, out_alpha_p, out_dissipation):  # pragma: no cover - compiled
    """:meth:`VonMisesPlasticity.update` one point at a time (numba): the return map of :func:`plastic_step`,
    Eq. (6.59)–(6.61) or the radial return, with the same formulas, the stress E : (eps − eps_p) and the tangent
    E − a n (x) n − b P_dev, for ``m`` points (flattened batch) into the ``out_`` arrays."""
    for k in range(eps.shape[0]):
        d = eps[k] - eps_p[k]
        mean = (d[0] + d[1] + d[2]) / 3.0
        s = np.empty(6)
        q2 = 0.0
        for i in range(6):
            s[i] = two_G * (d[i] - mean if i < 3 else d[i])
            q2 += s[i] * s[i]
        q = np.sqrt(q2)
        y = r_p + K_H * alpha_p[k]
        out_eps_p[k] = eps_p[k]
        out_alpha_p[k] = alpha_p[k]
        out_tangent[k] = stiffness
        increment = 0.0
        if q > y:
            if explicit:
                denominator = two_G * q + K_H * y
                d_rho = (q - y) / denominator
                for i in range(6):
                    out_eps_p[k, i] += d_rho * s[i]
                out_alpha_p[k] += d_rho * y
                increment = d_rho * q
                a = two_G * two_G * q * (y * (two_G + K_H) / denominator**2)
                b = two_G * two_G * d_rho
            else:
                d_gamma = (q - y) / (two_G + K_H)
                for i in range(6):
                    out_eps_p[k, i] += d_gamma * (s[i] / q)
                out_alpha_p[k] += d_gamma
                increment = d_gamma
                b = two_G * two_G * d_gamma / q
                a = two_G * two_G / (two_G + K_H) - b
            for i in range(6):
                for j in range(6):
                    out_tangent[k, i, j] -= a * (s[i] / q) * (s[j] / q) + b * _DEVIATORIC[i, j]
        out_dissipation[k] = dissipation[k] + r_p * increment
        for j in range(6):
            total = 0.0
            for i in range(6):
                total += (eps[k, i] - out_eps_p[k, i]) * stiffness[i, j]
            out_stress[k, j] = total


_DEVIATORIC = np.ascontiguousarray(DEVIATORIC)


@number_arguments
def uniaxial_yield_stress(r_p: float) -> float:
    """Uniaxial yield stress ``sigma_0 = sqrt(3/2) r_p`` of the yield function (6.51) (MPa)."""
    return float(np.sqrt(1.5) * r_p)


@number_arguments
def uniaxial_hardening_modulus(K_H: float) -> float:
    """Slope of uniaxial stress against axial plastic strain, ``1.5 K_H`` (MPa), since ``alpha_p = |eps_p|``."""
    return 1.5 * K_H


@dataclass(frozen=True)
class VonMisesPlasticity(IsotropicElasticity):
    """Elastoplastic material of Table 6.1: ``E``, ``nu``, yield limit ``r_p`` and hardening ``K_H`` (MPa).

    State: ``eps``, ``eps_p`` (Mandel, deviatoric), ``alpha_p`` and ``dissipation`` (accumulated
    ``r_p |d eps_p|``, Eq. 6.6, MPa). ``integration`` is ``"implicit"`` (radial return, the default) or
    ``"explicit"`` (the seed's Eq. 6.59).
    """

    E: float
    nu: float
    r_p: float
    K_H: float = 0.0
    integration: str = "implicit"

    def __post_init__(self):
        check_number_fields(self)
        object.__setattr__(self, "E", check_positive("E", self.E))
        object.__setattr__(self, "nu", check_poisson("nu", self.nu))
        object.__setattr__(self, "r_p", check_positive("r_p", self.r_p))
        object.__setattr__(self, "K_H", check_positive("K_H", self.K_H, allow_zero=True))
        check_option("integration", self.integration, INTEGRATIONS)
        self._init_elasticity()

    def initial_state(self, shape: tuple[int, ...]) -> dict[str, np.ndarray]:
        return {
            "eps": np.zeros((*shape, 6)),
            "eps_p": np.zeros((*shape, 6)),
            "alpha_p": np.zeros(shape),
            "dissipation": np.zeros(shape),
        }

    def update(self, state, eps, dt: float = 1.0, compiled: bool | None = None, **loading) -> MaterialResponse:
        """Stress ``E : (eps - eps_p^{m+1})`` (6.3) after the return map, algorithmic tangent, new state.

        ``compiled`` (default: where numba is installed) runs :func:`_update_compiled`, one loop over the points
        without temporaries (the return map is most of a small mesh's Newton iteration); ``False`` the vectorised
        NumPy :func:`plastic_step`. Both give the same numbers to round-off (tested)."""
        eps = check_strain(eps)
        if HAVE_NUMBA if compiled is None else compiled:
            return self._update_compiled(state, eps)
        step = _return_map(eps, state["eps_p"], state["alpha_p"], self.mu, self.r_p, self.K_H, self.integration)
        stress = (eps - step.eps_p) @ self.stiffness
        new_state = {
            "eps": eps.copy(),
            "eps_p": step.eps_p,
            "alpha_p": step.alpha_p,
            "dissipation": state["dissipation"] + self.r_p * step.plastic_increment,
        }
        return MaterialResponse(stress, self.stiffness - step.softening, new_state)

    def _update_compiled(self, state, eps) -> MaterialResponse:
        batch = eps.shape[:-1]
        m = math.prod(batch)
        flat = [_flat(state[k], batch, tail) for k, tail in (("eps_p", (6,)), ("alpha_p", ()), ("dissipation", ()))]
        stress, tangent = np.empty((m, 6)), np.empty((m, 6, 6))
        eps_p, alpha_p, dissipation = np.empty((m, 6)), np.empty(m), np.empty(m)
        _update_compiled(_flat(eps, batch, (6,)), *flat, self.stiffness, 2.0 * self.mu, self.r_p,
                         self.K_H, self.integration == "explicit", stress, tangent, eps_p, alpha_p, dissipation)
        new_state = {"eps": eps.copy(), "eps_p": eps_p.reshape(*batch, 6), "alpha_p": alpha_p.reshape(batch),
                     "dissipation": dissipation.reshape(batch)}
        return MaterialResponse(stress.reshape(*batch, 6), tangent.reshape(*batch, 6, 6), new_state)

    def stored_energy(self, state) -> np.ndarray:
        """``Psi = 1/2 (eps - eps_p) : E : (eps - eps_p) + 1/2 K_H alpha_p^2``, Eq. (6.2) (MPa)."""
        return self.elastic_energy(state["eps"] - state["eps_p"]) + 0.5 * self.K_H * state["alpha_p"] ** 2

    def dissipation(self, state) -> np.ndarray:
        """Accumulated plastic dissipation ``sum r_p |d eps_p|``, Eq. (6.6) (MPa)."""
        return state["dissipation"]
