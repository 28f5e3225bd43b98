"""Compiled kernels of :class:`~abrakit.fem.kinematics.FBarKinematics` (numba; private).

The same F-bar state and exact element tangent as the NumPy methods (the class docstring has the formulas), one
element at a time, using the structure of the gradient operator, G[(iJ), (a k)] = δ_ik ∂N_a/∂X_J, instead of
forming G and B̄ (9 × 24 per point) and multiplying them densely:

* B̄ᵀ A B̄ = α² [GᵀAG + ⅓ (GᵀA f) ⊗ h + ⅓ h ⊗ (Gᵀ Aᵀ f) + (f·A f)/9 h ⊗ h], with GᵀAG from 3 × 3 blocks;
* Gᵀ D G, D the derivative of vec F⁻ᵀ, is −g_a,k g_b,i with g = Gᵀ vec F⁻ᵀ (``Gtg``), a permuted outer product;
* the rank-one terms of one point are gathered into two outer products.

Checked against the NumPy methods to round-off (``tests/test_finite_strain.py``).
"""

from __future__ import annotations

import numpy as np

from ..compiled import inverse3, njit, prange

BLOCK = 32
"""Elements per block of the parallel loop (scratch arrays are allocated once per block)."""


@njit(cache=True, parallel=True)
def fbar_state(grad_N, dx, u_e, F, F_inv, J, J_bar, alpha, m, h, Gtg):  # pragma: no cover - compiled
    """F = I + ∇u, J, F⁻¹, J̄, α = (J̄/J)^⅓, m, h = m − g and g = Gᵀ vec F⁻ᵀ of every element (outputs as in
    :class:`~abrakit.fem.kinematics.FBarState`) from the element displacements ``u_e`` (nel, 3 nnode).
    Returns the smallest det F (≤ 0: an inverted element; its outputs are not used)."""
    nel, nqp, nnode, dim = grad_N.shape
    n_blocks = (nel + BLOCK - 1) // BLOCK
    smallest = np.empty(n_blocks)
    for blk in prange(n_blocks):
        low = np.inf
        for e in range(blk * BLOCK, min(nel, (blk + 1) * BLOCK)):
            volume = 0.0
            deformed = 0.0
            for q in range(nqp):
                Fq, Fi = F[e, q], F_inv[e, q]
                for i in range(3):
                    for L in range(3):
                        total = 1.0 if i == L else 0.0
                        for a in range(nnode):
                            total += u_e[e, 3 * a + i] * grad_N[e, q, a, L]
                        Fq[i, L] = total
                det = inverse3(Fq, Fi)
                J[e, q] = det
                low = min(low, det)
                for a in range(nnode):                 # g_(a i) = Σ_J F⁻¹_Ji ∂N_a/∂X_J
                    for i in range(3):
                        total = 0.0
                        for L in range(3):
                            total += Fi[L, i] * grad_N[e, q, a, L]
                        Gtg[e, q, 3 * a + i] = total
                volume += dx[e, q]
                deformed += det * dx[e, q]
            J_bar[e] = deformed / volume
            for b in range(3 * nnode):
                total = 0.0
                for q in range(nqp):
                    total += J[e, q] * dx[e, q] * Gtg[e, q, b]
                m[e, b] = total / deformed
            for q in range(nqp):
                alpha[e, q] = np.cbrt(J_bar[e] / J[e, q]) if J[e, q] > 0.0 else 0.0
                for b in range(3 * nnode):
                    h[e, q, b] = m[e, b] - Gtg[e, q, b]
        smallest[blk] = low
    return smallest.min() if n_blocks else np.inf


@njit(cache=True, parallel=True)
def element_tangents(grad_N, dx, F, J, J_bar, alpha, m, h, Gtg, A, P):  # pragma: no cover - compiled
    """The exact F-bar element tangents (nel, nbf, nbf) of
    :meth:`~abrakit.fem.kinematics.FBarKinematics.element_tangents` (module docstring for the factoring)."""
    nel, nqp, nnode, dim = grad_N.shape
    nbf = 3 * nnode
    K = np.zeros((nel, nbf, nbf))
    n_blocks = (nel + BLOCK - 1) // BLOCK
    for blk in prange(n_blocks):
        GA = np.empty((nbf, 9))
        GAf = np.empty(nbf)
        GAtf = np.empty(nbf)
        Gtp = np.empty(nbf)
        left = np.empty(nbf)
        right = np.empty(nbf)
        fA = np.empty(9)
        for e in range(blk * BLOCK, min(nel, (blk + 1) * BLOCK)):
            Ke = K[e]
            volume = 0.0
            for q in range(nqp):
                volume += dx[e, q]
            c = 0.0                                     # c_e = Σ_q α s dV_0 / 3, s = F : P
            for q in range(nqp):
                s = 0.0
                for I in range(9):
                    s += F[e, q, I // 3, I % 3] * P[e, q, I]
                c += dx[e, q] * alpha[e, q] * s / 3.0
            for q in range(nqp):
                N = grad_N[e, q]
                Aq, Pq, Fq = A[e, q], P[e, q], F[e, q]
                al, w0 = alpha[e, q], dx[e, q]
                w = w0 * al / 3.0
                s = 0.0
                fAf = 0.0
                for I in range(9):
                    s += Fq[I // 3, I % 3] * Pq[I]
                for K9 in range(9):                     # fA = Aᵀ f
                    total = 0.0
                    for I in range(9):
                        total += Fq[I // 3, I % 3] * Aq[I, K9]
                    fA[K9] = total
                    fAf += total * Fq[K9 // 3, K9 % 3]
                for a in range(nnode):
                    for i in range(3):
                        r = 3 * a + i
                        for K9 in range(9):             # (Gᵀ A)_(ai),(kL) = Σ_J ∂N_a/∂X_J A[iJ, kL]
                            GA[r, K9] = (N[a, 0] * Aq[3 * i, K9] + N[a, 1] * Aq[3 * i + 1, K9]
                                         + N[a, 2] * Aq[3 * i + 2, K9])
                        total = 0.0
                        for K9 in range(9):
                            total += GA[r, K9] * Fq[K9 // 3, K9 % 3]
                        GAf[r] = total
                        GAtf[r] = N[a, 0] * fA[3 * i] + N[a, 1] * fA[3 * i + 1] + N[a, 2] * fA[3 * i + 2]
                        Gtp[r] = N[a, 0] * Pq[3 * i] + N[a, 1] * Pq[3 * i + 1] + N[a, 2] * Pq[3 * i + 2]
                scale = al * al * w0
                for r in range(nbf):                    # α² dV_0 GᵀAG
                    for b in range(nnode):
                        for k in range(3):
                            Ke[r, 3 * b + k] += scale * (GA[r, 3 * k] * N[b, 0] + GA[r, 3 * k + 1] * N[b, 1]
                                                         + GA[r, 3 * k + 2] * N[b, 2])
                hq = h[e, q]
                gq = Gtg[e, q]
                for r in range(nbf):                    # left ⊗ h + h ⊗ right gathers the rank-one terms
                    left[r] = scale * (GAf[r] / 3.0 + fAf * hq[r] / 9.0) + w * (Gtp[r] + s * hq[r] / 3.0)
                    right[r] = scale * GAtf[r] / 3.0 + w * Gtp[r]
                ratio = J[e, q] * w0 / (volume * J_bar[e])
                coef_d = c * ratio - w * s              # (c r − w s) Gᵀ D G, (GᵀDG)_(ai),(bk) = −g_ak g_bi
                coef_g = c * ratio                      # c r g ⊗ g
                for a in range(nnode):
                    for i in range(3):
                        r = 3 * a + i
                        for b in range(nnode):
                            for k in range(3):
                                col = 3 * b + k
                                Ke[r, col] += (left[r] * hq[col] + hq[r] * right[col] + coef_g * gq[r] * gq[col]
                                               - coef_d * gq[3 * a + k] * gq[3 * b + i])
            for r in range(nbf):
                for col in range(nbf):
                    Ke[r, col] -= c * m[e, r] * m[e, col]
    return K


@njit(cache=True, parallel=True)
def element_forces(grad_N, dx, F, alpha, h, P):  # pragma: no cover - compiled
    """The F-bar element forces ∫ B̄ᵀ P dV_0 = Σ_q α dV_0 [Gᵀp + (s/3) h], s = F : P, ``(nel, nbf)``, of
    :meth:`~abrakit.fem.kinematics.FBarKinematics.element_forces` (P as 9-vectors, row-major iJ)."""
    nel, nqp, nnode, dim = grad_N.shape
    out = np.zeros((nel, 3 * nnode))
    for e in prange(nel):
        for q in range(nqp):
            w = dx[e, q] * alpha[e, q]
            Pq, Fq, N = P[e, q], F[e, q], grad_N[e, q]
            s = 0.0
            for I in range(9):
                s += Fq[I // 3, I % 3] * Pq[I]
            for a in range(nnode):
                for i in range(3):
                    r = 3 * a + i
                    t = Pq[3 * i] * N[a, 0] + Pq[3 * i + 1] * N[a, 1] + Pq[3 * i + 2] * N[a, 2]
                    out[e, r] += w * (t + s / 3.0 * h[e, q, r])
    return out
