"""Tensor notation of Ch. 2.1: second- and fourth-order tensors, Voigt and Mandel forms, spectral split.

Everything is batched over leading axes: a second-order tensor is ``(..., 3, 3)``, a fourth-order one
``(..., 3, 3, 3, 3)``, a Voigt or Mandel vector ``(..., 6)`` and a matrix ``(..., 6, 6)``.

The notations are *data* (see ``VOIGT_PAIRS`` and the weight vectors below), and every conversion is one
contraction with them, in the spirit of mechkit:

- Voigt order (11, 22, 33, 23, 13, 12), Eq. (2.17). Strains carry engineering shears (2 eps_23, ...),
  stresses the plain components, so that ``sigma : eps = to_voigt(sigma, "stress") @ to_voigt(eps, "strain")``.
- Mandel (Kelvin) form scales the shears by sqrt(2) for both, so norms and products are plain dot products
  and a stiffness is a symmetric 6x6 matrix with the same eigenvalues as the tensor.
"""

from __future__ import annotations

from functools import cache, lru_cache

import numpy as np
from numpy.typing import ArrayLike

from .validation import check_option, check_poisson, check_positive, number_arguments

__all__ = [
    "VECTOR_WEIGHTS", "VOIGT_PAIRS", "to_voigt", "from_voigt", "to_voigt4", "to_mandel", "to_mandel4", "trace",
    "ddot", "ddot42", "positive_part", "negative_part", "lame", "isotropic_stiffness", "sphere_quadrature",
    "sphere_average", "fourth_moment_contraction"
]

#: Index pairs of the Voigt/Mandel positions, order (11, 22, 33, 23, 13, 12), Eq. (2.17).
VOIGT_PAIRS = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))

_SQRT2 = np.sqrt(2.0)
#: Weight of each position when a symmetric tensor becomes a vector.
VECTOR_WEIGHTS = {
    "stress": np.array([1.0, 1.0, 1.0, 1.0, 1.0, 1.0]),
    "strain": np.array([1.0, 1.0, 1.0, 2.0, 2.0, 2.0]),
    "mandel": np.array([1.0, 1.0, 1.0, _SQRT2, _SQRT2, _SQRT2]),
}

I2 = np.eye(3)


def _check_tensor(name, A, order=2):
    A = np.asarray(A, dtype=float)
    if A.shape[A.ndim - order:] != (3,) * order:
        raise ValueError(f"{name} must have shape (..., {', '.join(['3'] * order)}), got {A.shape}")
    return A


def _check_vector(name, v, ndim=1):
    v = np.asarray(v, dtype=float)
    if v.shape[v.ndim - ndim:] != (6,) * ndim:
        raise ValueError(f"{name} must have shape (..., {', '.join(['6'] * ndim)}), got {v.shape}")
    return v


@cache
def _basis(kind: str) -> np.ndarray:
    """``P[k, i, j]`` with ``vector_k = w_k A_ij`` picked at pair k; symmetric so ``A = sum_k P[k] v_k``."""
    check_option("kind", kind, VECTOR_WEIGHTS)
    P = np.zeros((6, 3, 3))
    for k, (i, j) in enumerate(VOIGT_PAIRS):
        P[k, i, j] = P[k, j, i] = 1.0
    return P


def _to_vector(A, weights):
    i, j = np.array(VOIGT_PAIRS).T
    return A[..., i, j] * weights


def _from_vector(v, weights):
    P = _basis("stress")
    return np.einsum("...k,kij->...ij", v / weights, P)


# --- second-order tensors ---------------------------------------------------------------------------------


@number_arguments
def to_voigt(A: ArrayLike, kind: str = "stress") -> np.ndarray:
    """Voigt vector of a symmetric tensor, Eq. (2.17). ``kind="strain"`` doubles the shears."""
    check_option("kind", kind, ("stress", "strain"))
    return _to_vector(_check_tensor("A", A), VECTOR_WEIGHTS[kind])


@number_arguments
def from_voigt(v: ArrayLike, kind: str = "stress") -> np.ndarray:
    """Symmetric tensor from its Voigt vector (inverse of :func:`to_voigt`)."""
    check_option("kind", kind, ("stress", "strain"))
    return _from_vector(_check_vector("v", v), VECTOR_WEIGHTS[kind])


@number_arguments
def to_mandel(A: ArrayLike) -> np.ndarray:
    """Mandel (Kelvin) vector of a symmetric tensor: shears times sqrt(2); ``|A| = |to_mandel(A)|``."""
    return _to_vector(_check_tensor("A", A), VECTOR_WEIGHTS["mandel"])


@number_arguments
def from_mandel(v: ArrayLike) -> np.ndarray:
    """Symmetric tensor from its Mandel vector."""
    return _from_vector(_check_vector("v", v), VECTOR_WEIGHTS["mandel"])


@number_arguments
def mandel_rotation(Q: ArrayLike) -> np.ndarray:
    """Mandel matrix ``R`` (..., 6, 6) of the change of axes ``A' = Q A Q^T`` (rows of ``Q`` are the new axes):
    ``to_mandel(Q A Q^T) = R @ to_mandel(A)``. ``R`` is orthogonal, so ``A = R^T A'`` and a stiffness turns
    into ``R C R^T``."""
    Q = _check_tensor("Q", Q)
    units = from_mandel(np.eye(6))                                   # (6, 3, 3): the tensor of each basis vector
    turned = np.einsum("...ia,kab,...jb->...kij", Q, units, Q)
    return np.swapaxes(to_mandel(turned), -1, -2)


@number_arguments
def trace(A: ArrayLike) -> np.ndarray:
    """tr A, batched."""
    return np.trace(_check_tensor("A", A), axis1=-2, axis2=-1)


@number_arguments
def dev(A: ArrayLike) -> np.ndarray:
    """Deviator ``dev A = A - tr(A)/3 I``."""
    A = _check_tensor("A", A)
    return A - trace(A)[..., None, None] / 3.0 * I2


@number_arguments
def ddot(A: ArrayLike, B: ArrayLike) -> np.ndarray:
    """Double contraction ``A : B = A_ij B_ij`` of two second-order tensors."""
    return np.einsum("...ij,...ij->...", _check_tensor("A", A), _check_tensor("B", B))


@number_arguments
def norm(A: ArrayLike) -> np.ndarray:
    """Frobenius norm ``|A| = sqrt(A : A)``."""
    return np.sqrt(ddot(A, A))


@number_arguments
def outer(A: ArrayLike, B: ArrayLike) -> np.ndarray:
    """Dyadic product ``(A (x) B)_ijkl = A_ij B_kl``."""
    return np.einsum("...ij,...kl->...ijkl", _check_tensor("A", A), _check_tensor("B", B))


@number_arguments
def ddot42(C: ArrayLike, A: ArrayLike) -> np.ndarray:
    """``(C : A)_ij = C_ijkl A_kl``."""
    return np.einsum("...ijkl,...kl->...ij", _check_tensor("C", C, 4), _check_tensor("A", A))


# --- fourth-order tensors -------------------------------------------------------------------------------


def identity4_sym() -> np.ndarray:
    """Symmetric fourth-order identity ``I^s_ijkl = (d_ik d_jl + d_il d_jk)/2`` (maps symmetric A to A)."""
    return 0.5 * (np.einsum("ik,jl->ijkl", I2, I2) + np.einsum("il,jk->ijkl", I2, I2))


def identity4_vol() -> np.ndarray:
    """Volumetric projector ``I (x) I / 3``."""
    return np.einsum("ij,kl->ijkl", I2, I2) / 3.0


def identity4_dev() -> np.ndarray:
    """Deviatoric projector ``I^s - I (x) I / 3``: ``identity4_dev() : A = dev A`` for symmetric A."""
    return identity4_sym() - identity4_vol()


def _matrix_weights(kind):
    """Row/column weights that turn ``C_ijkl`` into the 6x6 matrix of the given notation."""
    if kind == "mandel":
        w = VECTOR_WEIGHTS["mandel"]
        return w, w
    if kind == "stiffness":  # stress = C strain, Voigt: plain rows, plain columns
        return VECTOR_WEIGHTS["stress"], VECTOR_WEIGHTS["stress"]
    # compliance: engineering strain = S stress; a shear row is doubled, a shear column counts twice
    return VECTOR_WEIGHTS["strain"], VECTOR_WEIGHTS["strain"]


_MATRIX_KINDS = ("stiffness", "compliance", "mandel")


@number_arguments
def to_voigt4(C: ArrayLike, kind: str = "stiffness") -> np.ndarray:
    """6x6 matrix of a fourth-order tensor with minor symmetries.

    ``kind="stiffness"``: ``to_voigt(C:eps, "stress") = M @ to_voigt(eps, "strain")``;
    ``kind="compliance"``: ``to_voigt(S:sig, "strain") = M @ to_voigt(sig, "stress")``.
    """
    check_option("kind", kind, _MATRIX_KINDS)
    C = _check_tensor("C", C, 4)
    i, j = np.array(VOIGT_PAIRS).T
    rows, cols = _matrix_weights(kind)
    M = C[..., i[:, None], j[:, None], i[None, :], j[None, :]]
    return M * rows[:, None] * cols[None, :]


@number_arguments
def from_voigt4(M: ArrayLike, kind: str = "stiffness") -> np.ndarray:
    """Fourth-order tensor (with minor symmetries) from its 6x6 matrix; inverse of :func:`to_voigt4`."""
    check_option("kind", kind, _MATRIX_KINDS)
    M = _check_vector("M", M, ndim=2)
    rows, cols = _matrix_weights(kind)
    P = _basis("stress")
    return np.einsum("...ab,aij,bkl->...ijkl", M / (rows[:, None] * cols[None, :]), P, P)


@number_arguments
def to_mandel4(C: ArrayLike) -> np.ndarray:
    """Mandel 6x6 matrix of a fourth-order tensor: ``to_mandel(C:A) = to_mandel4(C) @ to_mandel(A)``."""
    return to_voigt4(C, "mandel")


def from_mandel4(M) -> np.ndarray:
    """Fourth-order tensor from its Mandel matrix."""
    return from_voigt4(M, "mandel")


# --- isotropic elasticity -------------------------------------------------------------------------------


def lame(E, nu) -> tuple:
    """Lame constants ``(lambda, mu)`` from Young's modulus E and Poisson's ratio -1 < nu < 1/2."""
    E = check_positive("E", E)
    nu = check_poisson("nu", nu)
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


def isotropic_stiffness(E, nu, notation: str = "tensor") -> np.ndarray:
    """Isotropic elasticity tensor ``C = lambda I (x) I + 2 mu I^s`` (units of E).

    ``notation``: ``"tensor"`` (3x3x3x3), ``"voigt"`` (6x6, stress = C @ engineering strain) or ``"mandel"``.
    """
    check_option("notation", notation, ("tensor", "voigt", "mandel"))
    lam, mu = lame(E, nu)
    C = 3.0 * lam * identity4_vol() + 2.0 * mu * identity4_sym()
    if notation == "tensor":
        return C
    return to_voigt4(C, "stiffness" if notation == "voigt" else "mandel")


# --- spectral split, Eq. (6.57) -------------------------------------------------------------------------


def _spectral_part(eps, select):
    eps = _check_tensor("eps", eps)
    if not np.all(np.isfinite(eps)):
        raise ValueError("eps must be finite")
    sym = 0.5 * (eps + np.swapaxes(eps, -1, -2))
    values, vectors = np.linalg.eigh(sym)
    return np.einsum("...ia,...a,...ja->...ij", vectors, select(values), vectors)


def positive_part(eps) -> np.ndarray:
    """Tensile part ``eps+ = sum_a <eps_a>+ n_a (x) n_a`` of a symmetric tensor, Eq. (6.57)."""
    return _spectral_part(eps, lambda v: np.maximum(v, 0.0))


def negative_part(eps) -> np.ndarray:
    """Compressive twin of :func:`positive_part`: ``eps- = eps - eps+``."""
    return _spectral_part(eps, lambda v: np.minimum(v, 0.0))


# --- averages over the unit sphere, Eq. (5.18) ----------------------------------------------------------


@lru_cache(maxsize=32)
def _sphere_rule(degree: int):
    n_theta = degree // 2 + 1  # Gauss-Legendre in cos(theta): exact to 2 n_theta - 1 >= degree
    n_phi = degree + 1  # trapezoid in phi: exact for trigonometric degree <= n_phi - 1 = degree
    x, w = np.polynomial.legendre.leggauss(n_theta)
    phi = 2.0 * np.pi * np.arange(n_phi) / n_phi
    cos_t, ph = np.meshgrid(x, phi, indexing="ij")
    sin_t = np.sqrt(1.0 - cos_t**2)
    directions = np.stack([sin_t * np.cos(ph), sin_t * np.sin(ph), cos_t], axis=-1).reshape(-1, 3)
    weights = np.repeat(w / 2.0, n_phi) / n_phi
    directions.setflags(write=False)
    weights.setflags(write=False)
    return directions, weights


def sphere_quadrature(degree: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """Directions ``(m, 3)`` and weights ``(m,)`` (summing to 1) of a product Gauss rule on the unit sphere.

    The average of every polynomial of total degree <= ``degree`` in the direction components is exact.
    """
    if not isinstance(degree, int | np.integer) or degree < 0:
        raise ValueError(f"degree must be a non-negative integer, got {degree!r}")
    return _sphere_rule(int(degree))


def sphere_average(f, degree: int = 8) -> np.ndarray:
    """Average ``<f(n)>`` of ``f`` over unit directions; ``f`` maps ``(m, 3)`` directions to ``(m, ...)``.

    Exact for polynomial integrands up to ``degree``. Eq. (5.18): ``<n (x) n> = I/3`` and
    ``<n (x) n (x) n (x) n> : sigma = (tr(sigma) I + 2 sigma)/15``.
    """
    n, w = sphere_quadrature(degree)
    values = np.asarray(f(n))
    if values.shape[0] != n.shape[0]:
        raise ValueError(f"f must return one value per direction (leading axis {n.shape[0]}), got {values.shape}")
    return np.tensordot(w, values, axes=(0, 0))


@number_arguments
def fourth_moment_contraction(sigma: ArrayLike) -> np.ndarray:
    """Closed form of Eq. (5.18): ``<n n n n> : sigma = (tr(sigma) I + 2 sigma)/15`` for symmetric sigma."""
    sigma = _check_tensor("sigma", sigma)
    return (trace(sigma)[..., None, None] * I2 + 2.0 * sigma) / 15.0
