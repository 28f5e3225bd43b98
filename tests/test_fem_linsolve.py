"""The direct-solver layer: every back-end against SuperLU, analysis reuse over a multi-step run, refusals."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import skfem

from abrakit.fem import (
    Assembler,
    DirectSolver,
    Dirichlet,
    Kinematics,
    LinearSolveError,
    Solver,
    StepControl,
    pardiso_available,
    vector_basis,
)
from abrakit.materials import LinearElastic, VonMisesPlasticity

BACKENDS = ["superlu", "dense"] + (["pardiso"] if pardiso_available() else [])


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
    assert ls.analyses == 1 and ls.factorisations == ls.solves == int(result.iterations.sum())
    assert np.max(result.curves["F_top"]) > 0 and np.any(result.state["alpha_p"] > 0)
    reference = Solver(basis, material, bcs, linear_solver="superlu", control=control).run(progress=False)
    assert np.allclose(result.u, reference.u, rtol=1e-10, atol=1e-14)


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


def test_auto_chooses_dense_lu_for_the_smallest_systems_and_a_sparse_solver_above():
    """``auto`` picks its back-end at the first solve by the number of unknowns (DENSE_MAX_DOFS)."""
    from abrakit.fem.linsolve import DENSE_MAX_DOFS

    for n, expected in ((DENSE_MAX_DOFS, "direct-dense"),
                        (DENSE_MAX_DOFS + 1, "direct-pardiso" if pardiso_available() else "direct-superlu")):
        K = sp.diags([np.full(n - 1, -1.0), np.full(n, 4.0), np.full(n - 1, -1.0)], [-1, 0, 1], format="csr")
        solver = DirectSolver()
        x = solver.solve(K, np.ones(n))
        assert solver.name == expected
        np.testing.assert_allclose(K @ x, np.ones(n), rtol=0, atol=1e-12)
