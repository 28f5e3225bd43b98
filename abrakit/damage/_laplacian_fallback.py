r"""Fallback of :mod:`abrakit.damage.laplacian` for elements whose square Taylor system is singular or
ill-conditioned (Ch. 6.4.1).

Members: the element's 2-ring of vertex neighbours, boundary elements also the ghost centres (Eq. 6.44) of that
2-ring. Derivatives: the weighted least-squares Taylor fit over them, weights :math:`\min(1, \rho_n/\rho_j)^{2q}`.
Laplacian rows: nonnegative weights :math:`c_j` on :math:`f_j - f_i` meeting the moment conditions that make the
row exact for every quadratic, found as a nonnegative least-squares problem (Lawson-Hanson); the module docstring
of :mod:`abrakit.damage.laplacian` gives the equations. Increments are dimensionless (divided by the element's mean
face distance); the Taylor rows (6.70) of the members are passed in, computed by the caller.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.optimize import nnls

from abrakit.damage._laplacian_stencil import _equilibrated, _padded_rows

#: Exponents q of the fallback weights min(1, rho_n / rho)**(2 q), tried from steep (local) to flat (robust).
FALLBACK_WEIGHT_POWERS = (3, 1, 0)

#: Nonnegative fallback rows: a member at dimensionless distance rho costs (rho**q c)**2 (close ones preferred).
NONNEGATIVE_PENALTY_POWER = 3

#: Weight of the moment conditions over the penalty (weighting method for equality constraints, Lawson & Hanson,
#: ch. 22): the conditions are met to about (1 / weight)**2, i.e. to roundoff.
NONNEGATIVE_CONSTRAINT_WEIGHT = 1e8

#: A nonnegative fallback row is exact for quadratics when every dimensionless moment condition holds to this.
NONNEGATIVE_TOLERANCE = 1e-8


def _fallback_members(ghost_owner, ghost_points, centres, length, adjacency, targets):
    """Members of the fallback of the elements ``targets``: their 2-ring, boundary elements also the ghost centres of
    every element in their 2-ring.

    Returns ``(sources, dx_hat, near)``, each (m, k): the element whose value a member carries (-1: no member), the
    dimensionless increments (m, k, dim) and whether the member belongs to the 1-ring (a ghost: if its owner does).
    ``ghost_owner`` (nb,) and ``ghost_points`` (nb, dim) are the ghost centres of the mesh (``ghost_centres``).
    """
    nel = len(centres)
    ring = adjacency + sp.identity(nel, format="csr")
    one_ring = ring[targets]
    two_ring = (one_ring @ ring).tocsr()
    n_ghosts = ghost_owner.size
    ghost_of = sp.csr_matrix((np.ones(n_ghosts), (ghost_owner, np.arange(n_ghosts))), shape=(nel, n_ghosts))
    # An interior element's fit stays free of the boundary condition, so it remains exact for every quadratic.
    on_boundary = np.asarray(ghost_of[targets].sum(axis=1)).ravel() > 0
    ghosts = (sp.diags(on_boundary.astype(float)) @ two_ring @ ghost_of).tocsr()
    ghosts.eliminate_zeros()

    members = _padded_rows(two_ring)
    members = np.where(members == targets[:, None], -1, members)       # f_i - f_i carries no information
    ghost_ids = _padded_rows(ghosts)
    points = np.concatenate([centres[np.maximum(members, 0)], ghost_points[np.maximum(ghost_ids, 0)]], axis=1)
    sources = np.concatenate([members, np.where(ghost_ids >= 0, ghost_owner[np.maximum(ghost_ids, 0)], -1)], axis=1)
    dx_hat = (points - centres[targets, None, :]) / length[targets, None, None]
    present = (sources >= 0) & (np.sum(dx_hat**2, axis=-1) > 0.0)
    sources = np.where(present, sources, -1)
    near = np.any(sources[:, :, None] == _padded_rows(one_ring)[:, None, :], axis=2) & present
    return sources, dx_hat, near


def _least_squares_fit(targets, sources, dx_hat, rows, max_condition, square_condition):
    """Weighted least-squares Taylor fit over the members of ``_fallback_members`` for the elements ``targets``.

    Weights min(1, rho_n / rho_j)**(2 q), rho_n the distance of the n-th nearest member, with the first q of
    ``FALLBACK_WEIGHT_POWERS`` that gives a well-conditioned system; ``rows`` (m, k, n) are the Taylor rows (6.70)
    of ``dx_hat``.
    Returns ``(weights, condition)`` with dimensionless weights (m, n, k) acting on Delta f.
    """
    present = sources >= 0
    rho2 = np.sum(dx_hat**2, axis=-1)
    # Weights min(1, rho_n / rho)**(2 q): the n nearest members (n = number of unknowns) count fully, farther ones
    # fade. A steep q keeps the fit local and nearly as accurate as the square stencil; where that is ill-conditioned
    # (slivers) the next, flatter q is used.
    rho = np.sqrt(np.where(present, rho2, np.inf))
    rho_n = np.sort(rho, axis=1)[:, min(rows.shape[-1], rho.shape[1]) - 1]
    closeness = np.where(present, np.minimum(1.0, (rho_n[:, None] / np.where(present, rho, 1.0)) ** 2), 0.0)
    best = np.full(len(targets), np.inf)
    weights = np.zeros((len(targets), rows.shape[-1], rows.shape[-2]))
    for power in FALLBACK_WEIGHT_POWERS:
        todo = ~(best <= max_condition)
        if not todo.any():
            break
        weight = closeness[todo] ** power
        scaled, scale, condition = _equilibrated(rows[todo], weight)
        # d_hat = S (W^1/2 D_hat S)^+ W^1/2 Delta f
        weights[todo] = scale[:, :, None] * np.linalg.pinv(scaled) * np.sqrt(weight)[:, None, :]
        best[todo] = condition
    bad = ~(best <= max_condition)
    if bad.any():
        raise ValueError(
            f"mesh: the Taylor stencil of elements {targets[bad][:8].tolist()} is singular or ill-conditioned "
            f"(condition {square_condition[targets[bad]][:3]} for the square system, {best[bad][:3]} for the "
            f"least-squares fit over the 2-ring; max_condition={max_condition:g}); the mesh is too thin or "
            f"degenerate there to determine second derivatives"
        )
    return weights, best


def _nonnegative_rows(sources, dx_hat, rows, near):
    """Laplacian rows c >= 0 of the fallback elements: sum_j c_j (f_j - f_i), exact for quadratics where possible.

    Exactness for every quadratic means the moment conditions sum_j c_j D_j = (0, ..., 0, 1, ..., 1) on the Taylor
    rows D_j (6.70) (``rows``, (m, k, n)): sum_j c_j dx_j = 0, sum_j c_j dx_jk dx_jp = 0 (k < p),
    sum_j c_j dx_jk**2 = 2. Among the nonnegative solutions the one minimising sum_j (rho_j**q c_j)**2 (close members
    preferred, ties shared symmetrically) is found as a nonnegative least-squares problem, the conditions weighted by
    ``NONNEGATIVE_CONSTRAINT_WEIGHT`` over the penalty rows. The 1-ring is tried first, then the 2-ring; if neither
    admits a solution the 2-ring's best nonnegative fit is kept and the element marked inexact. The conditions are
    deliberately not normalised: in the dimensionless increments the fit then stays close to the moment tensor 2 I
    as a whole (error O(|Hessian|)) instead of meeting a condition with tiny increments (across a sliver) at the
    price of huge moments along it.
    Returns ``(weights (m, k), inexact (m,))`` with dimensionless weights acting on Delta f = f_j - f_i.
    """
    dim = dx_hat.shape[-1]
    moments = np.swapaxes(rows, 1, 2)                                  # (m, n, k)
    n = moments.shape[1]
    target = (np.arange(n) >= n - dim).astype(float)                  # only the unmixed second moments are 1
    penalty = np.linalg.norm(dx_hat, axis=-1) ** NONNEGATIVE_PENALTY_POWER
    big = NONNEGATIVE_CONSTRAINT_WEIGHT
    weights = np.zeros(sources.shape)
    inexact = np.zeros(len(sources), dtype=bool)
    for e in range(len(sources)):
        for members in (near[e], sources[e] >= 0):
            conditions = moments[e][:, members]
            system = np.vstack([big * conditions, np.diag(penalty[e, members])])
            rhs = np.concatenate([big * target, np.zeros(members.sum())])
            c = nnls(system, rhs, maxiter=20 * system.shape[1])[0]
            exact = np.abs(conditions @ c - target).max() <= NONNEGATIVE_TOLERANCE
            if exact:
                break
        weights[e, members] = c
        inexact[e] = not exact
    return weights, inexact


def _with_rows(matrix, owner, sources, weights) -> sp.csr_matrix:
    """``matrix`` with the rows ``owner`` replaced by sum_j weights_j (f_{sources_j} - f_owner), sources >= 0.

    Members carrying the owner's own value (its ghosts) add nothing; the other rows keep their entries bit for bit.
    """
    matrix = matrix.tocoo()
    keep = ~np.isin(matrix.row, owner)
    own = np.broadcast_to(owner[:, None], sources.shape)
    used = (sources >= 0) & (sources != own) & (weights != 0.0)
    rows = np.concatenate([matrix.row[keep], own[used], own[used]])
    cols = np.concatenate([matrix.col[keep], sources[used], own[used]])
    vals = np.concatenate([matrix.data[keep], weights[used], -weights[used]])
    return sp.csr_matrix((vals, (rows, cols)), shape=matrix.shape)

