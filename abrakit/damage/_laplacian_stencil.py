"""Members of the Taylor stencils of :mod:`abrakit.damage.laplacian` (Ch. 6.4.1): the element rings through shared
vertices, the choice of the extra members that close the square system (the seed's diagonal rule, Fig. 6.5, or
row-pivoted QR) and the column equilibration that gives each system its condition number."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def _padded_rows(matrix: sp.csr_matrix) -> np.ndarray:
    """Column indices of each CSR row as a padded (nrows, max_per_row) array, -1 where a row is shorter."""
    matrix = matrix.tocsr()
    counts = np.diff(matrix.indptr)
    out = np.full((matrix.shape[0], max(int(counts.max(initial=0)), 1)), -1, dtype=np.int64)
    rows = np.repeat(np.arange(matrix.shape[0]), counts)
    out[rows, np.arange(matrix.nnz) - matrix.indptr[rows]] = matrix.indices
    return out


def _vertex_adjacency(mesh) -> sp.csr_matrix:
    """Element-to-element adjacency through shared vertices, without the diagonal."""
    nel = mesh.t.shape[1]
    incidence = sp.csr_matrix(
        (np.ones(mesh.t.size), (mesh.t.ravel(), np.tile(np.arange(nel), mesh.t.shape[0]))),
        shape=(mesh.p.shape[1], nel),
    )
    adjacency = (incidence.T @ incidence).tocsr()
    adjacency.setdiag(0)
    adjacency.eliminate_zeros()
    adjacency.data[:] = 1.0
    return adjacency


def _equilibrated(rows, weights=None):
    """Scale the columns of stacked Taylor matrices (..., k, n) to unit norm; return (scaled, scale, condition)."""
    if weights is not None:
        rows = rows * np.sqrt(weights)[..., None]
    norms = np.linalg.norm(rows, axis=-2)
    scale = np.where(norms > 0.0, 1.0 / np.where(norms > 0.0, norms, 1.0), 0.0)
    scaled = rows * scale[..., None, :]
    singular = np.linalg.svd(scaled, compute_uv=False)
    with np.errstate(divide="ignore", invalid="ignore"):
        condition = np.where(singular[..., -1] > 0.0, singular[..., 0] / singular[..., -1], np.inf)
    condition = np.where(np.all(norms > 0.0, axis=-1) & (rows.shape[-2] >= rows.shape[-1]), condition, np.inf)
    return scaled, scale, condition


def _select_diagonal(dx_cand, valid, n_extra):
    """Seed rule (Fig. 6.5): per coordinate plane (k, p) the closest candidate in diagonal direction.

    Score |dx_k dx_p| / |dx|**3: largest for a 45-degree direction in that plane and for close elements.
    """
    chosen = np.full((dx_cand.shape[0], n_extra), -1, dtype=np.int64)
    available = valid.copy()
    dim = dx_cand.shape[-1]
    planes = [(k, p) for k in range(dim) for p in range(k + 1, dim)]
    rho = np.linalg.norm(dx_cand, axis=-1)
    rows = np.arange(dx_cand.shape[0])
    for slot, (k, p) in enumerate(planes):
        with np.errstate(divide="ignore", invalid="ignore"):
            score = np.abs(dx_cand[..., k] * dx_cand[..., p]) / rho**3
        score = np.where(available, score, -np.inf)
        best = np.argmax(score, axis=1)
        ok = np.isfinite(score[rows, best]) & (score[rows, best] > 0.0)
        chosen[:, slot] = np.where(ok, best, -1)
        available[rows[ok], best[ok]] = False
    return chosen


def _select_greedy(base_rows, cand_rows, cand_dx, valid, n_extra):
    """Add, one at a time, the candidate whose Taylor row has the largest part outside the rows chosen so far.

    This is row-pivoted QR on the candidate rows: the relative residual |(I - P) r| / |r| after projecting a row r
    on the span of the current rows measures how much new information it brings; dividing by the (dimensionless)
    distance prefers close members, whose truncation error is smaller.
    """
    nel = cand_rows.shape[0]
    chosen = np.full((nel, n_extra), -1, dtype=np.int64)
    available = valid.copy()
    cand_norm = np.maximum(np.linalg.norm(cand_rows, axis=-1), 1e-300)
    distance = np.maximum(np.linalg.norm(cand_dx, axis=-1), 1e-300)
    rows_now = base_rows
    elements = np.arange(nel)
    for slot in range(n_extra):
        basis = np.linalg.qr(np.swapaxes(rows_now, 1, 2))[0]            # (nel, n, k): span of the current rows
        residual = cand_rows - np.einsum("ecn,enk,emk->ecm", cand_rows, basis, basis)
        score = np.where(available, np.linalg.norm(residual, axis=-1) / cand_norm / distance, -np.inf)
        best = np.argmax(score, axis=1)
        ok = score[elements, best] > 1e-8
        chosen[:, slot] = np.where(ok, best, -1)
        available[elements[ok], best[ok]] = False
        picked = np.where(ok[:, None], cand_rows[elements, best], 0.0)
        rows_now = np.concatenate([rows_now, picked[:, None, :]], axis=1)
    return chosen
