"""The material interface of Ch. 6: a pure update from (old state, new total strain) to stress, tangent, new state.

Notation: strains and stresses are **Mandel** vectors ``(..., 6)`` in the order (11, 22, 33, 23, 13, 12) with
the shear components scaled by sqrt(2), so ``sigma : eps = stress @ eps``, ``|A|`` is the vector norm and a
tangent ``(..., 6, 6)`` acts as ``d stress = tangent @ d eps`` (symmetric for a hyperelastic model).
Units: MPa for stresses, moduli and energies per volume (N, mm, MPa), strains dimensionless.

Every model follows the same two methods (see :class:`Material`):

- ``initial_state(shape)`` -> dict of arrays for a batch of points of shape ``shape`` (e.g. ``(nel, nqp)``);
- ``update(state, eps, dt=1.0, **loading)`` -> :class:`MaterialResponse` with a *new* state dict.

The old state is never mutated, so a rejected Newton iterate or load step is simply retried from it.
Every state holds ``"eps"``, the total strain of that update, so ``stored_energy(state)`` and
``dissipation(state)`` are functions of the state alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike

from .. import tensors as T
from ..validation import check_finite, check_positive, check_shape, number_arguments

#: Mandel vector of the second-order identity I.
IDENTITY = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
#: Mandel matrix of the deviatoric projector, ``DEVIATORIC @ v = dev v`` (from abrakit.tensors).
DEVIATORIC = T.to_mandel4(T.identity4_dev())
for _array in (IDENTITY, DEVIATORIC):
    _array.setflags(write=False)


@dataclass(frozen=True)
class MaterialResponse:
    """Result of one constitutive update at every point of a batch.

    ``stress``: ``(..., 6)`` Mandel, MPa. ``tangent``: ``(..., 6, 6)`` Mandel, MPa, the algorithmic tangent
    ``d stress / d eps`` (or the operator-split one a model documents). ``state``: a new dict of new arrays.
    """

    stress: np.ndarray
    tangent: np.ndarray
    state: dict[str, np.ndarray]


@runtime_checkable
class Material(Protocol):
    """What the driver and the finite element assembly need from a constitutive model."""

    def initial_state(self, shape: tuple[int, ...]) -> dict[str, np.ndarray]: ...

    def update(self, state: dict[str, np.ndarray], eps: np.ndarray, dt: float = 1.0, **loading) -> MaterialResponse:
        ...


@number_arguments
def deviator(v: ArrayLike) -> np.ndarray:
    """``dev A = A - tr(A)/3 I`` of a Mandel vector ``v`` (..., 6)."""
    return _deviator(check_shape("v", np.asarray(v, dtype=float), (..., 6)))


def _deviator(v: np.ndarray) -> np.ndarray:
    """The kernel of :func:`deviator`, unchecked (the return maps call it on their own arrays)."""
    return v - v[..., :3].sum(axis=-1, keepdims=True) / 3.0 * IDENTITY


def _outer(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Batched dyadic product ``a (x) b`` of two Mandel vectors, ``(..., 6, 6)``."""
    return a[..., :, None] * b[..., None, :]


def check_strain(eps) -> np.ndarray:
    """Validate a batch of Mandel strains: shape ``(..., 6)`` and finite (never a silent NaN)."""
    eps = check_shape("eps", np.asarray(eps, dtype=float), (..., 6))
    check_finite("eps", eps)
    return eps


class IsotropicElasticity:
    """Shared elastic part of every model: Lame constants and the Mandel stiffness of ``C = E`` (MPa).

    A subclass is a frozen dataclass with fields ``E`` and ``nu``; call :meth:`_init_elasticity` from
    ``__post_init__``.
    """

    def _init_elasticity(self) -> None:
        lam, mu = T.lame(self.E, self.nu)
        stiffness = T.isotropic_stiffness(self.E, self.nu, notation="mandel")
        stiffness.setflags(write=False)
        object.__setattr__(self, "lam", lam)
        object.__setattr__(self, "mu", mu)
        object.__setattr__(self, "stiffness", stiffness)

    def elastic_energy(self, eps_e: np.ndarray) -> np.ndarray:
        """``Psi0 = 1/2 eps_e : E : eps_e`` of the undamaged material, Eq. (6.2)/(6.9), MPa."""
        return 0.5 * np.einsum("...i,ij,...j->...", eps_e, self.stiffness, eps_e)

    def tension_energy(self, eps_e: np.ndarray) -> np.ndarray:
        """Tension-only ``Psi0+ = 1/2 eps_e+ : E : eps_e+``, Eq. (6.56)/(6.57), MPa.

        With ``eps+ = sum <eps_a>+ n_a (x) n_a`` this is ``lambda/2 (sum <eps_a>+)^2 + mu sum <eps_a>+^2``:
        only the eigenvalues are needed (``abrakit.tensors.positive_part`` gives the same, with eigenvectors).
        """
        positive = np.maximum(np.linalg.eigvalsh(T.from_mandel(eps_e)), 0.0)
        return 0.5 * self.lam * positive.sum(axis=-1) ** 2 + self.mu * np.sum(positive**2, axis=-1)

    def driving_energy(self, eps_e: np.ndarray, kind: str) -> np.ndarray:
        """``Psi0`` (``kind="full"``) or ``Psi0+`` (``kind="tension"``) of the elastic strain, MPa."""
        return self.tension_energy(eps_e) if kind == "tension" else self.elastic_energy(eps_e)

    def driving_energy_gradient(self, eps_e: np.ndarray, kind: str) -> np.ndarray:
        """``d Psi0 / d eps_e`` (Mandel, MPa): ``E : eps_e``, or ``lambda tr(eps+) P+ + 2 mu eps+`` for Psi0+.

        ``P+`` is the projector onto the eigenvectors with positive eigenvalue, the derivative of ``tr eps+``.
        """
        if kind != "tension":
            return eps_e @ self.stiffness
        values, vectors = np.linalg.eigh(T.from_mandel(eps_e))
        positive = (values > 0.0).astype(float)
        projector = T.to_mandel(np.einsum("...ia,...a,...ja->...ij", vectors, positive, vectors))
        eps_plus = T.to_mandel(np.einsum("...ia,...a,...ja->...ij", vectors, values * positive, vectors))
        trace_plus = eps_plus[..., :3].sum(axis=-1, keepdims=True)
        return self.lam * trace_plus * projector + 2.0 * self.mu * eps_plus


def finite_difference_tangent(material, state, eps, h: float = 1e-8, dt: float = 1.0, **loading) -> np.ndarray:
    """Centred finite-difference tangent ``(s(eps + h e_k) - s(eps - h e_k)) / 2h`` of a stress update.

    Column ``k`` is the derivative with respect to Mandel strain component ``k``; shape ``(..., 6, 6)``.
    Used to check every model's returned tangent and, in the driver, as a fallback Jacobian.
    """
    eps = check_strain(eps)
    check_positive("h", h)
    check_positive("dt", dt)
    columns = []
    for k in range(6):
        step = np.zeros(6)
        step[k] = h
        plus = material.update(state, eps + step, dt, **loading).stress
        minus = material.update(state, eps - step, dt, **loading).stress
        columns.append((plus - minus) / (2.0 * h))
    return np.stack(columns, axis=-1)
