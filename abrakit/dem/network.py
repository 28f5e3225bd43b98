"""The exact static linear response of a contact network: the reference the dynamic elastic probe is checked against.

A packing in static equilibrium, strained by a small homogeneous ε, responds through its contact springs alone:
the particles move by u (fluctuations about the affine field) and rotate by θ until every particle is balanced
again. The relative displacement of B's contact point with respect to A's, for contact c with unit normal n from
A to B, branch vector l and arms a_A, a_B (centre to contact point, Eq. 4.4), is

    δ_c = u_B − u_A + ε l − (a_A θ_A + a_B θ_B) × n,

and the springs store W = ½ Σ_c δ_cᵀ K_c δ_c with K_c = k_n n⊗n + k_t (I − n⊗n) (Eq. 4.6, 4.7: the normal
tangent stiffness dF^n/dU and the shear stiffness K^t of the law at the present state). With q = (u, θ) of all
particles and e the Voigt strain (engineering shears), W = ½ qᵀ H q + qᵀ B e + ½ eᵀ A e; minimising over q gives
the stiffness of the cell

    C = (A − Bᵀ H⁻¹ B) / V,

A/V being the affine (Voigt) upper bound, Σ_c [k_n l² n⊗n⊗n⊗n + k_t l² (sym(n⊗I⊗n) − n⊗n⊗n⊗n)] / V for a
branch along the normal. Pre-stress terms (the contact forces already present turning with the branch vectors,
of the order of the pressure over the stiffness, 10⁻³ here) are left out. Contacts at the Coulomb limit
(|F^t| ≥ μ F^n within 10⁻⁹) keep their normal spring only: a small strain makes half of them slide.

H is singular: the cell's rigid translations (removed by holding one particle), rattlers and the free spins of
frictionless or single-contact particles (their rows are dropped where empty; a relative 10⁻¹² of the diagonal
regularises the rest; C moves by about twice that). Where every particle's contacts balance the affine field
(B = 0 to round-off, a lattice, whose counter-rotating "gears" are exact mechanisms) C = A/V without a solve.
One sparse factorisation of H (:class:`~abrakit.fem.linsolve.DirectSolver`: PARDISO where it loads, else
SuperLU) serves the six strain directions.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from abrakit.dem.contact_laws import _dot
from abrakit.dem.periodic import VOIGT, ElasticConstants

SLIDING = 1.0 - 1e-9
"""|F^t| ≥ SLIDING · μ F^n: a contact at the Coulomb limit (its tangential spring does not resist a small strain)."""

REGULARISATION = 1e-12
"""Relative diagonal added to H so that the mechanisms of the network (zero-energy modes) have a solution."""


def _strain_map(l: np.ndarray) -> np.ndarray:
    """D (K, 3, 6): (ε l)_a = Σ_k D[a, k] e_k for Voigt strains e (engineering shears), branch vectors l (K, 3)."""
    D = np.zeros((len(l), 3, 6))
    for k, (a, b) in enumerate(VOIGT):
        if a == b:
            D[:, a, k] = l[:, a]
        else:                             # γ_ab = 2 ε_ab moves a by ½ γ l_b and b by ½ γ l_a
            D[:, a, k] = 0.5 * l[:, b]
            D[:, b, k] = 0.5 * l[:, a]
    return D


def contact_stiffness_terms(sim):
    """The touching contacts' springs: ``(i, j, n, l, arm_i, arm_j, K_c)`` with K_c (K, 3, 3) of the module doc.

    Raises ``ValueError`` without a force evaluation (take a step first)."""
    c, p = sim.contacts, sim.particles
    if not len(c) or c.force is None:
        raise ValueError("the network stiffness needs contacts with forces: run at least one step first")
    t = np.flatnonzero(c.touching)
    prm = {key: np.asarray(value)[t] for key, value in c.prm.items()}
    overlap, fn = c.overlap[t], c.fn[t]
    kn = np.broadcast_to(sim.law.normal_force(overlap, prm)[1], t.shape).astype(float)
    kn = np.where(c.bonded[t], prm.get("kn", kn), kn)
    kt = np.broadcast_to(sim.law.shear_stiffness(fn, prm), t.shape).astype(float)
    ft = c.ft[:, t]
    at_limit = ~c.bonded[t] & (np.sqrt(_dot(ft, ft)) >= SLIDING * prm["mu"] * fn) & (kt > 0)
    kt = np.where(at_limit, 0.0, kt)
    i, j = c.i[t], c.j[t]
    l = sim.branch(i, j)                                                   # (K, 3), present positions
    n = l / np.linalg.norm(l, axis=1)[:, None]                             # Eq. (4.1), with them
    nn = n[:, :, None] * n[:, None, :]
    K = kn[:, None, None] * nn + kt[:, None, None] * (np.eye(3) - nn)
    return i, j, n, l, p.radius[i] - 0.5 * overlap, p.radius[j] - 0.5 * overlap, K


def _affine(D, K) -> np.ndarray:
    """A = Σ_c D_cᵀ K_c D_c, the springs' energy of an affine Voigt strain (6, 6)."""
    return np.einsum("cak,cab,cbm->km", D, K, D)


def affine_network_stiffness(sim) -> np.ndarray:
    """A/V: the (6, 6) Voigt stiffness of the affine deformation (no fluctuations, no rotations) [Pa]."""
    _, _, _, l, _, _, K = contact_stiffness_terms(sim)
    return _affine(_strain_map(l), K) / _volume(sim)


def _volume(sim) -> float:
    if sim.periodic is None:
        raise ValueError("the network stiffness needs a periodic simulation (Simulation(..., periodic=Periodic(...)))")
    return sim.periodic.volume


def _skew(v: np.ndarray) -> np.ndarray:
    """[v]× (K, 3, 3): [v]× w = v × w."""
    S = np.zeros(v.shape[:-1] + (3, 3))
    S[..., 0, 1], S[..., 0, 2], S[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    return S - np.swapaxes(S, -1, -2)


def network_stiffness(sim) -> ElasticConstants:
    """C = (A − Bᵀ H⁻¹ B)/V of the packing in ``sim`` (periodic, static), and E, ν of its isotropic projection.

    The exact static linear response of the contact network (module doc): no dynamics, no relaxation tolerance,
    the reference for :func:`~abrakit.dem.periodic.elastic_probe`.
    """
    from abrakit.fem.linsolve import DirectSolver  # imported here: the DEM alone does not load the FEM

    volume = _volume(sim)
    i, j, n, l, arm_i, arm_j, K = contact_stiffness_terms(sim)
    m = len(i)
    # G (K, 3, 12): δ = G (u_i, θ_i, u_j, θ_j); −(a θ) × n = a [n]× θ
    G = np.zeros((m, 3, 12))
    eye = np.broadcast_to(np.eye(3), (m, 3, 3))
    skew = _skew(n)
    G[:, :, 0:3], G[:, :, 3:6] = -eye, arm_i[:, None, None] * skew
    G[:, :, 6:9], G[:, :, 9:12] = eye, arm_j[:, None, None] * skew
    D = _strain_map(l)
    KG = K @ G
    h_local = np.einsum("cap,caq->cpq", G, KG)                          # (K, 12, 12)
    b_local = np.einsum("cap,cak->cpk", KG, D)                          # (K, 12, 6)
    A = _affine(D, K)
    dofs = np.concatenate([6 * i[:, None] + np.arange(6), 6 * j[:, None] + np.arange(6)], axis=1)   # (K, 12)
    size = 6 * len(sim.particles)
    rows = np.repeat(dofs, 12, axis=1).ravel()
    cols = np.tile(dofs, (1, 12)).ravel()
    H = sp.coo_matrix((h_local.ravel(), (rows, cols)), shape=(size, size)).tocsc()
    B = np.zeros((size, 6))
    np.add.at(B, dofs.ravel(), b_local.reshape(-1, 6))
    diagonal = H.diagonal()
    counts = np.bincount(np.concatenate([i, j]), minlength=len(sim.particles))
    held = 6 * int(np.argmax(counts)) + np.arange(3)                   # removes the rigid translations
    free = np.flatnonzero(diagonal > 1e-14 * diagonal.max())
    free = np.setdiff1d(free, held)
    H = H[free][:, free]
    H = H + sp.diags(REGULARISATION * H.diagonal())
    B = B[free]
    if np.abs(B).max() <= 1e-9 * np.abs(b_local).max():      # balanced contacts: the affine field is in equilibrium
        return ElasticConstants.from_stiffness(A / volume)    # (a lattice; B is round-off and H may have gears)
    X = DirectSolver(check_tol=1e-10).solve(H.tocsr(), B)
    return ElasticConstants.from_stiffness((A - B.T @ X) / volume)
