"""Linear solvers for the Newton correction K_II du_I = -R_I, Eq. (4.39).

- :class:`DirectSolver`: sparse LU (SuperLU with a symmetric ordering), the default in 2D and for small 3D meshes.
- :class:`AMGSolver`: conjugate gradients preconditioned by smoothed-aggregation AMG (pyamg) with the rigid-body
  modes as near-null space; the AMG hierarchy is built once per load step and reused by the step's Newton
  iterations (the tangent changes little within a step), and rebuilt if CG stalls.

A linear solver is any object with ``solve(K, rhs, new_step: bool) -> x``; the Newton solver also accepts a plain
callable ``f(K, rhs) -> x``.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..validation import check_option

# 3D problems with more free DOFs than this use AMG under linear_solver="auto". Measured on a hex block (one
# elastic solve): SuperLU 0.4 s vs AMG-CG 0.9 s at 7.6k DOF, 11 s vs 6 s at 29k, 56 s vs 4.4 s at 71k DOF.
AUTO_AMG_MIN_DOFS = 15_000


class LinearSolveError(RuntimeError):
    """The Newton correction could not be computed (singular tangent or a stalled iterative solver)."""


class DirectSolver:
    """Sparse LU of K_II at every Newton iteration (SuperLU, ordering on the structure of K + K^T)."""

    name = "direct"

    def solve(self, K: sp.csr_matrix, rhs: np.ndarray, new_step: bool = True) -> np.ndarray:
        try:
            lu = spla.splu(sp.csc_matrix(K), permc_spec="MMD_AT_PLUS_A")
        except RuntimeError as exc:  # "Factor is exactly singular"
            raise LinearSolveError(f"sparse LU failed: {exc}") from exc
        x = lu.solve(rhs)
        if not np.all(np.isfinite(x)):
            raise LinearSolveError("sparse LU produced non-finite values (singular tangent)")
        return x


def rigid_body_modes(points: np.ndarray, component: np.ndarray) -> np.ndarray:
    """Near-null space of elasticity: translations and infinitesimal rotations at the DOF locations.

    ``points`` is ``(dim, n)`` (DOF coordinates), ``component`` ``(n,)`` the displacement component of each DOF.
    Returns ``(n, 3)`` in 2D and ``(n, 6)`` in 3D.
    """
    dim, n = points.shape
    modes = [(component == c).astype(float) for c in range(dim)]
    x = points - points.mean(axis=1, keepdims=True)
    pairs = [(0, 1)] if dim == 2 else [(0, 1), (1, 2), (2, 0)]
    for a, b in pairs:  # rotation in the (a, b) plane: u_a = -x_b, u_b = x_a
        modes.append(np.where(component == a, -x[b], 0.0) + np.where(component == b, x[a], 0.0))
    return np.stack(modes, axis=1)


class AMGSolver:
    """CG (GMRES for non-symmetric tangents) preconditioned by smoothed-aggregation AMG from pyamg.

    ``krylov="auto"`` checks the symmetry of the tangent when the hierarchy is built and picks CG or GMRES.
    """

    name = "amg"

    def __init__(self, near_null_space: np.ndarray | None = None, rtol: float = 1e-10, maxiter: int = 1000,
                 krylov: str = "auto"):
        self.near_null_space = near_null_space
        self.rtol = rtol
        self.maxiter = maxiter
        self.krylov = check_option("krylov", krylov, ("auto", "cg", "gmres"))
        self._method = None
        self._ml = None
        self.iterations: list[int] = []

    def _build(self, K):
        import pyamg

        method = self.krylov
        if method == "auto":
            asymmetry = abs(K - K.T).max() if K.nnz else 0.0
            method = "cg" if asymmetry <= 1e-10 * abs(K).max() else "gmres"
        self._method = spla.cg if method == "cg" else spla.gmres
        # "local" Jacobi weighting skips pyamg's spectral-radius estimate, which dominated the set-up time
        self._ml = pyamg.smoothed_aggregation_solver(
            sp.csr_matrix(K), B=self.near_null_space,
            symmetry="symmetric" if method == "cg" else "nonsymmetric", coarse_solver="splu",
            smooth=("jacobi", {"omega": 4.0 / 3.0, "weighting": "local"}),
        )

    def solve(self, K: sp.csr_matrix, rhs: np.ndarray, new_step: bool = True) -> np.ndarray:
        count = [0]

        def callback(_):
            count[0] += 1

        for attempt in range(2):
            if self._ml is None or new_step or attempt == 1:
                self._build(K)
            count[0] = 0
            M = self._ml.aspreconditioner(cycle="V")
            extra = {"callback_type": "pr_norm", "restart": 50} if self._method is spla.gmres else {}
            x, info = self._method(K, rhs, rtol=self.rtol, atol=0.0, maxiter=self.maxiter, M=M,
                                   callback=callback, **extra)
            self.iterations.append(count[0])
            if info == 0 and np.all(np.isfinite(x)):
                return x
        raise LinearSolveError(f"AMG-preconditioned {self._method.__name__} did not converge in {self.maxiter} "
                               "iterations")


def make_linear_solver(kind, dim: int, n_free: int, near_null_space=None):
    """Linear solver for ``kind`` in ("auto", "direct", "amg") or a user object/callable (returned as is).

    ``auto``: direct LU in 2D and for 3D problems up to ``AUTO_AMG_MIN_DOFS`` free DOFs, AMG-CG above.
    """
    if not isinstance(kind, str):
        return kind
    check_option("linear_solver", kind, ("auto", "direct", "amg"))
    if kind == "auto":
        kind = "amg" if dim == 3 and n_free > AUTO_AMG_MIN_DOFS else "direct"
    return DirectSolver() if kind == "direct" else AMGSolver(near_null_space)
