"""Linear isotropic elasticity, Eq. (6.3) without plastic strain: ``sigma = E : eps``."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..validation import check_number_fields, check_poisson, check_positive
from .base import IsotropicElasticity, MaterialResponse, check_strain


@dataclass(frozen=True)
class LinearElastic(IsotropicElasticity):
    """Isotropic linear elasticity with Young's modulus ``E`` (MPa) and Poisson's ratio ``nu``.

    State: ``eps`` only. The tangent is the constant Mandel stiffness (symmetric).
    """

    E: float
    nu: float

    def __post_init__(self):
        check_number_fields(self)
        object.__setattr__(self, "E", check_positive("E", self.E))
        object.__setattr__(self, "nu", check_poisson("nu", self.nu))
        self._init_elasticity()

    def initial_state(self, shape: tuple[int, ...]) -> dict[str, np.ndarray]:
        return {"eps": np.zeros((*shape, 6))}

    def update(self, state, eps, dt: float = 1.0, **loading) -> MaterialResponse:
        """``sigma = E : eps`` (MPa); ``dt`` and ``loading`` are ignored."""
        eps = check_strain(eps)
        tangent = np.broadcast_to(self.stiffness, (*eps.shape[:-1], 6, 6)).copy()
        return MaterialResponse(eps @ self.stiffness, tangent, {"eps": eps.copy()})

    def stored_energy(self, state) -> np.ndarray:
        """``Psi = 1/2 eps : E : eps`` (MPa)."""
        return self.elastic_energy(state["eps"])

    def dissipation(self, state) -> np.ndarray:
        """Elasticity dissipates nothing."""
        return np.zeros(state["eps"].shape[:-1])
