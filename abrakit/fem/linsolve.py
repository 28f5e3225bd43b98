"""Linear solvers for the Newton correction K_II du_I = -R_I, Eq. (4.39).

- :class:`DirectSolver`: a sparse direct factorisation that keeps its symbolic analysis (ordering) across Newton
  iterations and load steps and refactorises numerically only; backed by MKL PARDISO (optional, pypardiso) or
  SuperLU, and by LAPACK's banded LU in a reverse Cuthill–McKee order where a cost model says it is faster (2D
  meshes of a few hundred to a few thousand unknowns, where a sparse solver's per-call overhead dominates). The
  default in 2D and for 3D meshes up to ``AUTO_AMG_MIN_DOFS`` free DOFs.
- :class:`AMGSolver`: conjugate gradients preconditioned by smoothed-aggregation AMG (pyamg) with the rigid-body
  modes as near-null space; the AMG hierarchy is built once per load step and reused by the step's Newton
  iterations (the tangent changes little within a step), and rebuilt if CG stalls.

A linear solver is any object with ``solve(K, rhs, new_step: bool) -> x``; the Newton solver also accepts a plain
callable ``f(K, rhs) -> x``.
"""

from __future__ import annotations

import functools
import os
import time
import warnings

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import ArrayLike
from scipy.linalg import lapack
from scipy.sparse.csgraph import reverse_cuthill_mckee

from ..validation import all_finite, check_option, check_positive, check_range, number_arguments

# 3D problems with more free DOFs than this use AMG under linear_solver="auto" (benchmarks/bench_linear_solvers.py,
# elastic hex block, factorisation + solve against AMG set-up + CG): with PARDISO 0.79 s vs 1.12 s at 28k DOFs and
# 7.9 s vs 5.1 s at 90k; with SuperLU alone 4.8 s vs 1.1 s at 28k.
AUTO_AMG_MIN_DOFS = 15_000
AUTO_AMG_MIN_DOFS_PARDISO = 60_000


class LinearSolveError(RuntimeError):
    """The Newton correction could not be computed (singular tangent or a stalled iterative solver)."""


class _SuperLUBackend:
    """SuperLU with the fill-reducing column order of the first factorisation (its "analysis") kept: later
    factorisations of the same pattern permute symmetrically and factor in the natural order, preferring
    diagonal pivots; a vanishing pivot falls back to a fresh ordering with partial pivoting."""

    name = "superlu"

    def __init__(self, order: np.ndarray | None = None):
        self.order = order
        self._lu = None
        self._p = None

    def analyse(self, K):
        self._p = self.order
        self._lu = None

    def factorise(self, K):
        K = sp.csc_matrix(K)
        if self._p is not None:
            p = self._p
            try:
                self._lu = (spla.splu(sp.csc_matrix(K[p][:, p]), permc_spec="NATURAL", diag_pivot_thresh=0.0,
                                      options={"SymmetricMode": True}), p)
                return
            except RuntimeError:
                pass                                           # a zero pivot in this order: order afresh
        try:
            lu = spla.splu(K, permc_spec="MMD_AT_PLUS_A")
        except RuntimeError as exc:  # "Factor is exactly singular"
            raise LinearSolveError(f"sparse LU failed: {exc}") from exc
        if self.order is None:
            self._p = np.argsort(lu.perm_c)   # perm_c[j] is the new position of column j; as an index array: inverse
        self._lu = (lu, None)

    def solve(self, rhs):
        lu, p = self._lu
        if p is None:
            return lu.solve(rhs)
        x = np.empty_like(rhs)
        x[p] = lu.solve(rhs[p])
        return x


class _DenseBackend:
    """LAPACK LU of the dense matrix (``scipy.linalg.lu_factor``): for the smallest systems, where a sparse
    solver's per-call overhead exceeds the O(n³) work (a Q9 plate of about 100 DOFs: 0.2 ms against 0.7 ms for
    PARDISO and 1.6 ms for SuperLU per factorisation and solve)."""

    name = "dense"

    def __init__(self):
        self._lu = None

    def analyse(self, K):
        self._lu = None

    def factorise(self, K):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error", sla.LinAlgWarning)
                self._lu = sla.lu_factor(K.toarray(), check_finite=False)
        except (sla.LinAlgWarning, ValueError, np.linalg.LinAlgError) as exc:
            raise LinearSolveError(f"dense LU failed: {exc}") from exc

    def solve(self, rhs):
        return sla.lu_solve(self._lu, rhs, check_finite=False)


class _BandedBackend:
    """LAPACK banded LU with partial pivoting (``dgbtrf``/``dgbtrs``) in a bandwidth-reducing DOF order: reverse
    Cuthill–McKee or the natural order, whichever is narrower, fixed by the analysis with the positions of the
    CSR entries in LAPACK's band storage. A 2D mesh of n unknowns has a band of about √n, so the factorisation
    costs O(n²) against O(n³) dense and without a sparse solver's per-call overhead: the fastest back-end from a
    hundred to a few thousand unknowns (``benchmarks/bench_linear_solvers.py``)."""

    name = "banded"

    def __init__(self):
        self._lu = None

    def analyse(self, K):
        n = K.shape[0]
        row = np.repeat(np.arange(n), np.diff(K.indptr))
        col = K.indices
        perm = (reverse_cuthill_mckee(sp.csr_matrix((np.ones(len(col)), col, K.indptr), shape=K.shape)) if n
                else np.zeros(0, np.int64))                            # no unknown: nothing to order
        inverse = np.empty(n, np.int64)
        inverse[perm] = np.arange(n)
        if len(col) and np.max(np.abs(inverse[row] - inverse[col])) >= np.max(np.abs(row - col)):
            perm = None                                                # the natural order is as narrow
        if perm is not None:
            row, col = inverse[row], inverse[col]
        self.lower = int(np.max(row - col, initial=0))
        self.upper = int(np.max(col - row, initial=0))
        self._shape = (2 * self.lower + self.upper + 1, n)             # dgbtrf's rows for the fill of pivoting
        self._slot = (self.lower + self.upper + row - col) * n + col   # entry k of K.data in the band array
        self._perm = perm
        self._lu = None

    @property
    def bandwidth(self) -> int:
        return max(self.lower, self.upper)

    def factorise(self, K):
        band = np.zeros(self._shape)
        band.ravel()[self._slot] = K.data
        lu, pivots, info = lapack.dgbtrf(band, self.lower, self.upper, overwrite_ab=True)
        if info != 0:
            raise LinearSolveError(f"banded LU failed (LAPACK dgbtrf info {info}: "
                                   f"{'a zero pivot' if info > 0 else 'an invalid argument'})")
        self._lu = (lu, pivots)

    def solve(self, rhs):
        lu, pivots = self._lu
        p = self._perm
        x, info = lapack.dgbtrs(lu, self.lower, self.upper, rhs if p is None else rhs[p], pivots)
        if p is None:
            return x
        out = np.empty_like(x)
        out[p] = x
        return out


class _PardisoBackend:
    """Intel MKL PARDISO through pypardiso (real unsymmetric, mtype 11): phase 11 (ordering and symbolic
    factorisation) once per pattern, phase 22 (numerical factorisation) per matrix, phase 33 per solve.

    ``single=True`` factorises and solves in single precision (``iparm(28) = 1``: the matrix, right-hand side and
    solution in float32). The factors then give a correction with a relative residual of about 10⁻⁶, which the
    :class:`DirectSolver`'s iterative refinement in double precision (x += K⁻¹(b − K x), the residual computed with
    the double matrix) brings to its ``check_tol`` in one or two solves. Half the bytes move through the
    factorisation; in 2D the factors are too small for that to outweigh the refinement's extra solve, so only the
    3D scratch asks for it (``benchmarks/bench_linear_solvers.py`` compares both on elastic blocks)."""

    name = "pardiso"
    IPARM = {1: 1, 2: 2, 8: 0, 10: 13, 11: 1, 13: 1, 28: 1}
    """The single-precision run's iparm (1-based, as MKL documents them): explicit values (iparm(1) = 1) equal to
    MKL's defaults for mtype 11 (METIS order, pivots perturbed by 10⁻¹³, scaling and matching), no refinement
    inside PARDISO (it would refine in single precision; the DirectSolver refines in double), single precision."""

    def __init__(self, single: bool = False):
        if not pardiso_available():
            raise ImportError("the PARDISO back-end needs pypardiso with MKL (pip install abrakit[fast])")
        import pypardiso

        self._solver = pypardiso.PyPardisoSolver(mtype=11)
        self.dtype = np.float32 if single else np.float64
        if single:
            self.name = "pardiso-single"
            for i, value in self.IPARM.items():
                self._solver.iparm[i - 1] = value
        self._K = None

    def _call(self, phase, K, b):
        self._solver.set_phase(phase)
        try:
            return self._solver._call_pardiso(K, b)
        except Exception as exc:  # PyPardisoError carries PARDISO's error code
            raise LinearSolveError(f"PARDISO phase {phase} failed: {exc}") from exc

    def _matrix(self, K):
        return K if K.dtype == self.dtype else sp.csr_matrix((K.data.astype(self.dtype), K.indices, K.indptr),
                                                             shape=K.shape)

    def analyse(self, K):
        self._solver._check_A(K)
        self._call(11, self._matrix(K), np.zeros((K.shape[0], 1), dtype=self.dtype))

    def factorise(self, K):
        self._K = self._matrix(K)
        self._call(22, self._K, np.zeros((K.shape[0], 1), dtype=self.dtype))

    def solve(self, rhs):
        x = self._call(33, self._K, np.asfortranarray(rhs, dtype=self.dtype))
        return x.reshape(rhs.shape).astype(float, copy=False)


BACKENDS = ("auto", "pardiso", "superlu", "dense", "banded")
SPARSE_SECONDS = {"pardiso": (8e-5, 1.25e-6), "superlu": (1e-4, 2.2e-6)}
"""Cost models a + b n of one sparse factorisation and solve (the whole ``DirectSolver.solve`` call, CPU seconds,
one thread) for n unknowns of a 2D elasticity tangent, fitted to ``benchmarks/bench_linear_solvers.py`` and to
plate-with-hole tangents: PARDISO 0.19 ms at 120 unknowns, 0.47 ms at 440, 2.0 ms at 1680; SuperLU 0.30, 0.84 and
3.3 ms. 3D tangents cost more per unknown, so the model errs towards the sparse solver there."""

BANDED_SECONDS = (4e-5, 2.2e-10)
"""The banded LU's cost model, a + b n w² seconds for n unknowns of (half-)bandwidth w, from the same runs: 0.07 ms
at n = 120, w = 23; 0.34 ms at n = 440, w = 43; 2.6 ms at n = 1680, w = 83; 26 ms at n = 6560, w = 163."""


@number_arguments
def banded_wins(n: int, bandwidth: int, sparse: str) -> bool:
    """Whether the banded LU is expected to beat the sparse back-end ``sparse`` on n unknowns of this bandwidth
    (the cost models :data:`BANDED_SECONDS` and :data:`SPARSE_SECONDS`)."""
    (a, b), (c, d) = BANDED_SECONDS, SPARSE_SECONDS[sparse]
    return a + b * n * bandwidth**2 <= c + d * n


def _name_mkl_library() -> None:
    """Set ``PYPARDISO_MKL_RT`` (unless the user has) to the MKL runtime library that pip installs into the
    environment's ``lib`` directory, found without a recursive search.

    Without that variable pypardiso looks for ``mkl_rt`` with ``ctypes.util.find_library`` (subprocesses) and then
    a recursive glob over the whole environment, once when it is imported (its module-level solver) and again at
    every solver construction (seconds per process in a pip-installed venv). With no such file the variable stays
    unset and pypardiso searches itself."""
    if os.environ.get("PYPARDISO_MKL_RT"):
        return
    import glob
    import site
    import sys

    for prefix in dict.fromkeys((sys.prefix, sys.base_prefix, site.USER_BASE or "")):
        found = sorted(glob.glob(os.path.join(prefix, "lib", "libmkl_rt.so*")) +
                       glob.glob(os.path.join(prefix, "Library", "bin", "mkl_rt*.dll")), key=len)
        if found:
            os.environ["PYPARDISO_MKL_RT"] = found[0]
            return


_name_mkl_library()          # before anything imports pypardiso, whose import already searches


@functools.cache
def pardiso_available() -> bool:
    """Whether the optional PARDISO back-end (pypardiso with MKL, extra ``fast``) can be loaded (probed once: the
    probe loads the MKL library).

    pypardiso looks for ``mkl_rt`` with a recursive glob over the environment at *every* solver construction
    unless ``PYPARDISO_MKL_RT`` names
    the library: :func:`_name_mkl_library` names it when this module is imported, and the probe sets it to the
    library pypardiso found otherwise, so later constructions load it directly."""
    try:
        import pypardiso

        solver = pypardiso.PyPardisoSolver()
    except (ImportError, OSError):
        return False
    path = getattr(solver.libmkl, "_name", None)
    if path and os.path.isfile(path):
        os.environ.setdefault("PYPARDISO_MKL_RT", path)
    return True


class DirectSolver:
    """Sparse direct solve of K_II du = −R_I that keeps the symbolic analysis while the sparsity pattern stays.

    Newton iterations and load steps of one problem share one CSR pattern (the assembler's), so the fill-reducing
    ordering and symbolic factorisation are computed once; every correction only refactorises numerically. A
    changed pattern (compared by its index arrays) triggers a new analysis. Every solution is checked by its
    relative residual ||K x − b|| / ||b||; above ``check_tol`` up to ``refinements`` steps of iterative
    refinement follow (x += K⁻¹(b − K x) with the same factors: the pivots that PARDISO perturbs, or that an order
    kept from a positive definite tangent makes small, in an indefinite softening tangent), and if that does not
    help the matrix is analysed afresh and solved again (PARDISO's matching and pivot perturbation are computed
    at analysis time).

    backend : ``"pardiso"`` (MKL PARDISO via the optional pypardiso), ``"superlu"`` (scipy, always there),
        ``"dense"`` (LAPACK LU), ``"banded"`` (LAPACK banded LU in a bandwidth-reducing order), or ``"auto"``
        (chosen at the first solve: banded where its cost model beats the sparse solver, :func:`banded_wins`;
        else PARDISO if it loads, else SuperLU). ``order``: a fill-reducing DOF order for SuperLU (e.g.
        the scratch's geometric nested dissection); PARDISO orders by METIS itself.
    precision : ``"double"`` or ``"single"``: PARDISO's factors in single precision, refined to ``check_tol`` in
        double (see ``_PardisoBackend``); the answer is that of the double factors, the factorisation faster. A
        tangent whose single factors do not refine to ``check_tol`` (too ill-conditioned for float32) is solved
        again with double factors, and the solver stays with them (``precision_fallbacks`` counts it). Only
        the PARDISO back-end has it.
    forcing : 0 (the default: every call factorises and solves to ``check_tol``) or the forcing term η of an
        inexact Newton method (Eisenstat and Walker, 1996), 0 < η < 1: a call within a load step
        (``new_step=False``) first solves K x = b by GMRES preconditioned with the factors *kept* from an earlier
        matrix (:func:`kept_factor_gmres`, at most ``krylov_iterations`` iterations) and returns the first x with
        ‖b − K x‖ ≤ η ‖b‖; only if that fails is K factorised. Newton then converges with corrections of relative
        error η instead of exact ones: to the same solution, in about as many iterations where η is well below the
        iteration's own contraction (the scratch's :data:`abrakit.scratch.run.SCENE_FORCING`;
        ``benchmarks/bench_kept_factors.py`` measures it).
        Counters ``krylov_solves`` (corrections taken from it), ``krylov_fallbacks`` (factorised after all) and
        ``gmres_iterations`` (each one solve with the kept factors and one product with K).

    Counters: ``analyses``, ``factorisations``, ``solves`` and the seconds spent in each (``times``).
    """

    @number_arguments
    def __init__(self, backend: str = "auto", order: np.ndarray | None = None, check_tol: float = 1e-8,
                 refinements: int = 2, precision: str = "double", forcing: float = 0.0,
                 krylov_iterations: int = 8):
        check_option("backend", backend, BACKENDS)
        check_option("precision", precision, ("double", "single"))
        if precision == "single" and backend != "pardiso":
            raise ValueError(f"precision='single' needs backend='pardiso', got backend={backend!r}")
        check_positive("check_tol", check_tol)
        check_range("refinements", refinements, 0, None)
        self.forcing = check_range("forcing", forcing, 0.0, 1.0, high_open=True)
        self.krylov_iterations = int(check_range("krylov_iterations", krylov_iterations, 1, None))
        self.krylov_solves = self.krylov_fallbacks = self.gmres_iterations = 0
        self.refinements = int(refinements)
        self._order = order
        self.precision = precision
        self.precision_fallbacks = 0
        self.backend = None if backend == "auto" else self._make(backend)
        self.name = "direct-auto" if self.backend is None else f"direct-{self.backend.name}"
        self.check_tol = check_tol
        self._pattern = None
        self._K = None                                  # the matrix of the last factorisation (resolve's)
        self.analyses = self.factorisations = self.solves = 0
        self.times = {"analyse": 0.0, "factorise": 0.0, "solve": 0.0}

    def _make(self, backend: str):
        if backend == "dense":
            return _DenseBackend()
        if backend == "banded":
            return _BandedBackend()
        if backend == "pardiso":
            return _PardisoBackend(single=self.precision == "single")
        return _SuperLUBackend(self._order)

    def _choose(self, K) -> None:
        """``"auto"``: the banded LU where its cost model beats the sparse back-end's (:func:`banded_wins`: small
        and medium 2D meshes), else PARDISO if it loads, else SuperLU."""
        sparse = "pardiso" if pardiso_available() else "superlu"
        banded = _BandedBackend()
        self._timed("analyse", banded.analyse, K)             # its band decides
        if banded_wins(K.shape[0], banded.bandwidth, sparse):
            self.backend, self.name = banded, "direct-banded"
            self._analyse(K, analysed=True)                   # kept: the first solve does not analyse again
        else:
            self.backend, self.name = self._make(sparse), f"direct-{sparse}"

    def _timed(self, what, fn, *args):
        t0 = time.perf_counter()
        out = fn(*args)
        self.times[what] += time.perf_counter() - t0
        return out

    def _analyse(self, K, analysed: bool = False):
        """The back-end's symbolic analysis of K's pattern (``analysed``: it has done it already), kept with the
        pattern it belongs to."""
        if not analysed:
            self._timed("analyse", self.backend.analyse, K)
        self._pattern = (K.indptr.copy(), K.indices.copy())
        self.analyses += 1

    def solve(self, K: sp.csr_matrix, rhs: np.ndarray, new_step: bool = True) -> np.ndarray:
        """x with K x = rhs; ``rhs`` ``(n,)`` or ``(n, k)`` (k right-hand sides, one factorisation)."""
        if not sp.isspmatrix_csr(K):
            K = sp.csr_matrix(K)
        K.sort_indices()
        rhs = np.asarray(rhs, dtype=float)
        if self.backend is None:
            self._choose(K)
        if not rhs.any():               # x = 0, also for a tangent without stiffness (e.g. everything damaged)
            return np.zeros_like(rhs)
        same = (self._pattern is not None and np.array_equal(self._pattern[0], K.indptr)
                and np.array_equal(self._pattern[1], K.indices))
        if self.forcing and same and not new_step and rhs.ndim == 1 and self.factorisations:
            x = self._kept_factor_solve(K, rhs)
            if x is not None:
                return x
        for attempt in range(2):
            if attempt == 1 and self.precision == "single":
                self.precision = "double"                                          # factors too coarse for K
                self.backend = self._make("pardiso")
                self.name = f"direct-{self.backend.name}"
                self.precision_fallbacks += 1
            if not same or attempt == 1:
                self._analyse(K)
            self._timed("factorise", self.backend.factorise, K)
            self.factorisations += 1
            self._K = K
            x = self._refined(K, rhs)
            if x is not None:
                return x
        raise LinearSolveError(f"{self.name} produced an inaccurate or non-finite solution (singular tangent?)")

    def _kept_factor_solve(self, K, rhs: np.ndarray) -> np.ndarray | None:
        """The inexact solve of ``forcing`` (class docstring), None if GMRES does not reach it."""
        t0 = time.perf_counter()
        x, iterations = kept_factor_gmres(K, rhs, self.backend.solve, self.forcing, self.krylov_iterations)
        self.times["solve"] += time.perf_counter() - t0
        self.solves += iterations
        self.gmres_iterations += iterations
        if x is None:
            self.krylov_fallbacks += 1
        else:
            self.krylov_solves += 1
        return x

    def _refined(self, K, rhs: np.ndarray) -> np.ndarray | None:
        """The solution of K x = rhs with the current factors and up to ``refinements`` steps of iterative
        refinement to ``check_tol``; None if that is not reached (or x is not finite)."""
        x = self._timed("solve", self.backend.solve, rhs)
        self.solves += 1
        scale = _norm(rhs)
        for _ in range(self.refinements + 1):   # iterative refinement: perturbed pivots of indefinite tangents
            if not all_finite(x):
                return None
            error = rhs - K @ x
            if scale == 0.0 or _norm(error) <= self.check_tol * scale:
                return x
            x = x + self._timed("solve", self.backend.solve, error)
            self.solves += 1
        return None

    def resolve(self, rhs: np.ndarray) -> np.ndarray:
        """x with K_last x = rhs, K_last the matrix of the last factorisation (a chord step's solve: no
        assembly, no factorisation), refined like :meth:`solve`'s where the refinement converges. Raises
        :class:`LinearSolveError` if nothing has been factorised yet or the solution is not finite."""
        if self.factorisations == 0:
            raise LinearSolveError("resolve needs a factorisation: call solve first")
        rhs = np.asarray(rhs, dtype=float)
        x = self._refined(self._K, rhs)
        if x is None:                      # not refined to check_tol: the plain solve, as a chord step may take
            x = self._timed("solve", self.backend.solve, rhs)
            self.solves += 1
        if not all_finite(x):
            raise LinearSolveError(f"{self.name}: non-finite solution with the kept factors")
        return x


def kept_factor_gmres(K, b: np.ndarray, precondition, rtol: float, max_iterations: int
                      ) -> tuple[np.ndarray | None, int]:
    """x with ‖b − K x‖ ≤ rtol ‖b‖ by GMRES from x = 0, right-preconditioned by ``precondition`` (x ↦ M⁻¹ x, e.g.
    the solve of factors kept from an earlier K), in at most ``max_iterations`` iterations (one cycle, no restart).
    Returns (x, iterations), or (None, iterations) if the tolerance is not reached or x is not finite.

    Right preconditioning (K M⁻¹ y = b, x = M⁻¹ y) makes GMRES minimise the true residual ‖b − K x‖ over the
    Krylov space, so the tolerance is tested on K itself (Saad, Iterative Methods for Sparse Linear Systems, 2003,
    Alg. 9.5); the Hessenberg least-squares problem of at most ``max_iterations`` columns is solved afresh in each
    iteration (``numpy.linalg.lstsq``: a few microseconds at this size). The returned x is checked once more
    against ‖b − K x‖, which guards the recurrence against round-off in the kept (possibly single) factors."""
    scale = _norm(b)
    if scale == 0.0:
        return np.zeros_like(b), 0
    V = np.empty((max_iterations + 1, b.size))
    Z = np.empty((max_iterations, b.size))
    H = np.zeros((max_iterations + 1, max_iterations))
    V[0] = b / scale
    for j in range(max_iterations):
        Z[j] = precondition(V[j])
        w = K @ Z[j]
        for i in range(j + 1):                                    # modified Gram–Schmidt
            H[i, j] = np.dot(V[i], w)
            w -= H[i, j] * V[i]
        H[j + 1, j] = _norm(w)
        e1 = np.zeros(j + 2)
        e1[0] = scale
        y = np.linalg.lstsq(H[:j + 2, :j + 1], e1, rcond=None)[0]
        if _norm(e1 - H[:j + 2, :j + 1] @ y) <= rtol * scale or H[j + 1, j] == 0.0:
            x = Z[:j + 1].T @ y
            ok = all_finite(x) and _norm(b - K @ x) <= rtol * scale * (1.0 + 1e-6)
            return (x if ok else None), j + 1
        V[j + 1] = w / H[j + 1, j]
    return None, max_iterations


def _norm(a: np.ndarray) -> float:
    """The 2-norm (Frobenius for several right-hand sides) in one dot product."""
    return float(np.sqrt(np.vdot(a, a)))


@number_arguments
def rigid_body_modes(points: ArrayLike, component: ArrayLike) -> np.ndarray:
    """Near-null space of elasticity: translations and infinitesimal rotations at the DOF locations.

    ``points`` is ``(dim, n)`` (DOF coordinates), ``component`` ``(n,)`` the displacement component of each DOF.
    Returns ``(n, 3)`` in 2D and ``(n, 6)`` in 3D.
    """
    dim, n = points.shape
    modes = [(component == c).astype(float) for c in range(dim)]
    x = points - (points.mean(axis=1, keepdims=True) if n else 0.0)     # n = 0: every DOF prescribed
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
        self.rtol = check_range("rtol", rtol, 0.0, 1.0, low_open=True, high_open=True)
        self.maxiter = int(check_range("maxiter", maxiter, 1, None))
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


@number_arguments
def make_linear_solver(kind, dim: int, n_free: int, near_null_space: ArrayLike | None = None):
    """Linear solver for ``kind`` in ("auto", "direct", "pardiso", "superlu", "dense", "banded", "amg") or a user
    object/callable.

    ``auto``: direct LU in 2D and for 3D problems up to ``AUTO_AMG_MIN_DOFS`` free DOFs, AMG-CG above.
    """
    if not isinstance(kind, str):
        return kind
    check_option("linear_solver", kind, ("auto", "direct", *BACKENDS[1:], "amg"))
    if kind == "auto":
        threshold = AUTO_AMG_MIN_DOFS_PARDISO if pardiso_available() else AUTO_AMG_MIN_DOFS
        kind = "amg" if dim == 3 and n_free > threshold else "direct"
    if kind == "amg":
        return AMGSolver(near_null_space)
    return DirectSolver("auto" if kind == "direct" else kind)
