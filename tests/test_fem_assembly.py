"""Kinematics and assembly of abrakit.fem: B-matrices, Eq. (4.37)/(4.40) against scikit-fem's generic forms."""

import numpy as np
import pytest
import skfem
from hypothesis import given, settings
from hypothesis import strategies as st

from abrakit.fem import Assembler, Dirichlet, Kinematics, Solver, StepControl, vector_basis
from abrakit.fem.assembly import skfem_internal_force, skfem_tangent
from abrakit.materials import LinearElastic


def distorted(mesh, amount=0.02, seed=0):
    """Move the interior nodes of a unit-square/cube mesh at random (keeps the boundary straight)."""
    rng = np.random.default_rng(seed)
    p = mesh.p.copy()
    interior = np.all((p > 1e-9) & (p < 1 - 1e-9), axis=0)
    p[:, interior] += amount * rng.uniform(-1, 1, (p.shape[0], interior.sum()))
    return type(mesh)(p, mesh.t)


MESHES = {
    "quad": lambda: distorted(skfem.MeshQuad().refined(3)),
    "tri": lambda: distorted(skfem.MeshTri().refined(3)),
    "hex": lambda: distorted(skfem.MeshHex().refined(2)),
    "tet": lambda: distorted(skfem.MeshTet().refined(2)),
}


def component_of_dofs(basis):
    comp = np.zeros(basis.N, dtype=int)
    for c in range(basis.mesh.dim()):
        comp[basis.nodal_dofs[c]] = c
    return comp


def linear_field(basis, G, c=None):
    """DOF vector of u(x) = G x + c."""
    comp = component_of_dofs(basis)
    u = np.einsum("ik,kn->in", G, basis.doflocs)
    if c is not None:
        u += np.asarray(c)[:, None]
    return u[comp, np.arange(basis.N)]


@pytest.mark.parametrize("name", list(MESHES))
def test_quadrature_is_explicit(name):
    kin = Kinematics.from_mesh(MESHES[name]())
    expected = {"quad": 4, "tri": 1, "hex": 8, "tet": 1}[name]
    assert kin.nqp == expected  # 2x2(x2) Gauss for bilinear/trilinear, one point for constant-strain simplices
    assert kin.volume == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("bbar", [False, True])
@pytest.mark.parametrize("name", list(MESHES))
def test_strain_of_linear_field_is_exact(name, bbar):
    """B u reproduces the symmetric gradient of a linear field in Mandel form, Eq. (4.26)–(4.29)."""
    kin = Kinematics.from_basis(vector_basis(MESHES[name]()), bbar=bbar)
    dim = kin.dim
    G = np.random.default_rng(3).standard_normal((dim, dim))
    eps = kin.strain(linear_field(kin.basis, G, np.ones(dim)))
    sym = 0.5 * (G + G.T)
    full = np.zeros((3, 3))
    full[:dim, :dim] = sym
    s = np.sqrt(2.0)
    expected = np.array([full[0, 0], full[1, 1], full[2, 2], s * full[1, 2], s * full[0, 2], s * full[0, 1]])
    assert np.allclose(eps, expected, atol=1e-13)


@pytest.mark.parametrize("bbar", [False, True])
@pytest.mark.parametrize("name", list(MESHES))
def test_assembly_matches_generic_scikit_fem_forms(name, bbar):
    """Our einsum assembly equals scikit-fem's BilinearForm/LinearForm for a random qp tangent and stress."""
    kin = Kinematics.from_basis(vector_basis(MESHES[name]()), bbar=bbar)
    asm = Assembler(kin)
    rng = np.random.default_rng(1)
    C = rng.standard_normal((kin.nel, kin.nqp, 6, 6))  # deliberately non-symmetric
    S = rng.standard_normal((kin.nel, kin.nqp, 6))
    K, f = asm.tangent(C), asm.internal_force(S)
    u = rng.standard_normal(kin.ndof)
    if not bbar:
        K_ref, f_ref = skfem_tangent(kin.basis, C), skfem_internal_force(kin.basis, S)
        assert abs(K - K_ref).max() <= 1e-12 * abs(K_ref).max()
        assert np.allclose(f, f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max())
    # independent of scikit-fem: u.K.u = sum_qp eps.C.eps dV and u.f = sum_qp eps.S dV (also for B-bar)
    eps, c = kin.strain(u), list(kin.components)
    energy = np.einsum("eqi,eqij,eqj,eq->", eps[..., c], C[..., c, :][..., c], eps[..., c], kin.dx)
    work = np.einsum("eqi,eqi,eq->", eps[..., c], S[..., c], kin.dx)
    assert u @ K @ u == pytest.approx(energy, rel=1e-11)
    assert u @ f == pytest.approx(work, rel=1e-11)


def test_quadratic_elements_match_generic_forms():
    mesh = distorted(skfem.MeshQuad().refined(2))
    for element in (skfem.ElementQuad2(), skfem.ElementTriP2()):
        m = mesh if isinstance(element, skfem.ElementQuad2) else distorted(skfem.MeshTri().refined(2))
        kin = Kinematics.from_basis(vector_basis(m, element))
        C = np.random.default_rng(0).standard_normal((kin.nel, kin.nqp, 6, 6))
        K_ref = skfem_tangent(kin.basis, C)
        assert abs(Assembler(kin).tangent(C) - K_ref).max() <= 1e-12 * abs(K_ref).max()


def test_elastic_tangent_is_symmetric_and_annihilates_rigid_motion():
    kin = Kinematics.from_mesh(MESHES["hex"]())
    C = np.broadcast_to(LinearElastic(210000.0, 0.3).stiffness, (kin.nel, kin.nqp, 6, 6))
    K = Assembler(kin).tangent(C)
    assert abs(K - K.T).max() <= 1e-10 * abs(K).max()
    W = np.array([[0.0, -0.3, 0.2], [0.3, 0.0, -0.1], [-0.2, 0.1, 0.0]])  # infinitesimal rotation
    rigid = linear_field(kin.basis, W, [1.0, -2.0, 0.5])
    assert np.abs(K @ rigid).max() <= 1e-9 * abs(K).max()


def test_pattern_is_reused_and_refilled():
    kin = Kinematics.from_mesh(MESHES["quad"]())
    asm = Assembler(kin)
    C1 = np.broadcast_to(np.eye(6), (kin.nel, kin.nqp, 6, 6))
    K1, K2 = asm.tangent(C1), asm.tangent(2 * C1)
    assert np.shares_memory(K1.indices, asm.indices) and np.shares_memory(K2.indptr, asm.indptr)  # no re-analysis
    assert np.allclose(K2.data, 2 * K1.data)


def test_bad_shapes_raise():
    asm = Assembler(Kinematics.from_mesh(MESHES["tri"]()))
    with pytest.raises(ValueError, match="stress"):
        asm.internal_force(np.zeros((3, 1, 6)))
    with pytest.raises(ValueError, match="tangent"):
        asm.tangent(np.zeros((asm.kin.nel, asm.kin.nqp, 3, 3)))
    with pytest.raises(TypeError, match="ElementVector"):
        Kinematics.from_basis(skfem.CellBasis(skfem.MeshTri(), skfem.ElementTriP1()))


# ---- patch tests: a linear displacement field is reproduced exactly by the whole solver -------------------------
@settings(max_examples=8, deadline=None)
@given(st.sampled_from(list(MESHES)), st.integers(0, 2**16), st.booleans())
def test_patch_test(name, seed, bbar):
    """Boundary displacements of a linear field give that field inside, on distorted meshes, 2D and 3D."""
    mesh = MESHES[name]()
    basis = vector_basis(mesh)
    rng = np.random.default_rng(seed)
    G = 1e-3 * rng.standard_normal((mesh.dim(), mesh.dim()))
    exact = linear_field(basis, G, 1e-3 * rng.standard_normal(mesh.dim()))
    boundary = basis.get_dofs().all()  # every DOF on the boundary
    solver = Solver(basis, LinearElastic(200000.0, 0.3), [Dirichlet(boundary, exact[boundary])],
                    control=StepControl(initial=1.0, maximum=1.0), bbar=bbar)
    result = solver.run(progress=False)
    assert np.abs(result.u - exact).max() <= 1e-10 * np.abs(exact).max()
    stress = result.response.stress
    assert np.ptp(stress, axis=(0, 1)).max() <= 1e-7 * np.abs(stress).max()  # constant stress everywhere
    assert result.iterations[-1] == 1  # linear problem: one Newton iteration


def test_chunked_assembly_without_caches_is_identical(monkeypatch):
    """The memory-saving path (B rebuilt per chunk, one scatter per chunk) gives the same matrix."""
    import abrakit.fem.assembly as assembly

    kin = Kinematics.from_basis(vector_basis(MESHES["hex"]()), bbar=True)
    C = np.random.default_rng(5).standard_normal((kin.nel, kin.nqp, 6, 6))
    cached = Assembler(kin)
    monkeypatch.setattr(assembly, "CACHE_BYTES", 0)
    monkeypatch.setattr(assembly, "_CHUNK_ENTRIES", 5000)
    chunked = Assembler(kin)
    assert chunked._B is None and not chunked._one_scatter and chunked._chunk < kin.nel
    assert np.allclose(chunked.tangent_data(C), cached.tangent_data(C), rtol=1e-13, atol=1e-13)


@pytest.mark.parametrize("bbar", [False, True])
@pytest.mark.parametrize("name", list(MESHES))
def test_strain_and_forces_through_the_cached_b_equal_the_gradient_table(name, bbar):
    """With B cached the assembler computes eps = B u_e and int B^T sigma dV as one product each; they equal the
    kinematics' own sums over the gradient table (the path without cache) to round-off."""
    kin = Kinematics.from_basis(vector_basis(MESHES[name]()), bbar=bbar)
    asm = Assembler(kin)
    assert asm._small_strain_B
    rng = np.random.default_rng(7)
    u, S = rng.standard_normal(kin.ndof), rng.standard_normal((kin.nel, kin.nqp, 6))
    np.testing.assert_allclose(asm.strain(u), kin.strain(u), rtol=0, atol=1e-12 * np.abs(kin.strain(u)).max())
    np.testing.assert_allclose(asm.element_forces(S), kin.element_forces(S), rtol=0,
                               atol=1e-12 * np.abs(kin.element_forces(S)).max())
