"""Element Laplacian of Model I (Eq. 6.44, 6.65-6.75): exactness, Neumann ghosts, convergence, fallback, errors."""

import numpy as np
import pytest
import skfem
from hypothesis import given, settings
from hypothesis import strategies as st

from abrakit.damage import element_laplacian, face_neighbours
from abrakit.damage.laplacian import derivative_names, ghost_centres, mirror_points, taylor_matrix, unit_cube_mesh

DIM = {"line": 1, "tri": 2, "quad": 2, "tet": 3, "hex": 3}


def random_quadratic(dim, seed):
    """f(x) = a + b.x + x.Q.x with its gradient and Hessian (Q symmetric)."""
    rng = np.random.default_rng(seed)
    a, b, Q = rng.normal(), rng.normal(size=dim), rng.normal(size=(dim, dim))
    Q = Q + Q.T

    def f(x):
        return a + x @ b + np.einsum("ik,kl,il->i", x, Q, x)

    return f, lambda x: b + 2.0 * x @ Q, 2.0 * Q


def interior(mesh):
    return np.all(face_neighbours(mesh) >= 0, axis=1)


def walls_of_boundary_facets(mesh):
    """For each boundary facet: index k and value (0 or 1) of the wall x_k = value it lies on."""
    facets, owner, _ = ghost_centres(mesh)
    nodes = mesh.p[:, mesh.facets[:, facets]]                        # (dim, nodes, nb)
    on = np.all(np.isclose(nodes, 0.0), axis=1) | np.all(np.isclose(nodes, 1.0), axis=1)
    assert np.all(on.sum(axis=0) == 1), "every boundary facet lies on exactly one wall"
    k = np.argmax(on, axis=0)
    return facets, owner, k, nodes[k, 0, np.arange(len(facets))]


# --- Eq. (6.69), (6.70): the Taylor system -------------------------------------------------------------------


def test_taylor_matrix_rows_follow_eq_6_70():
    a, b, c = 0.3, -1.2, 2.0
    assert np.allclose(taylor_matrix([[a, b, c]])[0], [a, b, c, a * b, a * c, b * c, a * a / 2, b * b / 2, c * c / 2])
    assert np.allclose(taylor_matrix([[a, b]])[0], [a, b, a * b, a * a / 2, b * b / 2])
    assert np.allclose(taylor_matrix([[a]])[0], [a, a * a / 2])
    assert derivative_names(2) == ("f_x", "f_y", "f_xy", "f_xx", "f_yy")
    assert derivative_names(3)[3:] == ("f_xy", "f_xz", "f_yz", "f_xx", "f_yy", "f_zz")


@settings(max_examples=30, deadline=None)
@given(dim=st.integers(1, 3), seed=st.integers(0, 10_000))
def test_taylor_row_times_derivatives_is_the_increment_of_a_quadratic(dim, seed):
    """Eq. (6.65) is exact for quadratics: D(dx) . d f(x) = f(x + dx) - f(x)."""
    f, grad, hess = random_quadratic(dim, seed)
    rng = np.random.default_rng(seed + 1)
    x, dx = rng.normal(size=(1, dim)), rng.normal(size=(5, dim))
    terms = [(k,) for k in range(dim)] + [(k, p) for k in range(dim) for p in range(k + 1, dim)]
    terms += [(k, k) for k in range(dim)]
    derivs = np.array([grad(x)[0][t[0]] if len(t) == 1 else hess[t] for t in terms])
    assert np.allclose(taylor_matrix(dx) @ derivs, f(x + dx) - f(x), rtol=1e-12, atol=1e-12)


# --- exactness on quadratic fields --------------------------------------------------------------------------

CASES = [(kind, grading, perturb) for kind in ("line", "tri", "quad", "tet", "hex")
         for grading, perturb in (("none", 0.0), ("side", 0.0), ("corner", 0.0), ("none", 0.25))]


@pytest.mark.parametrize(("kind", "grading", "perturb"), CASES)
def test_interior_laplacian_gradient_and_hessian_of_quadratics_are_exact(kind, grading, perturb):
    n = {1: 12, 2: 8, 3: 4}[DIM[kind]]
    mesh = unit_cube_mesh(kind, n, grading=grading, perturb=perturb if kind not in ("tri", "tet") else 0.2)
    lap = element_laplacian(mesh)
    assert lap.n_fallback == 0                                        # healthy meshes need no fallback
    f, grad, hess = random_quadratic(DIM[kind], seed=7)
    x, inside = lap.centres, interior(mesh)
    assert inside.sum() > 0
    scale = np.abs(hess).max()
    assert np.allclose(lap(f(x))[inside], np.trace(hess), rtol=0, atol=1e-10 * scale)
    assert np.allclose(lap.gradient(f(x))[inside], grad(x)[inside], rtol=0, atol=1e-10 * scale)
    assert np.allclose(lap.hessian(f(x))[inside], hess, rtol=0, atol=1e-10 * scale)


@pytest.mark.parametrize(("kind", "grading", "perturb"), CASES)
def test_boundary_elements_exact_for_quadratics_symmetric_about_their_walls(kind, grading, perturb):
    """f = a + sum q_k x_k**2 has zero normal derivative on the walls x_k = 0: mirrored ghosts reproduce it exactly.

    Every element whose boundary facets all lie on such walls (and every interior element) gets Lambda_f = 2 sum q_k.
    """
    dim = DIM[kind]
    n = {1: 12, 2: 8, 3: 4}[dim]
    mesh = unit_cube_mesh(kind, n, grading=grading, perturb=perturb if kind not in ("tri", "tet") else 0.2)
    lap = element_laplacian(mesh)
    q = np.array([1.5, -0.7, 2.2])[:dim]
    f = 0.3 + lap.centres**2 @ q
    _, owner, _, value = walls_of_boundary_facets(mesh)
    far_wall = np.zeros(mesh.t.shape[1], dtype=bool)
    far_wall[owner[value == 1.0]] = True
    near_wall_only = ~far_wall & ~interior(mesh)
    assert near_wall_only.sum() > 0
    assert np.allclose(lap(f)[~far_wall], 2.0 * q.sum(), rtol=0, atol=1e-10 * np.abs(q).max())


def test_strongly_graded_mesh_is_exact_to_roundoff():
    """Cells from 1e-4 to 0.2: exact up to the unavoidable cancellation eps |f| / h**2 of each element."""
    s = np.concatenate([[0.0], np.geomspace(1e-4, 1.0, 30)])
    mesh = skfem.MeshQuad.init_tensor(s, s)
    lap = element_laplacian(mesh)
    f, _, hess = random_quadratic(2, seed=3)
    h = np.ptp(mesh.p[:, mesh.t], axis=1).min(axis=0)                # smallest side of each cell
    error = np.abs(lap(f(lap.centres)) - np.trace(hess))[interior(mesh)]
    bound = 1e-12 * (np.abs(np.trace(hess)) + np.abs(f(lap.centres)).max() / h**2)[interior(mesh)]
    assert np.all(error <= bound)
    assert lap.condition.max() < 10.0                                # equilibration makes grading harmless


@settings(max_examples=20, deadline=None)
@given(shear=st.floats(-2.0, 2.0), stretch=st.floats(0.2, 5.0), angle=st.floats(0.0, 2 * np.pi),
       seed=st.integers(0, 10_000))
def test_exact_under_affine_maps_of_a_perturbed_mesh(shear, stretch, angle, seed):
    """Quadratics stay quadratics under affine maps, so interior exactness holds on any affinely mapped mesh."""
    mesh = unit_cube_mesh("quad", 6, perturb=0.25, seed=seed)
    c, s = np.cos(angle), np.sin(angle)
    A = np.array([[c, -s], [s, c]]) @ np.array([[stretch, shear], [0.0, 1.0]])
    mapped = skfem.MeshQuad(A @ mesh.p + np.array([[3.0], [-1.0]]), mesh.t)
    lap = element_laplacian(mapped)
    f, _, hess = random_quadratic(2, seed)
    inside = interior(mapped)
    assert np.allclose(lap(f(lap.centres))[inside], np.trace(hess), rtol=0, atol=1e-9 * np.abs(hess).max())


def test_translation_invariance_and_length_scaling():
    mesh = unit_cube_mesh("tri", 6, perturb=0.2)
    lap = element_laplacian(mesh)
    moved = element_laplacian(skfem.MeshTri(mesh.p + 10.0, mesh.t))
    scaled = element_laplacian(skfem.MeshTri(3.0 * mesh.p, mesh.t))
    assert abs(lap.matrix - moved.matrix).max() < 1e-9 * abs(lap.matrix).max()
    assert abs(lap.matrix - 9.0 * scaled.matrix).max() < 1e-12 * abs(lap.matrix).max()


def test_quadratic_meshes_use_their_vertices():
    mesh = skfem.MeshQuad().refined(2)
    assert abs(element_laplacian(skfem.MeshQuad2.from_mesh(mesh)).matrix - element_laplacian(mesh).matrix).max() == 0


# --- Neumann condition (6.44) by ghost centres ---------------------------------------------------------------


@pytest.mark.parametrize("kind", ["line", "tri", "quad", "tet", "hex"])
def test_ghosts_give_zero_normal_gradient_at_the_boundary(kind):
    """For ANY field, each boundary element's Taylor polynomial p has dp/dn = 0 at the foot of the perpendicular
    from its centre to the boundary facet (the mirror plane). Checked against the wall geometry, independently of
    the module's facet normals."""
    dim = DIM[kind]
    mesh = unit_cube_mesh(kind, {1: 9, 2: 7, 3: 3}[dim], perturb=0.2)
    lap = element_laplacian(mesh)
    f = np.random.default_rng(1).normal(size=mesh.t.shape[1])
    grad, hess = lap.gradient(f), lap.hessian(f)
    _, owner, k, value = walls_of_boundary_facets(mesh)
    centre = lap.centres[owner]
    foot = centre.copy()
    foot[np.arange(len(owner)), k] = value
    normal_gradient = (grad[owner] + np.einsum("bij,bj->bi", hess[owner], foot - centre))[np.arange(len(owner)), k]
    size = np.abs(grad[owner]).max() + np.abs(hess[owner]).max()
    assert np.abs(normal_gradient).max() < 1e-10 * size
    assert np.abs(grad[owner][np.arange(len(owner)), k]).max() > 1e-3 * size   # not trivially zero at the centre


@pytest.mark.parametrize("kind", ["line", "quad", "hex"])
def test_structured_laplacian_is_the_symmetric_neumann_five_point_operator(kind):
    """On a uniform grid Lambda_f is the classical 3/5/7-point Laplacian with reflecting walls: rows sum to zero
    (Lambda of a constant is 0), L is symmetric and its columns sum to zero (discrete divergence theorem with
    df/dn = 0: sum_i Lambda_f,i = 0 for every f). The diagonal (Eq. 6.75) is -(number of non-ghost faces)/h**2."""
    dim = DIM[kind]
    n = {1: 10, 2: 6, 3: 4}[dim]
    mesh = unit_cube_mesh(kind, n)
    L = element_laplacian(mesh).matrix.toarray()
    assert np.abs(L.sum(axis=1)).max() < 1e-10 * n**2
    assert np.abs(L.sum(axis=0)).max() < 1e-10 * n**2
    assert np.abs(L - L.T).max() < 1e-10 * n**2
    real_faces = (face_neighbours(mesh) >= 0).sum(axis=1)
    assert np.allclose(np.diag(L), -real_faces * n**2)
    # Seed's Eq. (6.75) counting every stencil row would give -2 dim n**2 on the boundary too.
    assert np.any(real_faces < 2 * dim)


def test_mirror_points_across_warped_and_unsorted_facets():
    rng = np.random.default_rng(0)
    points = rng.normal(size=(4, 3))
    square = np.array([[0, 0, 1.0], [1, 0, 1.0], [1, 1, 1.0], [0, 1, 1.0]])
    facets = np.stack([square, square[[0, 2, 1, 3]], square, square])
    facets[3, :, 2] += [0.01, -0.01, 0.01, -0.01]                    # slightly warped quadrilateral
    mirrored = mirror_points(points, facets)
    assert np.allclose(mirrored[:3, :2], points[:3, :2])
    assert np.allclose(mirrored[:3, 2], 2.0 - points[:3, 2])
    assert np.allclose(mirror_points(mirrored, facets), points)       # an involution
    assert np.allclose(mirror_points(np.array([[0.3]]), np.array([[[1.0]]])), [[1.7]])   # 1D: a point facet


# --- convergence on a smooth Neumann field -----------------------------------------------------------------


def cos_field_errors(kind, sizes, perturb=0.0):
    """Max and rms error of Lambda_f for f = prod cos(pi x_k) (df/dn = 0 on every wall of the unit cube)."""
    out = []
    for n in sizes:
        mesh = unit_cube_mesh(kind, n, perturb=perturb)
        lap = element_laplacian(mesh)
        f = np.prod(np.cos(np.pi * lap.centres), axis=1)
        error = lap(f) + DIM[kind] * np.pi**2 * f
        out.append((np.abs(error).max(), np.sqrt(np.mean(error**2))))
    return np.array(out)


@pytest.mark.parametrize(("kind", "sizes"), [("line", (16, 32, 64)), ("quad", (16, 32, 64)), ("hex", (8, 16))])
def test_second_order_convergence_on_structured_meshes_including_boundary(kind, sizes):
    errors = cos_field_errors(kind, sizes)
    rates = np.log2(errors[:-1, 0] / errors[1:, 0]) / np.log2(np.array(sizes[1:]) / sizes[:-1])
    assert np.all(rates > 1.9), rates


@pytest.mark.parametrize("kind", ["tri", "quad"])
def test_first_order_convergence_on_irregular_meshes(kind):
    """Without symmetric stencils the cubic Taylor terms do not cancel: the rms error falls like h (not h**2)."""
    errors = cos_field_errors(kind, (8, 16, 32, 64), perturb=0.2)
    rates = np.log2(errors[:-1, 1] / errors[1:, 1])
    assert np.all(rates > 0.85), rates
    assert errors[-1, 1] < 0.06 * errors[0, 1] * 8                     # and the errors are small in absolute terms


# --- ill-conditioned stencils: detection and least-squares fallback ----------------------------------------


def test_thin_strip_without_diagonal_neighbours_falls_back():
    """One row of quadrilaterals: no element has a diagonal neighbour, the 5x5 system cannot be closed."""
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0.0, 4.0, 17), np.array([0.0, 0.25]))
    lap = element_laplacian(mesh)
    assert lap.n_fallback == mesh.t.shape[1]
    assert np.all(lap.condition < 1e4)
    x = lap.centres[:, 0]
    away_from_ends = (x > 0.8) & (x < 3.2)                           # ends: f is not symmetric about x = 0, 4
    assert np.allclose(lap(1.0 + 2.0 * x - 0.75 * x**2)[away_from_ends], -1.5, rtol=0, atol=1e-10)


@pytest.mark.parametrize("shear", [1.0, 50.0])
def test_collinear_or_sliver_stencils_fall_back_and_stay_exact(shear):
    """Shear 1: the corner elements' only diagonal candidate is collinear with the centre (singular 5x5 system).
    Shear 50: sliver parallelograms, condition > 1e4. Both are detected and fitted over the 2-ring instead; the
    signed least-squares rows (``monotone=False``) are exact for quadratics on every interior element."""
    mesh = unit_cube_mesh("quad", 8)
    p = mesh.p.copy()
    p[0] += shear * p[1]
    mesh = type(mesh)(p, mesh.t)
    lap = element_laplacian(mesh, monotone=False)
    assert lap.n_fallback >= 2
    assert np.all(lap.condition[lap.fallback] <= 1e4)
    f, _, hess = random_quadratic(2, seed=5)
    values = f(lap.centres)
    inside = interior(mesh)
    assert np.any(lap.fallback & inside) or shear == 1.0
    scale = np.abs(values).max() * 64.0                               # |f| / h**2: roundoff level
    assert np.allclose(lap(values)[inside], np.trace(hess), rtol=0, atol=1e-12 * scale)
    assert not lap.inexact.any()


@pytest.mark.parametrize("shear", [1.0, 50.0])
def test_monotone_sliver_rows_are_exact_where_possible_and_flagged_elsewhere(shear):
    """The default nonnegative rows on the same meshes: gradient and Hessian (least-squares fit) stay exact for
    quadratics on interior elements; the Laplacian too where the ring admits a nonnegative exact row. The shear-50
    slivers would need members ~50 cells away along the sliver, so there they are flagged ``inexact``: error
    O(|Hessian|), not O(|f| / h**2)."""
    mesh = unit_cube_mesh("quad", 8)
    p = mesh.p.copy()
    p[0] += shear * p[1]
    mesh = type(mesh)(p, mesh.t)
    lap = element_laplacian(mesh)
    f, grad, hess = random_quadratic(2, seed=5)
    values = f(lap.centres)
    inside = interior(mesh)
    scale = np.abs(values).max() * 64.0
    assert np.allclose(lap.hessian(values)[inside], hess, rtol=0, atol=1e-12 * scale)
    assert np.allclose(lap.gradient(values)[inside], grad(lap.centres)[inside], rtol=0, atol=1e-12 * scale)
    exact = inside & ~lap.inexact
    assert np.allclose(lap(values)[exact], np.trace(hess), rtol=0, atol=1e-12 * scale)
    assert np.array_equal(lap.inexact, lap.fallback & (shear == 50.0))
    assert np.abs(lap(values) - np.trace(hess))[inside].max() < 2.0 * np.abs(hess).max()
    L = lap.matrix.toarray()
    rows = lap.fallback
    assert np.all((L - np.diag(np.diag(L)))[rows] >= -1e-12 * np.abs(np.diag(L)).max())


def test_forced_fallback_keeps_interior_exactness_and_smooth_accuracy():
    mesh = unit_cube_mesh("tri", 16, perturb=0.2)
    normal, forced = element_laplacian(mesh), element_laplacian(mesh, max_condition=8.0)
    assert normal.n_fallback == 0 < forced.n_fallback < mesh.t.shape[1]
    f, _, hess = random_quadratic(2, seed=11)
    inside = interior(mesh)
    assert np.allclose(forced(f(forced.centres))[inside], np.trace(hess), atol=1e-9)
    smooth = np.prod(np.cos(np.pi * forced.centres), axis=1)
    exact = -2.0 * np.pi**2 * smooth
    assert np.abs(forced(smooth) - exact).max() < 1.5 * np.abs(normal(smooth) - exact).max()


def vertex_rings(mesh, elements, rings):
    """Mask of the elements within ``rings`` vertex rings of ``elements`` (mask or indices)."""
    nel = mesh.t.shape[1]
    incidence = np.zeros((mesh.p.shape[1], nel), dtype=bool)
    incidence[mesh.t, np.arange(nel)] = True
    mask = np.zeros(nel, dtype=bool)
    mask[elements] = True
    for _ in range(rings):
        mask = np.any(incidence[np.any(incidence[:, mask], axis=1)], axis=0)
    return mask


def off_diagonal(matrix):
    L = matrix.toarray()
    return L - np.diag(np.diag(L)), np.abs(np.diag(L)).max()


def wall_symmetric_quadratic(lap, q):
    """f = 0.3 + sum q_k x_k**2 (zero normal derivative on the walls x_k = 0) and its Laplacian 2 sum q_k."""
    return 0.3 + lap.centres**2 @ q, 2.0 * np.sum(q)


def away_from_far_walls(mesh):
    """Elements whose fallback ring (1- and 2-ring ghosts) sees no wall x_k = 1 (or the strips' far ends)."""
    facets, owner, _ = ghost_centres(mesh)
    nodes = mesh.p[:, mesh.facets[:, facets]]
    top = mesh.p.max(axis=1)[:, None, None]
    far = np.any(np.all(np.isclose(nodes, top) & (top > 0.5), axis=1), axis=0)
    return ~vertex_rings(mesh, owner[far], 2)


ASPECT_8 = {   # one element high, elements 8 times longer than high: no diagonal neighbours, every element falls back
    "quad strip": lambda: skfem.MeshQuad.init_tensor(np.linspace(0.0, 8.0, 9), np.array([0.0, 0.125])),
    "hex plate": lambda: skfem.MeshHex.init_tensor(np.linspace(0.0, 8.0, 9), np.linspace(0.0, 8.0, 9),
                                                   np.array([0.0, 0.125])),
}


@pytest.mark.parametrize("name", ASPECT_8)
def test_fallback_rows_on_aspect_8_strips_are_nonnegative_and_exact(name):
    """M-matrix rows (discrete maximum principle): L_ij >= 0 off the diagonal and rows summing to zero, so at a
    local maximum Lambda_f <= 0. The 2-ring least-squares fit gave L_ij down to -2.78 (quad strip, next to +11.5)
    and -3.61 (hex plate). On the uniform strip the row is the classical reflecting 3-point stencil."""
    mesh = ASPECT_8[name]()
    lap = element_laplacian(mesh)
    assert lap.n_fallback == mesh.t.shape[1] and not lap.inexact.any()
    off, scale = off_diagonal(lap.matrix)
    assert off.min() >= -1e-12 * scale
    assert np.abs(lap.matrix.sum(axis=1)).max() <= 1e-12 * scale
    f, laplacian = wall_symmetric_quadratic(lap, np.append([1.5, -0.7][:mesh.dim() - 1], 0.0))   # flat across
    check = away_from_far_walls(mesh)
    assert check.sum() >= 3
    assert np.allclose(lap(f)[check], laplacian, rtol=0, atol=1e-10 * scale)
    if mesh.dim() == 2:
        L = lap.matrix.toarray()
        for i in range(2, 6):
            assert np.allclose(L[i, i - 1:i + 2], [1.0, -2.0, 1.0], rtol=0, atol=1e-12)
            assert np.count_nonzero(L[i]) == 3


FORCED = [("tet", 4, "none", 0.2, 20.0), ("quad", 8, "none", 0.25, 3.0), ("hex", 4, "side", 0.0, 6.0)]


@pytest.mark.parametrize(("kind", "n", "grading", "perturb", "max_condition"), FORCED)
def test_nonnegative_fallback_rows_stay_exact_for_quadratics(kind, n, grading, perturb, max_condition):
    """Perturbed and graded meshes with the fallback forced (low max_condition): the rows are nonnegative (the
    least-squares fit gave -8.9 on the tetrahedra, -15.8 on the graded hexahedra) and still exact for every
    quadratic on interior elements and for wall-symmetric quadratics on the others."""
    mesh = unit_cube_mesh(kind, n, grading=grading, perturb=perturb)
    lap = element_laplacian(mesh, max_condition=max_condition)
    assert lap.n_fallback > 0 and not lap.inexact.any()
    off, scale = off_diagonal(lap.matrix)
    assert off[lap.fallback].min() >= -1e-12 * scale
    f, _, hess = random_quadratic(mesh.dim(), seed=4)
    values = f(lap.centres)
    inside = interior(mesh) & lap.fallback
    assert inside.any() or kind == "hex"
    assert np.allclose(lap(values)[inside], np.trace(hess), rtol=0, atol=1e-12 * np.abs(values).max() * scale)
    symmetric, laplacian = wall_symmetric_quadratic(lap, np.array([1.5, -0.7, 2.2])[:mesh.dim()])
    check = lap.fallback & away_from_far_walls(mesh)
    assert check.any()
    assert np.allclose(lap(symmetric)[check], laplacian, rtol=0, atol=1e-10 * scale)


@pytest.mark.parametrize("mesh", [ASPECT_8["quad strip"](), unit_cube_mesh("tet", 4, perturb=0.2)])
def test_diagonal_is_the_derivative_of_the_applied_laplacian(mesh):
    """Eq. (6.75): d(Lambda_f)_i / d f_i by finite differences of lap(f) (linear in f: exact up to roundoff)."""
    lap = element_laplacian(mesh, max_condition=20.0)
    assert lap.n_fallback > 0
    f = np.random.default_rng(2).normal(size=mesh.t.shape[1])
    base, step = lap(f), 1e-3
    derivative = np.array([(lap(f + step * (np.arange(f.size) == i)) - base)[i] / step for i in range(f.size)])
    assert np.allclose(lap.diagonal, derivative, rtol=1e-8, atol=1e-8 * np.abs(lap.diagonal).max())


def test_hopeless_stencil_is_stopped_with_a_clear_message():
    with pytest.raises(ValueError, match="singular or ill-conditioned"):
        element_laplacian(skfem.MeshQuad())                           # one element: only its four ghosts


# --- input checks --------------------------------------------------------------------------------------------


def test_unsupported_meshes_and_options_raise():
    with pytest.raises(TypeError, match="scikit-fem mesh"):
        element_laplacian(np.zeros((2, 3)))
    with pytest.raises(TypeError, match="MeshWedge1"):
        element_laplacian(skfem.MeshWedge1())
    surface = skfem.MeshTri(np.vstack([skfem.MeshTri().p, np.zeros(4)]), skfem.MeshTri().t)
    with pytest.raises(ValueError, match="embedded in 3D"):
        element_laplacian(surface)
    mesh = unit_cube_mesh("quad", 4)
    with pytest.raises(ValueError, match="selection"):
        element_laplacian(mesh, selection="nearest")
    with pytest.raises(ValueError, match="use 'greedy'"):
        element_laplacian(unit_cube_mesh("tri", 4), selection="diagonal")
    with pytest.raises(ValueError, match="max_condition"):
        element_laplacian(mesh, max_condition=0.0)
    with pytest.raises(ValueError, match="max_candidates"):
        element_laplacian(mesh, max_candidates=0)
    with pytest.raises(TypeError, match="monotone"):
        element_laplacian(mesh, monotone="yes")
    with pytest.raises(ValueError, match="kind"):
        unit_cube_mesh("wedge", 4)
    with pytest.raises(ValueError, match="perturb"):
        unit_cube_mesh("quad", 4, perturb=0.5)
    lap = element_laplacian(mesh)
    with pytest.raises(ValueError, match="f must have shape"):
        lap(np.ones(3))
    with pytest.raises(ValueError, match="f must be finite"):
        lap(np.full(mesh.t.shape[1], np.nan))


@pytest.mark.parametrize(("name", "value", "error", "allowed"), [
    ("max_candidates", float("nan"), ValueError, "an integer >= 1"),
    ("max_candidates", float("inf"), ValueError, "an integer >= 1"),
    ("max_candidates", 2.5, ValueError, "an integer >= 1"),
    ("max_candidates", "abc", TypeError, "an integer >= 1"),
    ("max_candidates", None, TypeError, "an integer >= 1"),
    ("max_condition", float("nan"), ValueError, "a finite number >= 1"),
    ("max_condition", float("inf"), ValueError, "a finite number >= 1"),
    ("max_condition", 0.5, ValueError, "a finite number >= 1"),
    ("max_condition", "abc", TypeError, "a finite number >= 1"),
    ("max_condition", None, TypeError, "a finite number >= 1"),
])
def test_bad_numbers_are_refused_at_the_entry_by_name_and_range(name, value, error, allowed):
    with pytest.raises(error, match=f"{name} must be {allowed}"):
        element_laplacian(unit_cube_mesh("quad", 4), **{name: value})


def test_non_finite_node_coordinates_are_refused():
    mesh = unit_cube_mesh("quad", 4)
    p = mesh.p.copy()
    p[0, 7] = np.nan
    with pytest.raises(ValueError, match="mesh: node coordinates must be finite"):
        element_laplacian(type(mesh)(p, mesh.t))


def test_greedy_selection_also_works_on_quadrilaterals():
    mesh = unit_cube_mesh("quad", 8, perturb=0.25)
    lap = element_laplacian(mesh, selection="greedy")
    f, _, hess = random_quadratic(2, seed=2)
    assert lap.n_fallback == 0
    assert np.allclose(lap(f(lap.centres))[interior(mesh)], np.trace(hess), atol=1e-9)
