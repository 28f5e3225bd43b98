"""Compiled kernels of :class:`~abrakit.materials.LogStrainPlasticity` (numba; private, called by its ``update``).

Each kernel does one quadrature point at a time with the formulas of :mod:`abrakit.materials.finite_strain`,
written as explicit loops over 3 × 3 and 6 × 6 components. The vectorised NumPy path spends a Newton iteration of
the scratch (54 000 points) in batched ``eigh``, ``inv`` and ``einsum`` calls and the earlier compiled tangent in
tiny matrix products (a BLAS call each); here every point's work stays in registers and scratch arrays allocated
once per block of points. The points are split into blocks over the threads (``prange``).

* :func:`eigh3`: the symmetric 3 × 3 eigenproblem by cyclic Jacobi rotations (exact to round-off, repeated
  eigenvalues included: the undeformed state b = I needs no rotation at all);
* :func:`log_strain_update`: the exponential-map update of the module docstring (elastic trial b_e^tr, its
  logarithm, the radial return of :class:`~abrakit.materials.VonMisesPlasticity`, the new plastic metric, P);
* :func:`log_strain_tangent`: A = ∂P/∂F of :func:`abrakit.materials.finite_strain._tangent`.

Both are checked against the NumPy path to round-off (``tests/test_finite_strain.py``).
"""

from __future__ import annotations

import math

import numpy as np

from ..compiled import inverse3, njit, prange

_P = np.array([0, 1, 2, 1, 0, 0])                           # Mandel component I <-> pair (p_I, q_I)
_Q = np.array([0, 1, 2, 2, 2, 1])
_W = np.array([1.0, 1.0, 1.0, math.sqrt(2.0), math.sqrt(2.0), math.sqrt(2.0)])
BLOCK = 256
"""Points per block of a parallel loop (scratch arrays are allocated once per block)."""


@njit(cache=True, inline="always")
def eigh3(a, lam, Q):  # pragma: no cover - compiled
    """Eigenvalues ``lam`` (3,) and orthonormal eigenvectors (columns of ``Q``) of the symmetric 3 × 3 ``a``
    (overwritten: it ends diagonal) by cyclic Jacobi rotations a ← Jᵀ a J, Q ← Q J."""
    for i in range(3):
        for j in range(3):
            Q[i, j] = 1.0 if i == j else 0.0
    scale = a[0, 0] * a[0, 0] + a[1, 1] * a[1, 1] + a[2, 2] * a[2, 2]
    for _ in range(30):
        off = a[0, 1] * a[0, 1] + a[0, 2] * a[0, 2] + a[1, 2] * a[1, 2]
        if off <= 1e-36 * scale or off == 0.0:
            break
        for p, q in ((0, 1), (0, 2), (1, 2)):
            apq = a[p, q]
            if apq == 0.0:
                continue
            theta = (a[q, q] - a[p, p]) / (2.0 * apq)
            if abs(theta) > 1e150:
                t = 0.5 / theta
            else:
                t = (1.0 if theta >= 0.0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1.0))
            c = 1.0 / math.sqrt(t * t + 1.0)
            s = t * c
            for k in range(3):                                   # a J
                akp, akq = a[k, p], a[k, q]
                a[k, p] = c * akp - s * akq
                a[k, q] = s * akp + c * akq
            for k in range(3):                                   # Jᵀ (a J)
                apk, aqk = a[p, k], a[q, k]
                a[p, k] = c * apk - s * aqk
                a[q, k] = s * apk + c * aqk
            a[p, q] = a[q, p] = 0.0
            for k in range(3):                                   # Q J
                qkp, qkq = Q[k, p], Q[k, q]
                Q[k, p] = c * qkp - s * qkq
                Q[k, q] = s * qkp + c * qkq
    for i in range(3):
        lam[i] = a[i, i]


@njit(cache=True, inline="always")
def _pair(i, j):  # pragma: no cover - compiled
    """Mandel index of the off-diagonal pair (i, j): (1, 2) -> 3, (0, 2) -> 4, (0, 1) -> 5."""
    return 6 - i - j if i != j else i


@njit(cache=True, inline="always")
def _sandwich(A, M, out):  # pragma: no cover - compiled
    """The symmetric ``out`` = A M Aᵀ of 3 × 3 matrices, its upper triangle computed (b_e^tr = F C_p⁻¹ Fᵀ)."""
    for i in range(3):
        for j in range(i, 3):
            total = 0.0
            for a in range(3):
                row = 0.0
                for c in range(3):
                    row += M[a, c] * A[j, c]
                total += A[i, a] * row
            out[i, j] = out[j, i] = total


@njit(cache=True, inline="always")
def _plastic_metric(Q, eps_e, F_inv, w, b, Cp_new):  # pragma: no cover - compiled
    """The new plastic metric of a yielding point into ``Cp_new``: ε_e (Mandel) is coaxial with b_e^tr (eigenvectors
    ``Q``), so its eigenvalues are w_a = (Qᵀ ε_e Q)_aa and C_p⁻¹ = F⁻¹ Q diag(e^{2w}) Qᵀ F⁻ᵀ (``w``, ``b``: scratch)."""
    for a in range(3):
        total = 0.0
        for I in range(6):
            p, q = _P[I], _Q[I]
            weight = 1.0 if I < 3 else 2.0 / _W[I]       # both off-diagonal entries
            total += weight * Q[p, a] * Q[q, a] * eps_e[I]
        w[a] = math.exp(2.0 * total)
    for i in range(3):
        for j in range(3):
            total = 0.0
            for a in range(3):
                total += Q[i, a] * w[a] * Q[j, a]
            b[i, j] = total
    _sandwich(F_inv, b, Cp_new)


@njit(cache=True, inline="always")
def _first_piola(tau, F_inv, P):  # pragma: no cover - compiled
    """P = τ F⁻ᵀ as a row-major 9-vector ``P``, for the Kirchhoff stress ``tau`` (Mandel)."""
    for i in range(3):
        for L in range(3):
            total = 0.0
            for j in range(3):
                t_ij = tau[i] if i == j else tau[_pair(i, j)] / _W[3]
                total += t_ij * F_inv[L, j]
            P[3 * i + L] = total


@njit(cache=True, parallel=True)
def log_strain_update(F, Cp_inv, alpha_p, dissipation, stiffness, two_G, r_p, K_H, plastic,
                      P, Cp_new, alpha_new, dissipation_new, eps_e, cauchy, J, F_inv, Q, lam,
                      D):  # pragma: no cover - compiled
    """The exponential-map update of m points (flattened batch): inputs F (m, 3, 3), the state (C_p⁻¹ (m, 3, 3),
    α_p, dissipation), the base model's Mandel stiffness, 2G, r_p, K_H and ``plastic`` (False: Hencky
    elasticity); outputs into P (m, 9), the new state (C_p⁻¹, α_p, dissipation, ε_e (m, 6), Cauchy stress (m, 6),
    J) and what the tangent needs (F⁻¹, Q, λ of b_e^tr, the algorithmic tangent 𝔻 (m, 6, 6)). Returns the
    smallest det F (≤ 0: an inverted element; the outputs of such a point are not used)."""
    m = F.shape[0]
    n_blocks = (m + BLOCK - 1) // BLOCK
    smallest = np.empty(n_blocks)
    for blk in prange(n_blocks):
        b = np.empty((3, 3))
        Qp = np.empty((3, 3))
        lp = np.empty(3)
        e_tr = np.empty(6)
        s = np.empty(6)
        tau = np.empty(6)
        w = np.empty(3)
        low = np.inf
        for k in range(blk * BLOCK, min(m, (blk + 1) * BLOCK)):
            Fk, Fi = F[k], F_inv[k]
            det = inverse3(Fk, Fi)
            J[k] = det
            low = min(low, det)
            if not det > 0.0:
                continue
            _sandwich(Fk, Cp_inv[k], b)                              # b_e^tr = F C_p⁻¹ Fᵀ
            eigh3(b, lp, Qp)
            for a in range(3):
                lam[k, a] = lp[a]
                for i in range(3):
                    Q[k, i, a] = Qp[i, a]
            for I in range(6):                                       # ε^tr = Q diag(½ ln λ) Qᵀ, Mandel
                p, q = _P[I], _Q[I]
                total = 0.0
                for a in range(3):
                    total += Qp[p, a] * 0.5 * math.log(lp[a]) * Qp[q, a]
                e_tr[I] = total * _W[I]
            # radial return at ε^tr with ε_p = 0 (the base model of the log-strain update)
            mean = (e_tr[0] + e_tr[1] + e_tr[2]) / 3.0
            q2 = 0.0
            for I in range(6):
                s[I] = two_G * (e_tr[I] - mean if I < 3 else e_tr[I])
                q2 += s[I] * s[I]
            qn = math.sqrt(q2)
            for I in range(6):
                for L in range(6):
                    D[k, I, L] = stiffness[I, L]
            gamma = 0.0
            if plastic:
                alpha_new[k] = alpha_p[k]
                y = r_p + K_H * alpha_p[k]
                if qn > y:
                    gamma = (qn - y) / (two_G + K_H)
                    alpha_new[k] += gamma
                    bb = two_G * two_G * gamma / qn
                    aa = two_G * two_G / (two_G + K_H) - bb
                    for I in range(6):
                        for L in range(6):
                            dev = (1.0 if I == L else 0.0) - (1.0 / 3.0 if (I < 3 and L < 3) else 0.0)
                            D[k, I, L] -= aa * (s[I] / qn) * (s[L] / qn) + bb * dev
                dissipation_new[k] = dissipation[k] + r_p * gamma
            for I in range(6):
                e = e_tr[I] - (gamma * (s[I] / qn) if gamma > 0.0 else 0.0)
                eps_e[k, I] = e
            for L in range(6):                                       # τ = 𝔻_el : ε_e
                total = 0.0
                for I in range(6):
                    total += eps_e[k, I] * stiffness[I, L]
                tau[L] = total
                cauchy[k, L] = total / det
            if plastic:
                if gamma > 0.0:
                    _plastic_metric(Qp, eps_e[k], Fi, w, b, Cp_new[k])
                else:                           # elastic: the plastic metric stays
                    for i in range(3):
                        for j in range(3):
                            Cp_new[k, i, j] = Cp_inv[k, i, j]
            _first_piola(tau, Fi, P[k])                              # P = τ F⁻ᵀ
        smallest[blk] = low
    return smallest.min() if n_blocks else np.inf


@njit(cache=True, parallel=True)
def log_strain_tangent(F_inv, Q, lam, D, P):  # pragma: no cover - compiled
    """A = ∂P/∂F (m, 9, 9) of :func:`abrakit.materials.finite_strain._tangent`, one point at a time."""
    m = F_inv.shape[0]
    A = np.empty((m, 9, 9))
    n_blocks = (m + BLOCK - 1) // BLOCK
    for blk in prange(n_blocks):
        G = np.empty((3, 3))
        gamma = np.empty((3, 3))
        R = np.empty((6, 6))
        RD = np.empty((6, 6))
        Dt = np.empty((6, 6))
        d_eps = np.empty(6)
        d_tau = np.empty((3, 3))
        QT = np.empty((3, 3))
        for e in range(blk * BLOCK, min(m, (blk + 1) * BLOCK)):
            Qe, Fi = Q[e], F_inv[e]
            for i in range(3):                                       # G = F⁻¹ Q
                for b in range(3):
                    total = 0.0
                    for c in range(3):
                        total += Fi[i, c] * Qe[c, b]
                    G[i, b] = total
            for a in range(3):
                for b in range(3):
                    t = lam[e, a] / lam[e, b] - 1.0
                    ratio = 1.0 - t / 2.0 + t * t / 3.0 if abs(t) < 1e-5 else math.log1p(t) / t
                    gamma[a, b] = ratio / lam[e, b]
            for I in range(6):                                       # R: Mandel rotation into the eigenbasis
                a, b = _P[I], _Q[I]
                for J in range(6):
                    i, j = _P[J], _Q[J]
                    r = Qe[i, a] * Qe[j, b]
                    if i != j:
                        r += Qe[j, a] * Qe[i, b]
                    R[I, J] = r * _W[I] / _W[J]
            for I in range(6):                                       # D̃ = R 𝔻 Rᵀ
                for J in range(6):
                    total = 0.0
                    for K in range(6):
                        total += R[I, K] * D[e, K, J]
                    RD[I, J] = total
            for I in range(6):
                for J in range(6):
                    total = 0.0
                    for K in range(6):
                        total += RD[I, K] * R[J, K]
                    Dt[I, J] = total
            for k in range(3):
                for L in range(3):
                    for I in range(6):
                        a, b = _P[I], _Q[I]
                        h = Qe[k, a] * G[L, b] * lam[e, b] + lam[e, a] * Qe[k, b] * G[L, a]
                        d_eps[I] = 0.5 * gamma[a, b] * h * _W[I]
                    for I in range(6):
                        total = 0.0
                        for J in range(6):
                            total += Dt[I, J] * d_eps[J]
                        a, b = _P[I], _Q[I]
                        d_tau[a, b] = d_tau[b, a] = total / _W[I]
                    for i in range(3):                               # (Q d_tau)
                        for b in range(3):
                            total = 0.0
                            for c in range(3):
                                total += Qe[i, c] * d_tau[c, b]
                            QT[i, b] = total
                    for i in range(3):                               # X = Q d_tau Gᵀ, minus P_iL F⁻¹_Jk
                        for J in range(3):
                            total = 0.0
                            for b in range(3):
                                total += QT[i, b] * G[J, b]
                            A[e, 3 * i + J, 3 * k + L] = total - P[e, 3 * i + L] * Fi[J, k]
    return A
