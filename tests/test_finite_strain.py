"""Finite-strain J2 plasticity (exponential map in log strains) and the total-Lagrangian kinematics.

Closed forms: uniaxial tension to 50 % logarithmic strain, a rigid rotation of 90°, isochoric plastic flow
(ln J = tr τ / 3K); derivatives against finite differences (material tangent, matrix-log derivative, global
stiffness); the small-strain limit; clear refusals.
"""

import numpy as np
import pytest
import scipy.linalg
import skfem

from abrakit import tensors as T
from abrakit.compiled import HAVE_NUMBA
from abrakit.fem import Assembler, Dirichlet, Kinematics, NewtonOptions, Solver, StepControl, vector_basis
from abrakit.materials import LinearElastic, LogStrainPlasticity, VonMisesPlasticity
from abrakit.materials.finite_strain import (
    _mandel_rotation,
    log_derivative,
    log_divided_differences,
    material_tangent,
)

E, NU, R_P, K_H = 210000.0, 0.33, 289.9, 666.7
PLASTIC = LogStrainPlasticity(VonMisesPlasticity(E, NU, R_P, K_H, integration="implicit"))
ELASTIC = LogStrainPlasticity(LinearElastic(E, NU))


def rotation_z(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def fd_tangent(material, state, F, h=1e-7):
    columns = []
    for k in range(9):
        step = np.zeros(9)
        step[k] = h
        columns.append((material.update(state, F + step).stress - material.update(state, F - step).stress) / (2 * h))
    return np.stack(columns, axis=-1)


def unit_cube(n=2):
    axis = np.linspace(0.0, 1.0, n + 1)
    mesh = skfem.MeshHex.init_tensor(axis, axis, axis)
    tol = 1e-9
    return mesh.with_boundaries({"x0": lambda x: x[0] < tol, "y0": lambda x: x[1] < tol,
                                 "z0": lambda x: x[2] < tol, "x1": lambda x: x[0] > 1 - tol})


# ---- the matrix logarithm and its derivative --------------------------------------------------------------------


def test_log_divided_differences_are_continuous_through_repeated_eigenvalues():
    lam = np.array([[2.0, 2.0, 2.0 * (1 + 1e-9)], [1.0, 3.0, 0.5]])
    G = log_divided_differences(lam)
    assert np.allclose(np.diagonal(G, axis1=-2, axis2=-1), 1.0 / lam)
    assert G[0, 0, 2] == pytest.approx(1.0 / 2.0, rel=1e-8)
    assert G[1, 0, 1] == pytest.approx(np.log(3.0) / 2.0, rel=1e-14)


@pytest.mark.parametrize("spread", [0.3, 1e-7, 0.0])
def test_log_derivative_matches_finite_differences_of_the_matrix_log(spread):
    rng = np.random.default_rng(3)
    Q = np.linalg.qr(rng.standard_normal((3, 3)))[0]
    b = Q @ np.diag([1.2, 1.2 + spread, 0.8]) @ Q.T
    h = rng.standard_normal((3, 3))
    h = h + h.T
    lam, vec = np.linalg.eigh(b)
    exact = log_derivative(vec, log_divided_differences(lam), h)
    eps = 1e-6
    fd = (scipy.linalg.logm(b + eps * h) - scipy.linalg.logm(b - eps * h)).real / (2 * eps)
    assert np.allclose(exact, fd, atol=1e-7)


def test_mandel_rotation_rotates_symmetric_tensors():
    rng = np.random.default_rng(4)
    Q = np.linalg.qr(rng.standard_normal((5, 3, 3)))[0]
    A = rng.standard_normal((5, 3, 3))
    A = A + np.swapaxes(A, -1, -2)
    rotated = np.swapaxes(Q, -1, -2) @ A @ Q
    assert np.allclose(np.einsum("...IJ,...J->...I", _mandel_rotation(Q), T.to_mandel(A)), T.to_mandel(rotated))
    # the tangent's fast kernel is the public tensors.mandel_rotation of the transposed axes
    assert np.allclose(_mandel_rotation(Q), T.mandel_rotation(np.swapaxes(Q, -1, -2)))


# ---- material point --------------------------------------------------------------------------------------------


def test_a_rigid_rotation_of_90_degrees_gives_zero_stress():
    for material in (PLASTIC, ELASTIC):
        r = material.update(material.initial_state(()), rotation_z(np.pi / 2).ravel())
        assert np.abs(r.stress).max() < 1e-9
        assert np.abs(r.state["cauchy"]).max() < 1e-9


def test_a_rotation_after_plastic_flow_rotates_the_cauchy_stress_and_keeps_its_invariants():
    F = np.diag([1.1, 0.97, 0.95])
    first = PLASTIC.update(PLASTIC.initial_state(()), F.ravel())
    assert first.state["alpha_p"] > 0
    R = rotation_z(np.pi / 2)
    rotated = PLASTIC.update(first.state, (R @ F).ravel())      # same stretch, then turned by 90 degrees
    same = PLASTIC.update(first.state, F.ravel())
    sigma, sigma_r = T.from_mandel(same.state["cauchy"]), T.from_mandel(rotated.state["cauchy"])
    assert np.allclose(sigma_r, R @ sigma @ R.T, atol=1e-8)
    assert rotated.state["alpha_p"] == pytest.approx(same.state["alpha_p"], rel=1e-12)


@pytest.mark.parametrize("material", [PLASTIC, ELASTIC], ids=["plastic", "elastic"])
def test_consistent_tangent_matches_finite_differences(material):
    rng = np.random.default_rng(0)
    F0 = np.eye(3) + 0.05 * rng.standard_normal((6, 3, 3))
    first = material.update(material.initial_state((6,)), F0.reshape(6, 9))
    F1 = (F0 + 0.02 * rng.standard_normal((6, 3, 3))).reshape(6, 9)
    F1[0] = np.eye(3).ravel()                                 # repeated eigenvalues of b_e^tr
    F1[1] = (np.eye(3) + 1e-9 * rng.standard_normal((3, 3))).ravel()
    exact = material.update(first.state, F1).tangent
    fd = fd_tangent(material, first.state, F1)
    assert np.abs(exact - fd).max() <= 1e-6 * np.abs(fd).max()


def test_plastic_flow_is_isochoric_so_J_is_the_elastic_volume_change():
    rng = np.random.default_rng(1)
    F = np.eye(3) + 0.2 * rng.standard_normal((50, 3, 3))
    F[np.linalg.det(F) <= 0.2] = np.eye(3)
    r = PLASTIC.update(PLASTIC.initial_state((50,)), F.reshape(50, 9))
    assert np.mean(r.state["alpha_p"] > 0) > 0.5
    K = E / (3 * (1 - 2 * NU))
    kirchhoff_mean = r.state["J"] * r.state["cauchy"][:, :3].sum(axis=1) / 3
    assert np.allclose(np.log(r.state["J"]), kirchhoff_mean / K, rtol=1e-12, atol=1e-14)
    assert np.allclose(np.linalg.det(r.state["Cp_inv"]), 1.0, rtol=1e-12)   # det F_p = 1


def test_small_strain_limit_is_the_small_strain_model():
    small = VonMisesPlasticity(E, NU, R_P, K_H, integration="implicit")
    grad = 1e-7 * np.array([[1.0, 0.3, 0.0], [0.3, -0.5, 0.2], [0.0, 0.2, 0.1]])
    finite = ELASTIC.update(ELASTIC.initial_state(()), (np.eye(3) + grad).ravel())
    linear = small.update(small.initial_state(()), T.to_mandel(grad))
    # they differ at second order in the displacement gradient, |grad u|^2 E ~ 1e-14 * 2e5 MPa
    assert np.abs(finite.stress.reshape(3, 3) - T.from_mandel(linear.stress)).max() <= 1e-8


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="integration"):
        LogStrainPlasticity(VonMisesPlasticity(E, NU, R_P, K_H, integration="explicit"))
    with pytest.raises(TypeError, match="base"):
        LogStrainPlasticity("steel")
    with pytest.raises(ValueError, match="F"):
        PLASTIC.update(PLASTIC.initial_state(()), np.eye(3))
    with pytest.raises(FloatingPointError, match="inverted"):          # the solver cuts such a step back
        PLASTIC.update(PLASTIC.initial_state(()), np.diag([1.0, 1.0, -1.0]).ravel())


# ---- finite elements -------------------------------------------------------------------------------------------


def test_uniaxial_tension_to_50_percent_log_strain_follows_the_closed_form():
    """Kirchhoff stress against ln(stretch) is the small-strain 1D curve: tau = E eps, then
    tau = (sigma_0 + H eps) / (1 + H/E) with sigma_0 = sqrt(3/2) r_p, H = 1.5 K_H; the face force is
    P_11 = tau / lambda."""
    mesh = unit_cube(2)
    basis = vector_basis(mesh)
    stretch = np.exp(0.5)
    bcs = [Dirichlet.on(basis, "x0", "x"), Dirichlet.on(basis, "y0", "y"), Dirichlet.on(basis, "z0", "z"),
           Dirichlet.on(basis, "x1", "x", stretch - 1.0, name="end")]
    solver = Solver(basis, PLASTIC, bcs, finite_strain=True, control=StepControl(initial=0.02, maximum=0.05),
                    newton=NewtonOptions(residual_tol=1e-10))
    result = solver.run(progress=False)
    lam = 1.0 + result.curves["u_end"]
    eps = np.log(lam)
    sigma_0, H = np.sqrt(1.5) * R_P, 1.5 * K_H
    tau = np.where(eps < sigma_0 / E, E * eps, (sigma_0 + H * eps) / (1 + H / E))
    assert eps[-1] == pytest.approx(0.5)
    assert np.allclose(result.curves["F_end"], tau / lam, rtol=1e-8, atol=1e-8)
    assert result.iterations[1:].max() <= 6                          # quadratic convergence with the tangent


def test_rigidly_rotated_mesh_has_no_internal_force():
    mesh = unit_cube(1)
    kin = Kinematics.from_basis(vector_basis(mesh), finite_strain=True)
    R = rotation_z(np.pi / 2)
    u = np.zeros(kin.ndof)
    u[kin.basis.nodal_dofs] = (R - np.eye(3)) @ mesh.p
    F = kin.strain(u)
    assert np.allclose(F.reshape(-1, 3, 3), R)
    response = PLASTIC.update(PLASTIC.initial_state((kin.nel, kin.nqp)), F)
    assert np.abs(Assembler(kin).internal_force(response.stress)).max() < 1e-8


@pytest.mark.parametrize("dim", [2, 3])
def test_global_stiffness_is_the_derivative_of_the_internal_force(dim):
    axis = np.linspace(0.0, 1.0, 3)
    mesh = skfem.MeshQuad.init_tensor(axis, axis) if dim == 2 else skfem.MeshHex.init_tensor(axis, axis, axis)
    kin = Kinematics.from_basis(vector_basis(mesh), finite_strain=True)
    asm = Assembler(kin)
    rng = np.random.default_rng(2)
    state = PLASTIC.initial_state((kin.nel, kin.nqp))
    u = 0.03 * rng.standard_normal(kin.ndof)

    def force(v):
        return asm.internal_force(PLASTIC.update(state, kin.strain(v)).stress)

    K = asm.tangent(PLASTIC.update(state, kin.strain(u)).tangent).toarray()
    direction = rng.standard_normal(kin.ndof)
    h = 1e-7
    fd = (force(u + h * direction) - force(u - h * direction)) / (2 * h)
    assert np.allclose(K @ direction, fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba (extra 'fast') not installed")
def test_compiled_tangent_equals_the_numpy_one():
    rng = np.random.default_rng(5)
    F = (np.eye(3) + 0.1 * rng.standard_normal((40, 3, 3))).reshape(40, 9)
    F[0] = np.eye(3).ravel()
    state = PLASTIC.update(PLASTIC.initial_state((40,)), F).state
    F2 = F + 0.02 * rng.standard_normal((40, 9))
    args = _tangent_arguments(PLASTIC, state, F2)
    compiled, vectorised = material_tangent(*args, compiled=True), material_tangent(*args, compiled=False)
    assert np.abs(compiled - vectorised).max() <= 1e-12 * np.abs(vectorised).max()


def _tangent_arguments(material, state, F):
    """(F⁻¹, Q, λ, D, P) of an update, as :func:`material_tangent` takes them (recomputed here independently)."""
    F = F.reshape(-1, 3, 3)
    F_inv = np.linalg.inv(F)
    b = F @ state["Cp_inv"] @ np.swapaxes(F, -1, -2)
    lam, Q = np.linalg.eigh(0.5 * (b + np.swapaxes(b, -1, -2)))
    eps = T.to_mandel(np.einsum("...ia,...a,...ja->...ij", Q, 0.5 * np.log(lam), Q))
    base = material.base
    base_state = base.initial_state(lam.shape[:-1]) | {"alpha_p": state["alpha_p"]}
    small = base.update(base_state, eps)
    P = T.from_mandel(small.stress) @ np.swapaxes(F_inv, -1, -2)
    return F_inv, Q, lam, small.tangent, P


# ---- F-bar: the finite-strain counterpart of B-bar -----------------------------------------------------------------


def fbar_kinematics(n=2):
    axis = np.linspace(0.0, 1.0, n + 1)
    return Kinematics.from_basis(vector_basis(skfem.MeshHex.init_tensor(axis, axis, axis)), bbar=True,
                                 finite_strain=True)


def test_fbar_tangent_is_the_derivative_of_its_force():
    kin = fbar_kinematics()
    asm = Assembler(kin)
    rng = np.random.default_rng(2)
    state = PLASTIC.initial_state((kin.nel, kin.nqp))
    u = 0.05 * rng.standard_normal(kin.ndof)

    def force(v):
        return asm.internal_force(PLASTIC.update(state, kin.strain(v)).stress, v)

    r = PLASTIC.update(state, kin.strain(u))
    assert np.any(r.state["alpha_p"] > 0)
    K = asm.tangent(r.tangent, u, r.stress).toarray()
    direction = rng.standard_normal(kin.ndof)
    h = 1e-7
    fd = (force(u + h * direction) - force(u - h * direction)) / (2 * h)
    assert np.abs(K @ direction - fd).max() <= 1e-7 * np.abs(fd).max()


def test_fbar_keeps_the_element_volume_and_is_plain_total_lagrangian_for_homogeneous_deformation():
    kin = fbar_kinematics()
    plain = Kinematics.from_basis(kin.basis, finite_strain=True)
    rng = np.random.default_rng(3)
    u = 0.05 * rng.standard_normal(kin.ndof)
    F_bar = kin.strain(u).reshape(kin.nel, kin.nqp, 3, 3)
    assert np.allclose(np.linalg.det(F_bar), kin.fbar_state(u).J_bar[:, None], rtol=1e-13)
    # a homogeneous deformation: J is uniform, so F-bar changes nothing
    H = 0.1 * rng.standard_normal((3, 3))
    u_h = np.zeros(kin.ndof)
    u_h[kin.basis.nodal_dofs] = H @ kin.basis.mesh.p
    assert np.allclose(kin.strain(u_h), plain.strain(u_h), rtol=1e-13, atol=1e-14)
    stress = PLASTIC.update(PLASTIC.initial_state((kin.nel, kin.nqp)), kin.strain(u_h)).stress
    assert np.allclose(Assembler(kin).internal_force(stress, u_h), Assembler(plain).internal_force(stress),
                       rtol=1e-10, atol=1e-8)


def test_plain_gradient_elements_are_total_lagrangian_may_invert_and_keep_the_tangent_exact():
    """Elements switched to the plain gradient (eroded material) take F = I + ∇u and the plain force; an inverted
    one raises nothing while an inverted F-bar element does; the tangent stays the derivative of the force."""
    kin = fbar_kinematics()
    plain_kin = Kinematics.from_basis(kin.basis, finite_strain=True)
    asm = Assembler(kin)
    rng = np.random.default_rng(4)
    u = 0.05 * rng.standard_normal(kin.ndof)
    mask = np.zeros(kin.nel, dtype=bool)
    mask[[1, 6]] = True
    kin.use_plain_gradient(mask)
    F, F_plain = kin.strain(u).reshape(kin.nel, -1, 9), plain_kin.strain(u).reshape(kin.nel, -1, 9)
    assert np.allclose(F[mask], F_plain[mask], rtol=1e-14) and not np.allclose(F[~mask], F_plain[~mask])
    if HAVE_NUMBA:                                   # the compiled and the NumPy F-bar state agree on the mask
        numpy_state = kin.fbar_state(u, compiled=False)
        kin.use_plain_gradient(mask)
        for a, b in zip(numpy_state, kin.fbar_state(u, compiled=True), strict=True):
            assert np.allclose(a, b, rtol=1e-12, atol=1e-12)
    c = 1e-3 * 210000.0
    tangent = np.broadcast_to(c * np.eye(9), (kin.nel, kin.nqp, 9, 9)).copy()

    def force(v):
        return asm.internal_force(c * (kin.strain(v) - np.eye(3).ravel()), v)

    K = asm.tangent(tangent, u, c * (kin.strain(u) - np.eye(3).ravel())).toarray()
    direction = rng.standard_normal(kin.ndof)
    h = 1e-7
    fd = (force(u + h * direction) - force(u - h * direction)) / (2 * h)
    assert np.abs(K @ direction - fd).max() <= 1e-6 * np.abs(fd).max()
    p = kin.basis.mesh.p
    corner = int(np.flatnonzero(np.all(p == 0.0, axis=0))[0])            # the mesh's corner: in one element only
    owner = int(np.flatnonzero(np.any(kin.basis.mesh.t == corner, axis=0))[0])
    crushed = np.zeros(kin.ndof)
    crushed[kin.basis.nodal_dofs[:, corner]] = 0.7                     # past the element's opposite corner
    only = np.zeros(kin.nel, dtype=bool)
    only[owner] = True
    kin.use_plain_gradient(only)
    assert np.linalg.det(kin.strain(crushed).reshape(kin.nel, -1, 3, 3)[owner]).min() < 0   # inverted, no error
    kin.use_plain_gradient(np.zeros(kin.nel, dtype=bool))
    with pytest.raises(FloatingPointError, match="inverted"):
        kin.strain(crushed)
    with pytest.raises(ValueError, match="elements"):
        kin.use_plain_gradient(np.ones(3, dtype=bool))


def test_fbar_is_refused_in_plane_strain_and_needs_the_displacement():
    axis = np.linspace(0.0, 1.0, 3)
    with pytest.raises(ValueError, match="3D"):
        Kinematics.from_basis(vector_basis(skfem.MeshQuad.init_tensor(axis, axis)), bbar=True, finite_strain=True)
    kin = fbar_kinematics(1)
    with pytest.raises(ValueError, match="displacement"):
        Assembler(kin).internal_force(np.zeros((kin.nel, kin.nqp, 9)))


# ---- the compiled kernels against the vectorised NumPy path -------------------------------------------------------


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba (extra 'fast') not installed")
@pytest.mark.parametrize("material", [PLASTIC, ELASTIC], ids=["plastic", "hencky"])
def test_compiled_update_equals_the_numpy_one_to_round_off(material):
    """The kernel of :mod:`abrakit.materials._finite_strain_kernels` (Jacobi eigenvectors, explicit loops) and
    the vectorised path (LAPACK eigh, einsum) on points with distinct, double and triple eigenvalues."""
    rng = np.random.default_rng(6)
    F = np.eye(3) + 0.05 * rng.standard_normal((300, 3, 3))
    F[:5] = np.eye(3)                                            # b_e^tr = I: a triple eigenvalue
    F[5:10] = np.diag([1.02, 1.02, 0.97])                        # a double one
    F[10:15] = rotation_z(0.7) @ np.diag([1.1, 0.95, 0.95])      # a double one in a rotated basis
    state = material.update(material.initial_state((300,)), F.reshape(300, 9), compiled=False).state
    F2 = (F + 0.02 * rng.standard_normal((300, 3, 3))).reshape(300, 9)
    F2[:5] = np.eye(3).ravel()
    vectorised = material.update(state, F2, compiled=False)
    compiled = material.update(state, F2, compiled=True)
    if material is PLASTIC:
        assert np.any(vectorised.state["alpha_p"] > state["alpha_p"])     # the return map is exercised
    for key, value in vectorised.state.items():
        assert np.abs(compiled.state[key] - value).max() <= 1e-12 * max(np.abs(value).max(), 1.0), key
    assert np.abs(compiled.stress - vectorised.stress).max() <= 1e-12 * np.abs(vectorised.stress).max()
    assert np.abs(compiled.tangent - vectorised.tangent).max() <= 1e-12 * np.abs(vectorised.tangent).max()


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba (extra 'fast') not installed")
def test_jacobi_eigenvectors_diagonalise_exactly_also_for_repeated_eigenvalues():
    from abrakit.materials._finite_strain_kernels import eigh3

    rng = np.random.default_rng(7)
    for lam in ([1.0, 1.0, 1.0], [2.0, 2.0, 0.5], [1e-3, 1.0, 1e3], [1.0, 1.0 + 1e-12, 3.0]):
        Q0 = np.linalg.qr(rng.standard_normal((3, 3)))[0]
        a = Q0 @ np.diag(lam) @ Q0.T
        work, values, vectors = a.copy(), np.empty(3), np.empty((3, 3))
        eigh3(work, values, vectors)
        assert np.allclose(vectors.T @ vectors, np.eye(3), atol=1e-14)
        assert np.allclose(vectors @ np.diag(values) @ vectors.T, a, rtol=0, atol=1e-13 * max(lam))
        assert np.allclose(np.sort(values), np.sort(lam), rtol=1e-12)


@pytest.mark.parametrize("compiled", [False, pytest.param(True, marks=pytest.mark.skipif(
    not HAVE_NUMBA, reason="numba (extra 'fast') not installed"))])
def test_an_inverted_point_is_refused_by_name_in_both_paths(compiled):
    F = np.tile(np.eye(3).ravel(), (4, 1))
    F[2] = np.diag([1.0, 1.0, -0.5]).ravel()
    with pytest.raises(FloatingPointError, match="inverted"):
        PLASTIC.update(PLASTIC.initial_state((4,)), F, compiled=compiled)
    kin = fbar_kinematics()
    u = np.zeros(kin.ndof)
    u[kin.basis.nodal_dofs[1]] = -3.0 * kin.basis.mesh.p[1]                 # y -> -2 y: every element inverted
    kin._memo[0] = None
    with pytest.raises(FloatingPointError, match="inverted"):
        kin.fbar_state(u, compiled=compiled)


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba (extra 'fast') not installed")
def test_compiled_fbar_state_and_tangents_equal_the_numpy_ones():
    axis = np.linspace(0.0, 1.0, 4)
    graded = np.array([0.0, 0.1, 0.35, 1.0])                                 # unequal elements
    kin = Kinematics.from_basis(vector_basis(skfem.MeshHex.init_tensor(axis, graded, axis)), bbar=True,
                                finite_strain=True)
    rng = np.random.default_rng(8)
    u = 0.02 * rng.standard_normal(kin.ndof)
    vectorised = kin.fbar_state(u, compiled=False)
    kin._memo[0] = None
    compiled = kin.fbar_state(u, compiled=True)
    for name, a, b in zip(vectorised._fields, vectorised, compiled, strict=True):
        assert np.abs(a - b).max() <= 1e-13 * np.abs(a).max(), name
    r = PLASTIC.update(PLASTIC.initial_state((kin.nel, kin.nqp)), kin.strain(u))
    assert np.any(r.state["alpha_p"] > 0)
    K_numpy = kin.element_tangents(r.tangent, r.stress, u, compiled=False)
    K_numba = kin.element_tangents(r.tangent, r.stress, u, compiled=True)
    assert np.abs(K_numba - K_numpy).max() <= 1e-12 * np.abs(K_numpy).max()


def test_compiled_fbar_forces_equal_the_numpy_ones():
    axis = np.linspace(0.0, 1.0, 4)
    graded = np.array([0.0, 0.1, 0.35, 1.0])
    kin = Kinematics.from_basis(vector_basis(skfem.MeshHex.init_tensor(axis, graded, axis)), bbar=True,
                                finite_strain=True)
    u = 0.02 * np.random.default_rng(9).standard_normal(kin.ndof)
    r = PLASTIC.update(PLASTIC.initial_state((kin.nel, kin.nqp)), kin.strain(u))
    f_numpy = kin.element_forces(r.stress, u, compiled=False)
    f_numba = kin.element_forces(r.stress, u, compiled=HAVE_NUMBA)
    assert np.abs(f_numba - f_numpy).max() <= 1e-12 * np.abs(f_numpy).max()
