"""The direct-solver layer: every back-end against SuperLU, analysis reuse over a multi-step run, refusals."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import skfem

from abrakit.fem import Assembler, DirectSolver, Dirichlet, Kinematics, Solver, StepControl, vector_basis
from abrakit.fem.linsolve import LinearSolveError, kept_factor_gmres, pardiso_available
from abrakit.materials import LinearElastic, VonMisesPlasticity

BACKENDS = ["superlu", "dense", "banded"] + (["pardiso"] if pardiso_available() else [])


def block(n=4):
    axis = np.linspace(0.0, 1.0, n + 1)
    mesh = skfem.MeshHex.init_tensor(axis, axis, np.linspace(0.0, 2.0, 2 * n + 1))
    tol = 1e-9
    return mesh.with_boundaries({"bottom": lambda x: x[2] < tol, "top": lambda x: x[2] > 2 - tol})


def elastic_matrix():
    mesh = block()
    kin = Kinematics.from_mesh(mesh)
    material = LinearElastic(200000.0, 0.3)
    K = Assembler(kin).tangent(material.update(material.initial_state((kin.nel, kin.nqp)),
                                               np.zeros((kin.nel, kin.nqp, 6))).tangent)
    free = np.setdiff1d(np.arange(kin.ndof), Dirichlet.on(kin.basis, "bottom").dofs)   # clamped bottom
    return sp.csr_matrix(K[free][:, free])


def unsymmetric(K, seed=0):
    """K plus non-symmetric 3x3 nodal blocks, as frictional contact adds (inside K's pattern)."""
    rng = np.random.default_rng(seed)
    n = K.shape[0] - K.shape[0] % 3
    blocks = sp.block_diag([0.2 * K[i, i] * rng.standard_normal((3, 3)) for i in range(0, n, 3)])
    return sp.csr_matrix(K + sp.csr_matrix(blocks, shape=K.shape))


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("kind", ["elastic", "unsymmetric"])
def test_backends_agree_with_superlu_to_1e_10(backend, kind):
    K = elastic_matrix()
    if kind == "unsymmetric":
        K = unsymmetric(K)
        assert abs(K - K.T).max() > 1e-3 * abs(K).max()
    rhs = np.random.default_rng(1).standard_normal(K.shape[0])
    reference = spla.splu(sp.csc_matrix(K)).solve(rhs)
    x = DirectSolver(backend).solve(K, rhs)
    assert np.linalg.norm(x - reference) <= 1e-10 * np.linalg.norm(reference)


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_analysis_is_kept_across_newton_iterations_and_load_steps(backend):
    mesh = block(3)
    basis = vector_basis(mesh)
    bcs = [Dirichlet.on(basis, "bottom"), Dirichlet.on(basis, "top", "z", 0.01, name="top")]
    material = VonMisesPlasticity(200000.0, 0.3, 200.0, 2000.0, integration="implicit")
    control = StepControl(initial=0.25, maximum=0.25)
    solver = Solver(basis, material, bcs, linear_solver=backend, control=control)
    result = solver.run(progress=False)
    ls = solver.linear_solver
    assert ls.analyses == 1 and ls.solves == int(result.iterations.sum())
    assert ls.factorisations < ls.solves                        # chord steps (NewtonOptions.chord_check) reuse them
    assert np.max(result.curves["F_top"]) > 0 and np.any(result.state["alpha_p"] > 0)
    reference = Solver(basis, material, bcs, linear_solver="superlu", control=control).run(progress=False)
    assert np.allclose(result.u, reference.u, rtol=1e-10, atol=1e-14)


@pytest.mark.parametrize("backend", BACKENDS)
def test_resolve_solves_with_the_kept_factors_and_needs_them(backend):
    K = elastic_matrix()
    solver = DirectSolver(backend)
    rhs = np.random.default_rng(2).standard_normal(K.shape[0])
    with pytest.raises(LinearSolveError, match="factorisation"):
        solver.resolve(rhs)
    solver.solve(K, np.ones(K.shape[0]))
    x = solver.resolve(rhs)
    assert solver.factorisations == 1 and np.linalg.norm(K @ x - rhs) <= 1e-10 * np.linalg.norm(rhs)


def test_a_changed_pattern_is_analysed_again():
    K = elastic_matrix()
    solver = DirectSolver("superlu")
    rhs = np.ones(K.shape[0])
    solver.solve(K, rhs)
    solver.solve(2.0 * K, rhs)
    assert solver.analyses == 1
    bigger = sp.csr_matrix(K + sp.diags(np.ones(K.shape[0] - 40), 40))
    x = solver.solve(bigger, rhs)
    assert solver.analyses == 2 and np.allclose(bigger @ x, rhs)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_singular_matrix_raises_a_linear_solve_error(backend):
    K = sp.csr_matrix(np.array([[1.0, 1.0], [1.0, 1.0]]))
    with pytest.raises(LinearSolveError):
        DirectSolver(backend).solve(K, np.array([1.0, 0.0]))


def test_unknown_backend_is_refused():
    with pytest.raises(ValueError, match="backend"):
        DirectSolver("mumps")


def test_superlu_reuses_its_own_fill_reducing_order():
    """The kept order must be SuperLU's column order as an index array (the inverse of ``perm_c``): the
    refactorisation then has the fill of the first one, not several times more."""
    K = elastic_matrix()
    solver = DirectSolver("superlu")
    rhs = np.ones(K.shape[0])
    solver.solve(K, rhs)
    first = solver.backend._lu[0]
    solver.solve(2.0 * K, rhs)
    again = solver.backend._lu[0]
    assert again.L.nnz + again.U.nnz <= 1.01 * (first.L.nnz + first.U.nnz)


@pytest.mark.skipif(not pardiso_available(), reason="pypardiso/MKL not installed")
def test_pardiso_probe_names_the_mkl_library_for_later_solvers():
    """pypardiso globs the whole environment for mkl_rt at every construction unless PYPARDISO_MKL_RT names it;
    the probe names the library it found (an existing file), so later solvers load it directly."""
    import os

    assert os.path.isfile(os.environ["PYPARDISO_MKL_RT"])


@pytest.mark.skipif(not pardiso_available(), reason="pypardiso/MKL not installed")
def test_the_mkl_library_is_named_before_pypardiso_is_imported_and_a_users_choice_is_kept(monkeypatch):
    """A fresh process that imports abrakit's solvers and then pypardiso loads the library pip installed into the
    environment's ``lib`` directly (no recursive glob: pypardiso's own search cost 1.5–5 s per process); a path the
    user set stays."""
    import os
    import subprocess
    import sys

    from abrakit.fem.linsolve import _name_mkl_library

    probe = ("import glob, os; import abrakit.fem.linsolve as L; calls = []; g = glob.glob;"
             "glob.glob = lambda *a, **k: calls.append(a) if k.get('recursive') else None or g(*a, **k);"
             "import pypardiso; assert L.pardiso_available(); pypardiso.PyPardisoSolver();"
             "print(os.environ['PYPARDISO_MKL_RT'], len(calls))")
    env = {k: v for k, v in os.environ.items() if k != "PYPARDISO_MKL_RT"}
    path, globs = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True,
                                 check=True).stdout.split()
    assert os.path.isfile(path) and "mkl_rt" in os.path.basename(path) and globs == "0"
    monkeypatch.setenv("PYPARDISO_MKL_RT", "/chosen/by/the/user/libmkl_rt.so")
    _name_mkl_library()
    assert os.environ["PYPARDISO_MKL_RT"] == "/chosen/by/the/user/libmkl_rt.so"


def plate_tangent(element, n_angular, n_radial):
    """K_II of the plastic plate with a hole (2D, elastic tangent)."""
    from abrakit.fem.problems import TABLE_7_1_PLASTICITY, plate_with_hole_problem

    solver = plate_with_hole_problem(VonMisesPlasticity(**TABLE_7_1_PLASTICITY), n_angular=n_angular,
                                     n_radial=n_radial, element=element)
    kin = solver.kin
    response = solver.material.update(solver.material.initial_state((kin.nel, kin.nqp)),
                                      np.zeros((kin.nel, kin.nqp, 6)))
    return solver.tangent(response, [])[1]


def test_auto_chooses_the_banded_lu_for_small_2d_meshes_and_a_sparse_solver_for_wide_bands(monkeypatch):
    """``auto`` decides at the first solve by the cost model of :func:`banded_wins`: the banded LU for a 2D plate
    of a hundred unknowns (band 19), the sparse solver for the 3D block (band of order n^(2/3)) and for a 2D
    mesh of 6000 unknowns."""
    from abrakit.fem.linsolve import _BandedBackend, banded_wins

    banded_analyses = []
    analyse = _BandedBackend.analyse
    monkeypatch.setattr(_BandedBackend, "analyse", lambda self, K: banded_analyses.append(1) or analyse(self, K))
    sparse = "direct-pardiso" if pardiso_available() else "direct-superlu"
    for K, expected in ((plate_tangent("Q4", 8, 6), "direct-banded"), (elastic_matrix(), sparse),
                        (plate_tangent("Q4", 64, 48), sparse)):
        solver = DirectSolver()
        rhs = np.ones(K.shape[0])
        x = solver.solve(K, rhs)
        assert solver.name == expected
        np.testing.assert_allclose(K @ x, rhs, rtol=0, atol=1e-10 * np.abs(K).max())
        solver.solve(2.0 * K, rhs)
        assert solver.analyses == 1 and len(banded_analyses) == 1   # the banded analysis that decided is kept
        banded_analyses.clear()
    assert banded_wins(100, 10, "superlu") and not banded_wins(100_000, 300, "pardiso")


@pytest.mark.parametrize("n_rhs", [1, 3])
def test_banded_lu_reorders_for_a_narrow_band_and_solves_several_right_hand_sides(n_rhs):
    """Numbered badly (randomly), the plate's band spans the matrix; the analysis' reverse Cuthill–McKee order
    brings it back within 1.5 times the mesh generator's numbering (band 19 of 107 unknowns), and the solution is
    the sparse LU's."""
    K = plate_tangent("Q4", 8, 6)
    order = np.random.default_rng(2).permutation(K.shape[0])
    K = sp.csr_matrix(K[order][:, order])
    coo = K.tocoo()
    assert np.max(np.abs(coo.row - coo.col)) > 0.9 * K.shape[0]
    rhs = np.random.default_rng(3).standard_normal((K.shape[0], n_rhs)).squeeze()
    solver = DirectSolver("banded")
    x = solver.solve(K, rhs)
    assert solver.backend.bandwidth <= 1.5 * 19
    reference = spla.splu(sp.csc_matrix(K)).solve(rhs)
    assert np.linalg.norm(x - reference) <= 1e-10 * np.linalg.norm(reference)


@pytest.mark.parametrize("backend", ["auto", "banded"])
def test_a_system_without_unknowns_is_solved_by_every_choice(backend):
    """Every DOF prescribed (a single element held on all nodes): K_II is 0 × 0 and the correction empty."""
    x = DirectSolver(backend).solve(sp.csr_matrix((0, 0)), np.zeros(0))
    assert x.shape == (0,)


needs_pardiso = pytest.mark.skipif(not pardiso_available(), reason="pypardiso/MKL not installed")


@needs_pardiso
@pytest.mark.parametrize("kind", ["elastic", "unsymmetric"])
def test_single_precision_factors_refined_in_double_give_the_double_answer(kind):
    """Float32 factors alone leave a relative residual of about 1e-6; the refinement in double precision brings it
    to check_tol, and the correction then agrees with the double factors' to the conditioning times check_tol."""
    K = elastic_matrix()
    if kind == "unsymmetric":
        K = unsymmetric(K)
    rhs = np.random.default_rng(1).standard_normal(K.shape[0])
    reference = spla.splu(sp.csc_matrix(K)).solve(rhs)
    solver = DirectSolver("pardiso", precision="single", check_tol=1e-13)
    x = solver.solve(K, rhs)
    assert solver.name == "direct-pardiso-single" and solver.precision_fallbacks == 0
    assert np.linalg.norm(K @ x - rhs) <= 1e-13 * np.linalg.norm(rhs)
    assert np.linalg.norm(x - reference) <= 1e-10 * np.linalg.norm(reference)
    raw = solver.backend.solve(rhs)                    # the factors are single: refinement did the work
    assert np.linalg.norm(K @ raw - rhs) > 1e-9 * np.linalg.norm(rhs)
    assert solver.solves > solver.factorisations
    chord = solver.resolve(2.0 * rhs)                  # the chord step's solve is refined too
    assert np.linalg.norm(K @ chord - 2.0 * rhs) <= 1e-13 * np.linalg.norm(2.0 * rhs)


@needs_pardiso
def test_a_tangent_too_ill_conditioned_for_single_factors_is_solved_with_double_ones():
    """A nearly singular matrix (a 1D Laplacian without supports, shifted by 1e-7: condition about 4e7, against
    float32's 6e-8 rounding) defeats float32 factors, whose refinement then diverges; the solver refactorises in
    double, stays there and counts the fallback. (A shift of 1e-5 is still solved in single precision.)"""
    n = 400
    laplacian = sp.diags([-np.ones(n - 1), 2.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1]).tolil()
    laplacian[0, 0] = laplacian[n - 1, n - 1] = 1.0
    K = sp.csr_matrix(laplacian + 1e-7 * sp.identity(n))
    rhs = np.random.default_rng(3).standard_normal(n)
    solver = DirectSolver("pardiso", precision="single")
    x = solver.solve(K, rhs)
    assert solver.precision_fallbacks == 1 and solver.precision == "double" and solver.name == "direct-pardiso"
    assert np.linalg.norm(K @ x - rhs) <= 1e-8 * np.linalg.norm(rhs)


def test_single_precision_is_refused_where_it_does_not_exist():
    with pytest.raises(ValueError, match="precision"):
        DirectSolver("pardiso", precision="half")
    with pytest.raises(ValueError, match="precision='single' needs backend='pardiso'"):
        DirectSolver("superlu", precision="single")


def perturbed(K, size, seed=2):
    """K with its values scaled by 1 + size·(random in [−1, 1]), in K's own pattern: the next Newton tangent."""
    rng = np.random.default_rng(seed)
    return sp.csr_matrix((K.data * (1.0 + size * rng.uniform(-1.0, 1.0, K.nnz)), K.indices, K.indptr),
                         shape=K.shape)


@pytest.mark.parametrize("backend", ["superlu"] + (["pardiso"] if pardiso_available() else []))
def test_inexact_corrections_with_kept_factors_meet_the_forcing_term_without_a_factorisation(backend):
    """forcing = η: within a step, a tangent close to the factorised one is solved by GMRES preconditioned with the
    kept factors to ‖b − K x‖ ≤ η ‖b‖, with no new factorisation; a new step factorises; a tangent far from the
    kept factors (here every value changed by up to ±90 %) is factorised after all and solved to check_tol."""
    K0 = unsymmetric(elastic_matrix())
    rhs = np.random.default_rng(1).standard_normal(K0.shape[0])
    solver = DirectSolver(backend, forcing=0.03, krylov_iterations=8)
    solver.solve(K0, rhs, new_step=True)
    assert solver.factorisations == 1
    K1 = perturbed(K0, 0.02)
    x = solver.solve(K1, rhs, new_step=False)
    assert solver.factorisations == 1 and solver.krylov_solves == 1 and 1 <= solver.gmres_iterations <= 8
    assert np.linalg.norm(rhs - K1 @ x) <= 0.03 * np.linalg.norm(rhs)
    assert np.linalg.norm(rhs - K1 @ x) > 1e-8 * np.linalg.norm(rhs)       # inexact: no refinement to check_tol
    solver.solve(K1, rhs, new_step=True)
    assert solver.factorisations == 2
    K2 = perturbed(K0, 0.9, seed=5)
    x = solver.solve(K2, rhs, new_step=False)
    assert solver.krylov_fallbacks == 1 and solver.factorisations == 3
    assert np.linalg.norm(rhs - K2 @ x) <= 1e-8 * np.linalg.norm(rhs)


def test_kept_factor_gmres_is_exact_with_the_matrix_own_factors_and_meets_its_tolerance_on_the_true_residual():
    """With K's own LU as the preconditioner GMRES converges in one iteration to round-off. With a Jacobi
    preconditioner every returned x meets ‖b − K x‖ ≤ rtol ‖b‖ on K itself (right preconditioning), a tighter rtol
    never needs fewer iterations (GMRES's residual is non-increasing), and too few iterations give None, not a
    wrong x. A zero right-hand side needs no iteration."""
    K = unsymmetric(elastic_matrix())
    b = np.random.default_rng(4).standard_normal(K.shape[0])
    lu = spla.splu(sp.csc_matrix(K))
    x, iterations = kept_factor_gmres(K, b, lu.solve, 1e-10, 5)
    assert iterations == 1 and np.linalg.norm(b - K @ x) <= 1e-10 * np.linalg.norm(b)
    jacobi = sp.diags(1.0 / K.diagonal())
    needed = []
    for rtol in (0.5, 0.2, 0.1, 0.05, 0.02):
        x, iterations = kept_factor_gmres(K, b, lambda v: jacobi @ v, rtol, 200)
        assert x is not None and np.linalg.norm(b - K @ x) <= rtol * np.linalg.norm(b) * (1 + 1e-6)
        needed.append(iterations)
    assert needed == sorted(needed) and needed[-1] > needed[0]
    assert kept_factor_gmres(K, b, lambda v: jacobi @ v, 0.02, needed[-1] - 1) == (None, needed[-1] - 1)
    x, iterations = kept_factor_gmres(K, np.zeros_like(b), lu.solve, 1e-3, 5)
    assert iterations == 0 and not x.any()


def test_the_forcing_term_and_the_krylov_iterations_are_checked():
    with pytest.raises(ValueError, match="forcing"):
        DirectSolver("superlu", forcing=1.0)
    with pytest.raises(ValueError, match="forcing"):
        DirectSolver("superlu", forcing=-0.1)
    with pytest.raises(ValueError, match="krylov_iterations"):
        DirectSolver("superlu", forcing=0.1, krylov_iterations=0)
