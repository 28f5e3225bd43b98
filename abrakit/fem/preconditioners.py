"""Orderings and preconditioners for the Newton corrections of large 3D tensor-grid meshes, Eq. (4.39).

- :func:`nested_dissection`: a fill-reducing order of the DOFs of a tensor-product mesh for a sparse LU
  (:class:`~abrakit.fem.DirectSolver` ``order=``), from the grid indices of the DOF positions alone;
- :class:`ReusedPreconditioner`: GMRES on the current tangent K, preconditioned by a smoothed-aggregation AMG
  hierarchy built on the symmetric part of an earlier K and kept across Newton iterations and load steps.

Both serve a linear solver of the form ``solve(K, rhs, new_step) -> x`` (:mod:`abrakit.fem.linsolve`).

Example::

    order = nested_dissection(basis.doflocs[:, free])          # (dim, n) DOF positions
    solver = DirectSolver("superlu", order=order)
"""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .linsolve import LinearSolveError


def nested_dissection(points: np.ndarray, leaf: int = 192) -> np.ndarray:
    """Fill-reducing order of the DOFs at ``points`` (dim, n) of a tensor-product mesh: geometric nested dissection.

    The DOF set is split recursively at the middle grid plane of its longest index extent; both halves are
    ordered first (recursively), the plane (the separator) last; sets of at most ``leaf`` DOFs (or one plane
    thick) keep their order. Returns a permutation of ``range(n)``.
    """
    index = np.stack([np.unique(np.round(c, 12), return_inverse=True)[1] for c in points], axis=1)
    order: list[np.ndarray] = []

    def dissect(items, depth=0):
        if items.size <= leaf or depth > 60:
            order.append(items)
            return
        g = index[items]
        lo, extent = g.min(axis=0), np.ptp(g, axis=0)
        axis = int(np.argmax(extent))
        if extent[axis] < 2:
            order.append(items)
            return
        mid = lo[axis] + extent[axis] // 2
        dissect(items[g[:, axis] < mid], depth + 1)
        dissect(items[g[:, axis] > mid], depth + 1)
        order.append(items[g[:, axis] == mid])

    dissect(np.arange(index.shape[0]))
    return np.concatenate(order)


class ReusedPreconditioner:
    """GMRES on the current tangent K, preconditioned by a smoothed-aggregation AMG hierarchy (pyamg, on the
    symmetric part (K + Kᵀ)/2 of an *earlier* K, the rigid-body modes ``near_null_space`` as near-null space).

    The hierarchy is kept across Newton iterations and load steps (a scratch's tangent changes only near the tip)
    and rebuilt when GMRES needs more than ``rebuild_after`` iterations, or fails. GMRES (restart 50, at most
    ``maxiter`` iterations) always sees K itself (the contact tangent is non-symmetric in slip) and stops at
    ‖b − K x‖ ≤ ``rtol`` ‖b‖. Counters: ``builds``, ``build_time`` (s), ``iterations`` (one entry per solve).
    """

    name = "gmres+reused-amg"

    def __init__(self, *, near_null_space=None, rtol: float = 1e-9, rebuild_after: int = 12, maxiter: int = 300):
        self.near_null_space = near_null_space
        self.rtol = rtol
        self.rebuild_after = rebuild_after
        self.maxiter = maxiter
        self._M = None
        self.builds = 0
        self.build_time = 0.0
        self.iterations: list[int] = []

    def _build(self, K):
        import pyamg

        t0 = time.perf_counter()
        sym = sp.csr_matrix(0.5 * (K + K.T))
        ml = pyamg.smoothed_aggregation_solver(sym, B=self.near_null_space, symmetry="symmetric", max_coarse=500)
        self._M = ml.aspreconditioner(cycle="V")
        self.builds += 1
        self.build_time += time.perf_counter() - t0

    def solve(self, K: sp.csr_matrix, rhs: np.ndarray, new_step: bool = True) -> np.ndarray:
        for attempt in range(2):
            fresh = self._M is None or attempt == 1
            if fresh:
                self._build(K)
            count = [0]

            def callback(_, count=count):
                count[0] += 1

            x, info = spla.gmres(K, rhs, rtol=self.rtol, atol=0.0, restart=50, maxiter=self.maxiter // 50 + 1,
                                 M=self._M, callback=callback, callback_type="pr_norm")
            self.iterations.append(count[0])
            if info == 0 and np.all(np.isfinite(x)):
                if count[0] > self.rebuild_after:
                    self._M = None                                     # rebuild before the next solve
                return x
            if fresh and attempt == 1:
                break
        raise LinearSolveError("GMRES with a fresh AMG preconditioner did not converge")
