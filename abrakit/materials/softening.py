"""Isotropic damage with linear softening: the textbook material whose bar snaps back (the path-following test).

Not a model of the dissertation: it is the smallest local softening law with a closed-form structural response,
the one every text on path following uses (Crisfield 1991, Ch. 9; de Borst et al. 2012, Ch. 4). With the
equivalent strain ``kappa`` = the largest strain norm ``|eps|`` reached so far (Mandel norm; in uniaxial strain
``|eps| = eps_11``),

    sigma = (1 - d) E : eps,        d(kappa) = eps_f (kappa - eps_0) / (kappa (eps_f - eps_0))   for eps_0 <= kappa,

so that under uniaxial strain the stress falls linearly from ``f_t = E eps_0`` at ``eps_0`` to zero at ``eps_f``
(``E`` here is the 1D modulus ``C_1111``; with ``nu = 0`` it is Young's modulus), and unloading is secant (towards
the origin). ``eps_0`` may be an array broadcast over the quadrature points (a weakened element). The energy
dissipated per volume up to ``kappa`` is the area under the softening line minus the recoverable secant energy,

    D(kappa) = 1/2 f_t eps_0 + 1/2 (f_t + sigma(kappa)) (kappa - eps_0) - 1/2 sigma(kappa) kappa,

``1/2 f_t eps_f`` at complete failure (uniaxial strain). ``d`` is capped at ``d_max`` (default ``1 - 1e-9``) so the
tangent keeps a trace of stiffness. The tangent is the consistent one:
``(1 - d) E - d'(kappa) (E : eps) (x) eps / |eps|`` while loading, ``(1 - d) E`` otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..validation import check_number_fields, check_poisson, check_positive, check_range
from .base import IsotropicElasticity, MaterialResponse, _outer, check_strain


@dataclass(frozen=True)
class LinearSofteningDamage(IsotropicElasticity):
    """Local isotropic damage with linear softening (see the module docstring). ``E`` (MPa), ``nu``, the strain
    ``eps_0`` at the peak (number or array broadcast to the batch) and the strain ``eps_f`` at which the stress
    vanishes (``eps_f > eps_0``)."""

    E: float
    nu: float
    eps_0: float | np.ndarray
    eps_f: float
    d_max: float = 1.0 - 1e-9

    def __post_init__(self):
        check_number_fields(self)
        object.__setattr__(self, "E", check_positive("E", self.E))
        object.__setattr__(self, "nu", check_poisson("nu", self.nu))
        eps_0 = np.asarray(check_positive("eps_0", self.eps_0), dtype=float)
        object.__setattr__(self, "eps_0", eps_0)
        check_range("eps_f", self.eps_f, float(np.max(eps_0)), None, low_open=True)
        check_range("d_max", self.d_max, 0.0, 1.0, high_open=True)
        self._init_elasticity()

    def initial_state(self, shape: tuple[int, ...]) -> dict[str, np.ndarray]:
        return {"eps": np.zeros((*shape, 6)), "kappa": np.broadcast_to(self.eps_0, shape).copy(),
                "d": np.zeros(shape)}

    def damage(self, kappa: np.ndarray) -> np.ndarray:
        """d(kappa) of the linear softening law, capped at ``d_max``."""
        eps_0 = np.broadcast_to(self.eps_0, np.shape(kappa))
        d = self.eps_f * (kappa - eps_0) / (kappa * (self.eps_f - eps_0))
        return np.clip(d, 0.0, self.d_max)

    def update(self, state, eps, dt: float = 1.0, **loading) -> MaterialResponse:
        """Stress ``(1 - d) E : eps``, the consistent tangent and the new state (``kappa`` never decreases)."""
        eps = check_strain(eps)
        norm = np.linalg.norm(eps, axis=-1)
        loading_ = norm > state["kappa"]
        kappa = np.where(loading_, norm, state["kappa"])
        d = self.damage(kappa)
        effective = eps @ self.stiffness
        stress = (1.0 - d)[..., None] * effective
        tangent = (1.0 - d)[..., None, None] * self.stiffness
        eps_0 = np.broadcast_to(self.eps_0, kappa.shape)
        softening = loading_ & (d > 0.0) & (d < self.d_max)
        if np.any(softening):
            k, e0 = kappa[softening], eps_0[softening]
            d_prime = self.eps_f * e0 / (kappa[softening] ** 2 * (self.eps_f - e0))     # dd/dkappa
            direction = eps[softening] / k[:, None]                                       # dkappa/deps
            tangent[softening] -= d_prime[:, None, None] * _outer(effective[softening], direction)
        return MaterialResponse(stress, tangent, {"eps": eps.copy(), "kappa": kappa, "d": d})

    def dissipation(self, state) -> np.ndarray:
        """Energy dissipated per volume (MPa) in uniaxial strain, ``D(kappa)`` of the module docstring."""
        kappa = state["kappa"]
        eps_0 = np.broadcast_to(self.eps_0, kappa.shape)
        f_t = self.stiffness[0, 0] * eps_0
        k = np.minimum(kappa, self.eps_f)
        sigma = f_t * (self.eps_f - k) / (self.eps_f - eps_0)
        return np.where(kappa > eps_0, 0.5 * f_t * eps_0 + 0.5 * (f_t + sigma) * (k - eps_0) - 0.5 * sigma * k, 0.0)
