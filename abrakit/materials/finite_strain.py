"""Finite-strain J2 plasticity by the exponential map in logarithmic strains (Simo 1992; Simo & Hughes 1998, Box 9.1).

Why this formulation: it keeps the small-strain return map of Eq. (6.59)–(6.61) (``VonMisesPlasticity``, radial
return) *unchanged*, applied to the logarithmic elastic strain, and its consistent tangent needs only the first
derivative of the matrix logarithm. The multiplicative split F = F_e F_p is carried by the plastic metric
C_p⁻¹ = F_p⁻¹ F_p⁻ᵀ; plastic flow is isochoric (det F_p = 1 exactly, because the return is deviatoric).

One step, from (C_p⁻¹, α_p) at t_m to the new deformation gradient F:

    b_e^tr = F C_p⁻¹ Fᵀ,      ε_e^tr = ½ ln b_e^tr                         (elastic trial, spatial log strain)
    τ, 𝔻, Δε_p = small-strain return map at ε_e^tr with ε_p = 0, α_p      (Eq. 6.59–6.61, Kirchhoff stress τ)
    b_e = exp(2 (ε_e^tr − Δε_p)),  C_p⁻¹ = F⁻¹ b_e F⁻ᵀ                     (update, coaxial with b_e^tr)
    P = τ F⁻ᵀ                                                              (first Piola–Kirchhoff stress)

Consistent tangent A = ∂P/∂F (9 × 9, row-major index iJ): with l = δF F⁻¹,

    δb_e^tr = l b + b lᵀ,    δτ = 𝔻 : ½ D ln(b)[δb_e^tr],    δP = δτ F⁻ᵀ − τ F⁻ᵀ δFᵀ F⁻ᵀ,

and the derivative of the logarithm of a symmetric matrix b = Q diag(λ) Qᵀ by the Daleckii–Krein formula
D ln(b)[h] = Q (Γ ∘ Qᵀ h Q) Qᵀ with the divided differences Γ_ij = (ln λ_i − ln λ_j)/(λ_i − λ_j), Γ_ii = 1/λ_i
(computed as log1p(t)/(t λ_j), t = λ_i/λ_j − 1, so repeated eigenvalues, e.g. the undeformed state, are exact).

Closed forms the tests check: a rigid rotation F = R gives τ = 0; uniaxial stress gives the small-strain
uniaxial curve between the Kirchhoff stress τ_11 and the logarithmic strain ln λ (so P_11 = τ_11 / λ); the
tangent equals a finite-difference derivative of P. Units: MPa, strains dimensionless.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike

from .. import tensors as T
from ..compiled import HAVE_NUMBA, njit, prange
from ..validation import check_callable, check_finite, check_instance, check_shape, number_arguments
from . import _finite_strain_kernels as _kernels
from .elastic import LinearElastic
from .model_two import ModelIIDamage
from .plasticity import VonMisesPlasticity

_PAIRS = np.array(T.VOIGT_PAIRS)                               # Mandel component I <-> index pair (p_I, q_I)
_WEIGHT = np.array([1.0, 1.0, 1.0, np.sqrt(2.0), np.sqrt(2.0), np.sqrt(2.0)])


@number_arguments
def log_divided_differences(lam: ArrayLike) -> np.ndarray:
    """Γ_ij = (ln λ_i − ln λ_j)/(λ_i − λ_j), with Γ_ii = 1/λ_i, for eigenvalues ``lam`` (..., 3) > 0."""
    li, lj = lam[..., :, None], lam[..., None, :]
    t = li / lj - 1.0
    small = np.abs(t) < 1e-5
    safe_t = np.where(small, 1.0, t)
    ratio = np.where(small, 1.0 - t / 2.0 + t * t / 3.0, np.log1p(safe_t) / safe_t)   # log1p(t)/t
    return ratio / lj


@number_arguments
def log_derivative(vectors: ArrayLike, gamma: ArrayLike, h: ArrayLike) -> np.ndarray:
    """D ln(b)[h] = Q (Γ ∘ Qᵀ h Q) Qᵀ for b = Q diag(λ) Qᵀ; ``h`` (..., [k,] 3, 3) symmetric directions."""
    Q = vectors if h.ndim == vectors.ndim else vectors[..., None, :, :]
    G = gamma if h.ndim == gamma.ndim else gamma[..., None, :, :]
    Qt = np.swapaxes(Q, -1, -2)
    return Q @ (G * (Qt @ h @ Q)) @ Qt


def _mandel_rotation(Q: np.ndarray) -> np.ndarray:
    """R (..., 6, 6) with to_mandel(Qᵀ A Q) = R @ to_mandel(A) for symmetric A and rotations Q (..., 3, 3)."""
    p, q = _PAIRS[:, 0], _PAIRS[:, 1]                # rows: components in the rotated basis (a, b) = (p_I, q_I)
    i, j = p[None, :], q[None, :]                    # columns: global components (i, j) = (p_J, q_J)
    a, b = p[:, None], q[:, None]
    shear = (i != j).astype(float)
    R = Q[..., i, a] * Q[..., j, b] + shear * Q[..., j, a] * Q[..., i, b]
    return R * (_WEIGHT[:, None] / _WEIGHT[None, :])


def _tangent(F_inv, Q, lam, D, P):
    """A = ∂P/∂F (..., 9, 9) worked in the eigenbasis Q of b_e^tr, where D ln is elementwise (module docstring).

    For δF = e_k ⊗ e_L: l̃ = Qᵀ δF F⁻¹ Q has l̃_ab = Q_ka G_Lb with G = F⁻¹ Q; the trial log strain changes by
    δε̃_ab = ½ Γ_ab (l̃_ab λ_b + λ_a l̃_ba); δτ̃ = D̃ δε̃ with D̃ = R D Rᵀ; and
    δP_iJ = Σ_ab Q_ia δτ̃_ab G_Jb − P_iL F⁻¹_Jk.
    """
    G = F_inv @ Q
    l_t = Q[..., :, None, :, None] * G[..., None, :, None, :]             # (..., k, L, a, b)
    h_t = l_t * lam[..., None, None, None, :] + lam[..., None, None, :, None] * np.swapaxes(l_t, -1, -2)
    d_eps = 0.5 * log_divided_differences(lam)[..., None, None, :, :] * h_t
    d_eps = d_eps[..., _PAIRS[:, 0], _PAIRS[:, 1]] * _WEIGHT                # Mandel in the eigenbasis, (.., k, L, 6)
    R = _mandel_rotation(Q)
    D_t = R @ D @ np.swapaxes(R, -1, -2)
    d_tau_v = np.einsum("...IJ,...klJ->...klI", D_t, d_eps)
    d_tau = np.zeros(d_tau_v.shape[:-1] + (3, 3))
    d_tau[..., _PAIRS[:, 0], _PAIRS[:, 1]] = d_tau_v / _WEIGHT
    d_tau[..., _PAIRS[:, 1], _PAIRS[:, 0]] = d_tau_v / _WEIGHT
    A = np.einsum("...ia,...klab,...Jb->...iJkl", Q, d_tau, G, optimize=True)
    A -= P[..., :, None, None, :] * F_inv[..., None, :, :, None]                  # P_iL F⁻¹_Jk
    return A.reshape(*A.shape[:-4], 9, 9)


class DeferredTangentResponse:
    """A :class:`~abrakit.materials.MaterialResponse` whose tangent is computed on first access: the Newton
    solver never reads it at the converged iterate nor at rejected line-search trials, where it would be most
    of the cost of a finite-strain update.

    ``tangent_of(elements)`` gives the tangent of the points of the selected elements only (the first axis of
    the point array), computed for them alone where ``partial`` is given (the compiled update), else sliced from
    the whole tangent; ``yielding`` flags the points that flowed plastically in this update (their tangent is the
    algorithmic one; elsewhere it is the elastic tangent at F). Both serve
    :class:`~abrakit.fem.tangent_reuse.ElementTangentReuse`."""

    def __init__(self, stress: np.ndarray, state: dict, tangent: Callable[[], np.ndarray],
                 partial: Callable[[np.ndarray], np.ndarray] | None = None, yielding: np.ndarray | None = None):
        if not (isinstance(stress, np.ndarray) and stress.dtype.kind == "f"):   # NaN: a diverged trial's, checked
            raise TypeError(f"stress must be a float array, got {stress!r}")       # by the Newton solver
        check_instance("state", state, dict)
        check_callable("tangent", tangent)
        check_callable("partial", partial, optional=True)
        if yielding is not None and not (isinstance(yielding, (np.ndarray, np.bool_)) and yielding.dtype == bool):
            raise TypeError(f"yielding must be a boolean array or None, got {yielding!r}")
        self.stress = stress
        self.state = state
        self._tangent = tangent
        self._partial = partial
        self.yielding = yielding

    @cached_property
    def tangent(self) -> np.ndarray:
        return self._tangent()

    def tangent_of(self, elements: np.ndarray) -> np.ndarray:
        """The tangent of the points of ``elements`` (indices into the first axis), ``(n, ..., 9, 9)``."""
        if self._partial is None or "tangent" in self.__dict__:
            return self.tangent[elements]
        return self._partial(np.asarray(elements))


@njit(cache=True, parallel=True)
def _tangent_compiled(F_inv, Q, lam, D, P):  # pragma: no cover - compiled; checked against _tangent
    """The same A = ∂P/∂F as :func:`_tangent`, one point at a time (numba, parallel over points)."""
    n = F_inv.shape[0]
    A = np.zeros((n, 3, 3, 3, 3))
    pi, qi = _PAIRS[:, 0], _PAIRS[:, 1]
    for e in prange(n):
        G = F_inv[e] @ Q[e]
        gamma = np.empty((3, 3))
        for a in range(3):
            for b in range(3):
                t = lam[e, a] / lam[e, b] - 1.0
                ratio = 1.0 - t / 2.0 + t * t / 3.0 if abs(t) < 1e-5 else np.log1p(t) / t
                gamma[a, b] = ratio / lam[e, b]
        R = np.empty((6, 6))
        for I in range(6):
            for J in range(6):
                a, b, i, j = pi[I], qi[I], pi[J], qi[J]
                r = Q[e, i, a] * Q[e, j, b]
                if i != j:
                    r += Q[e, j, a] * Q[e, i, b]
                R[I, J] = r * _WEIGHT[I] / _WEIGHT[J]
        Dt = R @ D[e] @ R.T
        d_eps = np.empty(6)
        d_tau = np.empty((3, 3))
        for k in range(3):
            for L in range(3):
                for I in range(6):
                    a, b = pi[I], qi[I]
                    h = Q[e, k, a] * G[L, b] * lam[e, b] + lam[e, a] * Q[e, k, b] * G[L, a]
                    d_eps[I] = 0.5 * gamma[a, b] * h * _WEIGHT[I]
                d_tau_v = Dt @ d_eps
                for I in range(6):
                    d_tau[pi[I], qi[I]] = d_tau_v[I] / _WEIGHT[I]
                    d_tau[qi[I], pi[I]] = d_tau_v[I] / _WEIGHT[I]
                X = Q[e] @ d_tau @ G.T
                for i in range(3):
                    for J in range(3):
                        A[e, i, J, k, L] = X[i, J] - P[e, i, L] * F_inv[e, J, k]
    return A.reshape(n, 9, 9)


@number_arguments
def material_tangent(F_inv: ArrayLike, Q: ArrayLike, lam: ArrayLike, D: ArrayLike, P: ArrayLike,
                     compiled: bool | None = None) -> np.ndarray:
    """A = ∂P/∂F for a batch of points: the numba kernel where numba is installed (``compiled=None``), else the
    vectorised NumPy :func:`_tangent`; both give the same numbers (tested)."""
    if compiled is None:
        compiled = HAVE_NUMBA
    shape = F_inv.shape[:-2]
    if not compiled:
        return _tangent(F_inv, Q, lam, D, P)
    flat = [np.ascontiguousarray(x.reshape(-1, *x.shape[len(shape):])) for x in (F_inv, Q, lam, D, P)]
    return _tangent_compiled(*flat).reshape(*shape, 9, 9)


@dataclass(frozen=True)
class LogStrainPlasticity:
    """Finite-strain J2 plasticity (exponential map, logarithmic strains) around a small-strain ``base`` model.

    ``base`` is :class:`~abrakit.materials.VonMisesPlasticity` (with ``integration="implicit"``, the radial
    return the exponential map is exact for), :class:`~abrakit.materials.LinearElastic` (then the model is the
    Hencky hyperelastic material) or :class:`~abrakit.materials.ModelIIDamage` (Model II's ERVE damage on top,
    Eq. 6.81–6.105, plasticity by the implicit radial return of the effective stress): its scalar f̄(d) scales
    the Kirchhoff stress, so the return stays coaxial with b_e^tr and the exponential map applies unchanged; the
    rate limit (``external_work`` or ``external_power``) is passed through ``update``'s keywords. Model II runs
    on the NumPy path only. ``update(state, F)`` takes the deformation gradient as 9-vectors (row-major
    F_iJ) and returns P (9-vectors, MPa) and A = ∂P/∂F (9 × 9). The state holds ``Cp_inv`` (..., 3, 3),
    ``alpha_p``, ``dissipation`` (accumulated r_p |Δε_p| per unit *reference* volume, MPa), the logarithmic
    elastic strain ``eps_e`` and the Cauchy stress ``cauchy`` (Mandel, MPa) for output, and ``J`` = det F.
    """

    base: VonMisesPlasticity | LinearElastic | ModelIIDamage

    def __post_init__(self):
        if not isinstance(self.base, (VonMisesPlasticity, LinearElastic, ModelIIDamage)):
            raise TypeError(f"base must be a VonMisesPlasticity, LinearElastic or ModelIIDamage, got "
                            f"{type(self.base).__name__}")
        if self.plastic and self.base.integration != "implicit":
            raise ValueError("base.integration must be 'implicit': the exponential map is the radial return in "
                             "logarithmic strains")

    @property
    def plastic(self) -> bool:
        if isinstance(self.base, ModelIIDamage):
            return self.base.r_p is not None
        return isinstance(self.base, VonMisesPlasticity)

    @property
    def damaged(self) -> bool:
        """Model II's damage on top (state ``d``, ``psi0``)."""
        return isinstance(self.base, ModelIIDamage)

    @property
    def E(self) -> float:
        return self.base.E

    @property
    def nu(self) -> float:
        return self.base.nu

    def initial_state(self, shape: tuple[int, ...]) -> dict[str, np.ndarray]:
        state = {"Cp_inv": np.broadcast_to(np.eye(3), (*shape, 3, 3)).copy(), "eps_e": np.zeros((*shape, 6)),
                 "cauchy": np.zeros((*shape, 6)), "J": np.ones(shape)}
        if self.plastic or self.damaged:
            state.update(alpha_p=np.zeros(shape), dissipation=np.zeros(shape))
        if self.damaged:
            state.update(d=np.zeros((*shape, self.base.n)), psi0=np.zeros(shape))
        return state

    def update(self, state, F, dt: float = 1.0, compiled: bool | None = None,
               **loading) -> DeferredTangentResponse:
        """P, A = ∂P/∂F and the new state at the deformation gradients ``F`` (..., 9) (see module docstring).

        ``compiled`` (default: where numba is installed) runs the point-by-point kernels of
        :mod:`abrakit.materials._finite_strain_kernels` (Jacobi eigenvectors, explicit loops: 5–10× faster on the
        scratch's 54 000 points); ``False`` the vectorised NumPy path below. Both give the same numbers to
        round-off (tested)."""
        F = check_shape("F", np.asarray(F, dtype=float), (..., 9))
        check_finite("F", F)
        if (HAVE_NUMBA if compiled is None else compiled) and not self.damaged:
            return self._update_compiled(state, F)
        F = F.reshape(*F.shape[:-1], 3, 3)
        J = np.linalg.det(F)
        if np.any(J <= 0.0):
            raise FloatingPointError(f"det F = {J.min():.3g} <= 0: an element is inverted (cut the step back)")
        F_inv = np.linalg.inv(F)
        F_inv_T = np.swapaxes(F_inv, -1, -2)
        b_trial = F @ state["Cp_inv"] @ np.swapaxes(F, -1, -2)
        b_trial = 0.5 * (b_trial + np.swapaxes(b_trial, -1, -2))
        lam, Q = np.linalg.eigh(b_trial)
        eps_trial = T.to_mandel(np.einsum("...ia,...a,...ja->...ij", Q, 0.5 * np.log(lam), Q))

        shape = J.shape
        base_state = self.base.initial_state(shape)
        carried = [k for k in ("alpha_p", "dissipation", "d") if k in base_state and k in state]
        for key in carried:
            base_state[key] = np.broadcast_to(state[key], base_state[key].shape)
        if self.damaged:
            # the old strain, which Model II's seed tangent reads
            base_state["eps"] = np.broadcast_to(state["eps_e"], base_state["eps"].shape)
            response = self.base.update(base_state, eps_trial, dt, **loading)
        else:
            response = self.base.update(base_state, eps_trial, dt)
        tau = response.stress
        eps_e = eps_trial - response.state["eps_p"] if self.plastic else eps_trial
        new_state = {"J": J, "eps_e": eps_e, "cauchy": tau / J[..., None]}
        new_state.update({key: response.state[key] for key in carried})
        if self.damaged:
            new_state["psi0"] = response.state["psi0"]
        if self.plastic:
            # ε_e is coaxial with b_e^tr (radial return): its eigenvalues are the diagonal of Qᵀ ε_e Q
            w = np.einsum("...ia,...ij,...ja->...a", Q, T.from_mandel(eps_e), Q)
            b_e = np.einsum("...ia,...a,...ja->...ij", Q, np.exp(2.0 * w), Q)
            Cp_inv = F_inv @ b_e @ np.swapaxes(F_inv, -1, -2)
            new_state["Cp_inv"] = 0.5 * (Cp_inv + np.swapaxes(Cp_inv, -1, -2))
        else:
            new_state["Cp_inv"] = state["Cp_inv"]

        P = T.from_mandel(tau) @ F_inv_T
        yielding = None                  # damage: its growth changes the tangent too; no element tangent is reused
        if not self.damaged:
            yielding = (new_state["alpha_p"] > state["alpha_p"]) if self.plastic else np.zeros(shape, dtype=bool)
        return DeferredTangentResponse(P.reshape(*shape, 9), new_state,
                                       lambda: material_tangent(F_inv, Q, lam, response.tangent, P),
                                       yielding=yielding)

    def _update_compiled(self, state, F) -> DeferredTangentResponse:
        """:meth:`update` by :func:`~abrakit.materials._finite_strain_kernels.log_strain_update` (same formulas)."""
        shape = F.shape[:-1]
        m = math.prod(shape)
        flat = np.ascontiguousarray(F).reshape(m, 3, 3)
        Cp_inv = np.ascontiguousarray(np.broadcast_to(state["Cp_inv"], (*shape, 3, 3))).reshape(m, 3, 3)
        base = self.base
        plastic = self.plastic
        alpha_p = dissipation = np.zeros(0)
        if plastic:
            alpha_p = np.ascontiguousarray(np.broadcast_to(state["alpha_p"], shape), dtype=float).reshape(m)
            dissipation = np.ascontiguousarray(np.broadcast_to(state["dissipation"], shape), dtype=float).reshape(m)
        P, eps_e, cauchy = np.empty((m, 9)), np.empty((m, 6)), np.empty((m, 6))
        Cp_new, J, F_inv = np.empty((m, 3, 3)), np.empty(m), np.empty((m, 3, 3))
        Q, lam, D = np.empty((m, 3, 3)), np.empty((m, 3)), np.empty((m, 6, 6))
        alpha_new, dissipation_new = np.empty_like(alpha_p), np.empty_like(dissipation)
        r_p, K_H = (base.r_p, base.K_H) if plastic else (0.0, 0.0)
        smallest = _kernels.log_strain_update(flat, Cp_inv, alpha_p, dissipation, base.stiffness, 2.0 * base.mu,
                                              r_p, K_H, plastic, P, Cp_new, alpha_new, dissipation_new, eps_e,
                                              cauchy, J, F_inv, Q, lam, D)
        if not smallest > 0.0:
            raise FloatingPointError(f"det F = {smallest:.3g} <= 0: an element is inverted (cut the step back)")
        new_state = {"J": J.reshape(shape), "eps_e": eps_e.reshape(*shape, 6), "cauchy": cauchy.reshape(*shape, 6),
                     "Cp_inv": Cp_new.reshape(*shape, 3, 3) if plastic else state["Cp_inv"]}
        if plastic:
            new_state.update(alpha_p=alpha_new.reshape(shape), dissipation=dissipation_new.reshape(shape))

        def of(*arrays, elements):                  # the points of the selected elements (first axis of shape)
            return [np.ascontiguousarray(a.reshape(*shape, *a.shape[1:])[elements].reshape(-1, *a.shape[1:]))
                    for a in arrays]

        def partial(elements):
            picked = _kernels.log_strain_tangent(*of(F_inv, Q, lam, D, P, elements=elements))
            return picked.reshape(len(elements), *shape[1:], 9, 9)

        yielding = (alpha_new > alpha_p).reshape(shape) if plastic else np.zeros(shape, dtype=bool)
        return DeferredTangentResponse(
            P.reshape(*shape, 9), new_state,
            lambda: _kernels.log_strain_tangent(F_inv, Q, lam, D, P).reshape(*shape, 9, 9),
            partial=partial if len(shape) > 1 else None, yielding=yielding)

    @property
    def d_max(self) -> float:
        """Model II's damage cap (a damaged base only)."""
        return self.base.d_max

    def effective_damage(self, state) -> np.ndarray:
        """Model II's scalar damage 1 − √f̄ of each point (a damaged base only)."""
        return self.base.effective_damage(state)

    def stored_energy(self, state) -> np.ndarray:
        """ψ(ε_e) + ½ K_H α_p² per unit reference volume (MPa): the small-strain energy of the log elastic strain
        (Model II: f̄(d) ψ(ε_e) + ½ K_H α_p², Eq. 6.89)."""
        if self.damaged:
            return self.base.stored_energy({"eps": state["eps_e"], "eps_p": np.zeros_like(state["eps_e"]),
                                            "d": state["d"], "alpha_p": state["alpha_p"]})
        energy = self.base.elastic_energy(state["eps_e"])
        if self.plastic:
            energy = energy + 0.5 * self.base.K_H * state["alpha_p"] ** 2
        return energy

    def dissipation(self, state) -> np.ndarray:
        return state["dissipation"] if self.plastic or self.damaged else np.zeros(state["J"].shape)


def ductile_damage_update(criterion, damage: ArrayLike, old_state: dict, new_state: dict) -> np.ndarray:
    """The ductile damage indicator D of every point after a converged increment of :class:`LogStrainPlasticity`,
    D_{n+1} = D_n + Δε̄ᵖ/ε_f(η, ξ) (:mod:`abrakit.materials.ductile_failure`), as a new array.

    A post-processing step: it reads the two states that :meth:`LogStrainPlasticity.update` returned at the start
    (``old_state``) and at the end (``new_state``) of the increment and changes neither, nor the plasticity's
    results. Δε̄ᵖ = √(2/3) (α_p,new − α_p,old), the equivalent logarithmic plastic strain of the radial return
    (|Δε_p| accumulates in α_p); η and ξ come from the Kirchhoff stress τ = J σ at the end of the increment (the
    state's ``cauchy`` and ``J``). ``criterion`` is a failure model with ``update(damage, plastic_strain_increment,
    stress)``, e.g. :class:`~abrakit.materials.ductile_failure.JohnsonCookFailure`; ``damage`` (≥ 0) has the
    points' shape (or broadcasts to it)."""
    if not callable(getattr(criterion, "update", None)):
        raise TypeError(f"criterion must be a failure model with update(damage, plastic_strain_increment, stress), "
                        f"got {type(criterion).__name__}")
    for name, state in (("old_state", old_state), ("new_state", new_state)):
        if not isinstance(state, dict) or "alpha_p" not in state:
            raise ValueError(f"{name} must be a state of a plastic LogStrainPlasticity (with 'alpha_p')")
    if not {"cauchy", "J"} <= new_state.keys():
        raise ValueError("new_state must hold the 'cauchy' stress and 'J' of LogStrainPlasticity.update")
    alpha_old = check_finite("old_state['alpha_p']", old_state["alpha_p"])
    alpha_new = check_finite("new_state['alpha_p']", new_state["alpha_p"])
    growth = np.asarray(alpha_new, dtype=float) - np.asarray(alpha_old, dtype=float)
    if np.any(growth < 0.0):
        raise ValueError(f"new_state['alpha_p'] must not fall below old_state['alpha_p'] (were the states swapped?), "
                         f"got a change of {growth.min():.3g}")
    J = check_finite("new_state['J']", new_state["J"])
    cauchy = check_shape("new_state['cauchy']", check_finite("new_state['cauchy']", new_state["cauchy"]), (..., 6))
    kirchhoff = T.from_mandel(np.asarray(J)[..., None] * cauchy)
    return criterion.update(damage, math.sqrt(2.0 / 3.0) * growth, kirchhoff)
