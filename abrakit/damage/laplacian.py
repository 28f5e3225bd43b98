r"""Element Laplacian of Model I: a Taylor stencil over neighbour element centres (Ch. 6.4.1).

Model I keeps one damage function :math:`f_i` per element, located at the element centre :math:`\mathbf{x}_i`
(here: the mean of the element's nodes). The indicator function (6.64, 6.76) needs the Laplacian
:math:`\Lambda_f = \nabla^2 f` at every centre; it is reconstructed from the values at neighbouring centres.

**Taylor expansion (6.65).** Around the centre of element *i*, for every stencil member *j*,

.. math::

    \Delta f_{i,j} = f_j - f_i = \sum_k \partial_k f_i\, \Delta x_{j,k}
                     + \tfrac12 \sum_{k,p} \partial_k\partial_p f_i\, \Delta x_{j,k}\Delta x_{j,p},
    \qquad \Delta\mathbf{x}_j = \mathbf{x}_j - \mathbf{x}_i .

**Linear system (6.67)–(6.70).** Collecting the rows gives :math:`\Delta\mathbf{f}_i = \mathbf{D}\,\partial\mathbf{f}_i`
with the unknowns ordered as in (6.69) -- first derivatives, mixed second derivatives, unmixed second derivatives::

    1D: (f_x, f_xx)                               n = 2
    2D: (f_x, f_y, f_xy, f_xx, f_yy)              n = 5
    3D: (f_x, f_y, f_z, f_xy, f_xz, f_yz, f_xx, f_yy, f_zz)   n = 9

and the rows of :math:`\mathbf{D}` (6.70): :math:`D_{j,k} = \Delta x_{j,k}`,
:math:`D_{j,kp} = \Delta x_{j,k}\Delta x_{j,p}` (mixed), :math:`D_{j,kk} = \Delta x_{j,k}^2/2` (unmixed).

**Stencil.** The *n* members are the face neighbours (2 in 1D, 3 for triangles, 4 for quadrilaterals and
tetrahedra, 6 for hexahedra) plus extra elements from the vertex ring that close the system: the seed's rule
for quadrilaterals and hexahedra is one element per coordinate plane, "the closest ones located in diagonal
direction" (2D: 4 + 1; 3D: 6 + 3). The seed gives no rule for simplices (3 + 2, 4 + 5); there the extra members
are chosen greedily (row-pivoted QR): each next member is the close one adding the most new information.

**Neumann condition (6.44) by ghost centres.** A boundary facet contributes a ghost centre: the element centre
mirrored across the facet's plane, carrying the element's own value. Then :math:`\Delta f = 0` for that row,
which makes the reconstructed Taylor polynomial's normal derivative vanish at the foot of the perpendicular
from the centre to the facet.

**Operator (6.71)–(6.75).** :math:`\partial\mathbf{f}_i = \mathbf{D}^{-1}\Delta\mathbf{f}_i`; the rows of the unmixed
second derivatives form :math:`\mathbf{B}^{\nabla^2}` (6.72) and
:math:`(\Lambda_f)_i = \sum_l (\mathbf{B}^{\nabla^2}\Delta\mathbf{f}_i)_l` (6.74). Since :math:`\Delta\mathbf{f}_i`
is linear in the element values, all of this is one sparse matrix, precomputed once per mesh::

    lap = element_laplacian(mesh)      # once per mesh
    Lf = lap.matrix @ f                # every Newton step, Eq. (6.74)
    dL = lap.diagonal                  # d(Lambda_f)_i / d f_i, Eq. (6.75)

**Ill-conditioned stencils.** On unstructured, graded or distorted meshes the square system can be singular or
nearly so (collinear centres, missing neighbours on thin strips). Each system is solved in a dimensionless,
column-equilibrated form (increments divided by the mean face distance :math:`h_i`, columns scaled to unit norm),
so uniform grading and stretching cost nothing; its condition number is recorded, and where it exceeds
``max_condition`` (or the stencil cannot be completed) the element falls back to a weighted least-squares fit over
its 2-ring of vertex neighbours (boundary elements: plus the ghost centres of that 2-ring), with weights
:math:`\min(1, \rho_n/\rho_j)^{2q}` (:math:`\rho_n`: distance of the *n*-th nearest member; q = 3, or flatter
where that is ill-conditioned). A quadratic field is still reproduced exactly on interior elements (the
over-determined system is consistent). If even the fallback is ill-conditioned the construction stops with a
``ValueError`` naming the elements.

**Nonnegative fallback rows.** The least-squares fit gives good derivatives (``derivative_matrix``, ``gradient``,
``hessian``), but its Laplacian rows can carry negative off-diagonal weights (strips one element high with elements
8 times longer than high: -2.8 next to +11.5 on elements of unit length). The discrete Laplacian then loses the
M-matrix property -- the maximum principle :math:`\Lambda_f \le 0` wherever :math:`f_i` is a local maximum --
and oscillating damage fields are no longer smoothed. On fallback elements the rows of ``matrix`` are therefore
solved for directly: weights :math:`c_j \ge 0` on :math:`f_j - f_i` meeting the moment conditions that make the
row exact for every quadratic, :math:`\sum_j c_j\Delta\mathbf{x}_j = \mathbf{0}`,
:math:`\sum_j c_j \Delta x_{j,k}\Delta x_{j,p} = 2\delta_{kp}`, and among those the one minimising
:math:`\sum_j (\rho_j^3 c_j)^2` (dimensionless distances :math:`\rho_j`: close members preferred). This strictly
convex problem has one solution, so symmetric neighbourhoods give symmetric rows (a linear program would pick an
arbitrary vertex); it is solved as a small nonnegative least-squares problem (Lawson-Hanson), the moment conditions
weighted by 1e8 over the penalty, which meets them to roundoff. The 1-ring (with its ghosts) is tried before the
2-ring, so a uniform strip gets the classical reflecting 3-point stencil; ghosts of the element itself carry
:math:`f_i` and drop out of the row. Where neither ring admits a nonnegative exact row (slivers, whose Laplacian
needs members far along the sliver) the best nonnegative fit of the moments is kept and the element is marked in
``inexact``: there :math:`\Lambda_f` of a quadratic is off by O(:math:`|\nabla^2 f|`), never NaN. ``diagonal``
is the diagonal of this ``matrix``, i.e. the exact derivative of the operator applied.

**Accuracy.** Second derivatives from a Taylor fit lose two orders: on uniform grids the symmetric stencil cancels
the cubic terms and the error is O(h^2) (the classical 3/5/7-point Laplacian with reflecting walls); on irregular,
perturbed or simplex meshes it is O(h), exact for quadratics.

Deviations from the seed, all harmless for :math:`\Lambda_f`: (6.66) prints :math:`\Delta\mathbf{x}_j =
\mathbf{x}_i - \mathbf{x}_j`, inconsistent with (6.65); we use :math:`\mathbf{x}_j - \mathbf{x}_i` (only the sign of
the first derivatives depends on it). (6.75) sums :math:`-\mathbf{B}^{\nabla^2}\cdot\mathbf{1}` over all rows; a row
of the element's own ghost has :math:`\Delta f \equiv 0`, so its derivative is 0, not -1 -- ``diagonal`` is the
exact derivative of the operator actually applied.

The vertex rings, the choice of the extra members and the column equilibration are in
``abrakit.damage._laplacian_stencil``, the fallback (least-squares fit and nonnegative rows) in
``abrakit.damage._laplacian_fallback``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import skfem
from numpy.typing import ArrayLike

from abrakit.damage._laplacian_fallback import _fallback_members, _least_squares_fit, _nonnegative_rows, _with_rows
from abrakit.damage._laplacian_stencil import (
    _equilibrated,
    _padded_rows,
    _select_diagonal,
    _select_greedy,
    _vertex_adjacency,
)
from abrakit.validation import all_finite, check_finite, check_option, check_range, check_shape, number_arguments

#: Element families with a Taylor stencil: mesh class -> number of face neighbours.
SUPPORTED_MESHES = {
    skfem.MeshLine1: 2,
    skfem.MeshTri1: 3,
    skfem.MeshQuad1: 4,
    skfem.MeshTet1: 4,
    skfem.MeshHex1: 6,
}

_AXES = "xyz"



@number_arguments
def taylor_terms(dim: int) -> tuple[tuple[int, ...], ...]:
    """Unknowns of Eq. (6.69) in order: first ``(k,)``, mixed second ``(k, p)``, unmixed second ``(k, k)``."""
    first = [(k,) for k in range(dim)]
    mixed = [(k, p) for k in range(dim) for p in range(k + 1, dim)]
    unmixed = [(k, k) for k in range(dim)]
    return tuple(first + mixed + unmixed)


@number_arguments
def derivative_names(dim: int) -> tuple[str, ...]:
    """Names of the unknowns of Eq. (6.69), e.g. ``('f_x', 'f_y', 'f_xy', 'f_xx', 'f_yy')`` in 2D."""
    return tuple("f_" + "".join(_AXES[k] for k in term) for term in taylor_terms(dim))


def taylor_matrix(dx) -> np.ndarray:
    """Rows of the coefficient matrix D, Eq. (6.70), for increments ``dx`` of shape (..., dim) -> (..., n).

    ``D_jk = dx_k``, ``D_j,kp = dx_k dx_p`` (k < p), ``D_j,kk = dx_k**2 / 2``; units follow ``dx``.
    """
    dx = np.asarray(check_finite("dx", dx), dtype=float)
    columns = []
    for term in taylor_terms(dx.shape[-1]):
        if len(term) == 1:
            columns.append(dx[..., term[0]])
        elif term[0] != term[1]:
            columns.append(dx[..., term[0]] * dx[..., term[1]])
        else:
            columns.append(0.5 * dx[..., term[0]] ** 2)
    return np.stack(columns, axis=-1)


def _mesh_kind(mesh) -> int:
    """Number of face neighbours of the mesh's element type; clear errors for everything else."""
    if not isinstance(mesh, skfem.Mesh):
        raise TypeError(f"mesh must be a scikit-fem mesh (MeshLine1, MeshTri1, MeshQuad1, MeshTet1, MeshHex1), "
                        f"got {type(mesh).__name__}")
    for cls, n_faces in SUPPORTED_MESHES.items():
        if isinstance(mesh, cls):
            if mesh.p.shape[0] != mesh.dim():
                raise ValueError(f"mesh: {type(mesh).__name__} embedded in {mesh.p.shape[0]}D is not supported; "
                                 f"the Taylor stencil needs a {mesh.dim()}D mesh")
            if not all_finite(np.asarray(mesh.p, dtype=float)):
                raise ValueError("mesh: node coordinates must be finite (no NaN or infinity)")
            return n_faces
    names = ", ".join(cls.__name__ for cls in SUPPORTED_MESHES)
    raise TypeError(f"mesh: element Laplacian supports {names} (and their subclasses), got {type(mesh).__name__}")


def _at_least(name: str, value, low, *, integer: bool = False):
    """``value`` as a float (an int where ``integer``) if it is a finite real number >= ``low``; else ``TypeError``
    (not a real number) or ``ValueError`` naming ``name`` and the allowed range."""
    message = f"{name} must be {'an integer' if integer else 'a finite number'} >= {low:g}, got {value!r}"
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise TypeError(message)
    if not (np.isfinite(value) and value >= low and (not integer or value == int(value))):
        raise ValueError(message)
    return int(value) if integer else float(value)


def element_centres(mesh) -> np.ndarray:
    """Element centres x_i as the mean of the element's vertices, shape (nel, dim)."""
    return mesh.p[:, mesh.t].mean(axis=1).T


def face_neighbours(mesh) -> np.ndarray:
    """Element across each facet, shape (nel, faces per element); -1 where the facet is on the boundary."""
    facets = mesh.t2f.T
    first, second = mesh.f2t[0, facets], mesh.f2t[1, facets]
    own = np.arange(mesh.t.shape[1])[:, None]
    return np.where(first == own, second, first)


@number_arguments
def mirror_points(points: ArrayLike, facet_nodes: ArrayLike) -> np.ndarray:
    """Mirror ``points`` (m, dim) across the planes through facets with node coordinates (m, nodes, dim).

    The plane is fitted to the facet nodes (centroid and the least singular direction), so warped quadrilateral
    facets and unsorted node orders are handled; in 1D the facet is a point and the mirror is 2 x_b - x.
    """
    facet_nodes = np.asarray(facet_nodes, dtype=float)
    base = facet_nodes.mean(axis=1)
    normal = np.linalg.svd(facet_nodes - base[:, None, :])[2][:, -1, :]
    distance = np.einsum("md,md->m", points - base, normal)
    return points - 2.0 * distance[:, None] * normal


def ghost_centres(mesh):
    """Ghost centres of Eq. (6.44): each boundary facet's owner centre mirrored across the facet.

    Returns ``(facets, owner, points)``: the boundary facets (nb,), their owning elements (nb,) and the ghost points
    (nb, dim). A ghost carries its owner's value, so the reconstructed normal derivative vanishes on the boundary.
    """
    facets = mesh.boundary_facets()
    owner = mesh.f2t[0, facets]
    nodes = mesh.p[:, mesh.facets[:, facets]].transpose(2, 1, 0)
    return facets, owner, mirror_points(element_centres(mesh)[owner], nodes)


@dataclass(frozen=True, eq=False)
class ElementLaplacian:
    """Precomputed Taylor-stencil operators of one mesh (Eq. 6.65-6.75).

    ``matrix`` (nel, nel) gives the Laplacian at the element centres, ``Lambda_f = matrix @ f`` (Eq. 6.74), in
    units of f / length**2; ``derivative_matrix`` (nel * n, nel) gives all unknowns of Eq. (6.69), row
    ``i * n + l`` holding derivative ``l`` of element ``i``. ``condition`` is the condition number of the
    dimensionless, column-equilibrated system used for each element, ``fallback`` marks the elements solved by the
    least-squares fit over the 2-ring. On fallback elements the rows of ``matrix`` are the nonnegative Laplacian
    stencils (off-diagonal entries >= 0), not the unmixed sum of ``derivative_matrix``; ``inexact`` marks those
    whose ring admits no nonnegative stencil exact for quadratics (the best nonnegative fit is used there).
    """

    matrix: sp.csr_matrix
    derivative_matrix: sp.csr_matrix
    centres: np.ndarray
    condition: np.ndarray
    fallback: np.ndarray
    inexact: np.ndarray
    names: tuple[str, ...]

    def __call__(self, f) -> np.ndarray:
        """Lambda_f at every element centre, Eq. (6.74)."""
        return self.matrix @ self._values(f)

    def derivatives(self, f) -> np.ndarray:
        """All derivatives of Eq. (6.69) at every element centre, shape (nel, n), order as in ``names``."""
        return (self.derivative_matrix @ self._values(f)).reshape(len(self.centres), len(self.names))

    def gradient(self, f) -> np.ndarray:
        """Reconstructed gradient at every element centre, shape (nel, dim)."""
        dim = self.centres.shape[1]
        return self.derivatives(f)[:, :dim]

    def hessian(self, f) -> np.ndarray:
        """Reconstructed (symmetric) matrix of second derivatives at every element centre, shape (nel, dim, dim)."""
        dim = self.centres.shape[1]
        derivs = self.derivatives(f)
        out = np.zeros((len(derivs), dim, dim))
        for l, term in enumerate(taylor_terms(dim)):
            if len(term) == 2:
                out[:, term[0], term[1]] = out[:, term[1], term[0]] = derivs[:, l]
        return out

    @property
    def diagonal(self) -> np.ndarray:
        """(D Lambda_f)_i = d(Lambda_f)_i / d f_i of ``matrix``, Eq. (6.75) (own ghosts: Delta f = 0, no share)."""
        return self.matrix.diagonal()

    @property
    def n_fallback(self) -> int:
        """Number of elements whose square Taylor system was replaced by the least-squares fit."""
        return int(self.fallback.sum())

    def _values(self, f) -> np.ndarray:
        return check_shape("f", check_finite("f", f), (len(self.centres),))


def element_laplacian(
    mesh,
    *,
    max_condition: float = 1e4,
    selection: str = "auto",
    max_candidates: int = 16,
    monotone: bool = True,
) -> ElementLaplacian:
    """Precompute the element Laplacian of Model I on a scikit-fem mesh, Eq. (6.65)-(6.75).

    Parameters
    ----------
    mesh : skfem.MeshLine1, MeshTri1, MeshQuad1, MeshTet1 or MeshHex1 (or a subclass, e.g. MeshQuad2; only the
        vertices are used). Lengths in any unit; the Laplacian comes out per length squared.
    max_condition : condition number of the dimensionless, column-equilibrated Taylor system above which an
        element falls back to the weighted least-squares fit over its 2-ring (and above which that fit is refused);
        finite and >= 1, since no condition number is below 1.
    selection : how the extra (non-face) stencil members are chosen: ``"diagonal"`` (the seed's rule, one per
        coordinate plane; quadrilaterals and hexahedra), ``"greedy"`` (most new information, any element type) or
        ``"auto"`` (diagonal for quadrilaterals/hexahedra, greedy for simplices).
    max_candidates : the nearest this-many vertex neighbours are considered as extra members (an integer >= 1).
    monotone : on fallback elements use the nonnegative Laplacian rows (maximum principle; ``inexact`` where no
        nonnegative row is exact for quadratics); ``False`` keeps the signed least-squares rows, exact for
        quadratics on every interior element but possibly with negative off-diagonal weights.
    """
    n_faces = _mesh_kind(mesh)
    max_condition = _at_least("max_condition", max_condition, 1.0)     # no condition number is below 1
    check_option("selection", selection, ("auto", "diagonal", "greedy"))
    if not isinstance(monotone, bool):
        raise TypeError(f"monotone must be True or False, got {monotone!r}")
    max_candidates = _at_least("max_candidates", max_candidates, 1, integer=True)
    dim = mesh.dim()
    n_extra = len(taylor_terms(dim)) - n_faces
    is_simplex = isinstance(mesh, skfem.MeshTri1 | skfem.MeshTet1)
    if selection == "auto":
        selection = "greedy" if is_simplex else "diagonal"
    if selection == "diagonal" and is_simplex and n_extra > 0:
        raise ValueError(f"selection='diagonal' is the seed's rule for quadrilaterals and hexahedra (one extra "
                         f"element per plane); {type(mesh).__name__} needs {n_extra} extras: use 'greedy'")

    centres = element_centres(mesh)
    face_source, dx_face = _face_members(mesh, centres)
    length = np.linalg.norm(dx_face, axis=-1).mean(axis=1)           # local length scale h_i
    if np.any(length <= 0.0):
        raise ValueError(f"mesh: elements {np.nonzero(length <= 0.0)[0][:5]} have coincident neighbour centres")
    adjacency = _vertex_adjacency(mesh)
    extra_source, dx_extra = _extra_members(centres, face_source, dx_face / length[:, None, None], length, adjacency,
                                            n_extra, selection, max_candidates)

    # Square system (6.67) in dimensionless, column-equilibrated form: (D_hat S)(S^-1 d_hat) = Delta f.
    source = np.concatenate([face_source, extra_source], axis=1)
    dx_hat = np.concatenate([dx_face, dx_extra], axis=1) / length[:, None, None]
    scaled, scale, condition = _equilibrated(taylor_matrix(dx_hat))
    square = np.all(source >= 0, axis=1) & (condition <= max_condition)
    inverse = np.zeros(scaled.shape)
    inverse[square] = np.linalg.inv(scaled[square])
    blocks = [(np.nonzero(square)[0], source[square], scale[square, :, None] * inverse[square])]  # Eq. (6.71)

    fallback = ~square
    condition = condition.copy()
    inexact = np.zeros(len(centres), dtype=bool)
    if fallback.any():
        targets = np.nonzero(fallback)[0]
        _, ghost_owner, ghost_points = ghost_centres(mesh)
        sources, dx_fit, near = _fallback_members(ghost_owner, ghost_points, centres, length, adjacency, targets)
        rows = taylor_matrix(dx_fit)                                    # Eq. (6.70) of the fallback members
        weights, condition[fallback] = _least_squares_fit(targets, sources, dx_fit, rows, max_condition, condition)
        blocks.append((targets, sources, weights))
        if monotone:
            stencils, inexact[fallback] = _nonnegative_rows(sources, dx_fit, rows, near)

    derivative_matrix = _assemble(blocks, length, dim, len(centres))
    matrix = _unmixed_sum(derivative_matrix, dim)
    if monotone and fallback.any():
        matrix = _with_rows(matrix, targets, sources, stencils / length[targets, None] ** 2)
    return ElementLaplacian(
        matrix=matrix,
        derivative_matrix=derivative_matrix,
        centres=centres,
        condition=condition,
        fallback=fallback,
        inexact=inexact,
        names=derivative_names(dim),
    )


def _face_members(mesh, centres):
    """Face neighbours, or ghost centres (Eq. 6.44) across boundary facets: (source (nel, F), dx (nel, F, dim)).

    A ghost's source is the element itself (the ghost carries its owner's value).
    """
    elements = np.arange(len(centres))[:, None]
    neighbours = face_neighbours(mesh)
    source = np.where(neighbours >= 0, neighbours, elements)
    points = centres[source]
    facets, _, ghosts = ghost_centres(mesh)
    ghost_of_facet = np.zeros((mesh.facets.shape[1], centres.shape[1]))
    ghost_of_facet[facets] = ghosts
    boundary = neighbours < 0
    points[boundary] = ghost_of_facet[mesh.t2f.T[boundary]]
    return source, points - centres[:, None, :]


def _extra_members(centres, face_source, dx_face_hat, length, adjacency, n_extra, selection, max_candidates):
    """Extra stencil members from the vertex ring (not self, not a face neighbour): (source, dx), -1 if missing."""
    nel, dim = centres.shape
    if n_extra == 0:
        return np.zeros((nel, 0), dtype=np.int64), np.zeros((nel, 0, dim))
    candidates = _padded_rows(adjacency)
    valid = (candidates >= 0) & ~np.any(candidates[:, :, None] == face_source[:, None, :], axis=2)
    dx = centres[np.maximum(candidates, 0)] - centres[:, None, :]
    nearest = np.argsort(np.where(valid, np.linalg.norm(dx, axis=-1), np.inf), axis=1, kind="stable")
    nearest = nearest[:, :max_candidates]
    candidates = np.take_along_axis(candidates, nearest, axis=1)
    valid = np.take_along_axis(valid, nearest, axis=1)
    dx = np.take_along_axis(dx, nearest[..., None], axis=1)
    if selection == "diagonal":
        chosen = _select_diagonal(dx, valid, n_extra)
    else:
        dx_hat = dx / length[:, None, None]
        chosen = _select_greedy(taylor_matrix(dx_face_hat), taylor_matrix(dx_hat), dx_hat, valid, n_extra)
    found = chosen >= 0
    chosen = np.maximum(chosen, 0)
    source = np.where(found, np.take_along_axis(candidates, chosen, axis=1), -1)
    return source, np.where(found[..., None], np.take_along_axis(dx, chosen[..., None], axis=1), 0.0)


def _assemble(blocks, length, dim, nel) -> sp.csr_matrix:
    """Sparse derivative operator (nel * n, nel) from per-element weights (m, n, k) acting on Delta f_ij = f_j - f_i.

    The weights are dimensionless; first derivatives are divided by h_i and second derivatives by h_i**2.
    """
    order = np.array([len(term) for term in taylor_terms(dim)])
    n = len(order)
    rows, cols, vals = [], [], []
    for owner, source, weight in blocks:
        weight = weight / length[owner, None, None] ** order[None, :, None]
        row = np.broadcast_to(owner[:, None, None] * n + np.arange(n)[None, :, None], weight.shape)
        used = np.broadcast_to((source >= 0)[:, None, :], weight.shape)
        rows += [row[used], row[used]]
        cols += [np.broadcast_to(source[:, None, :], weight.shape)[used],
                 np.broadcast_to(owner[:, None, None], weight.shape)[used]]
        vals += [weight[used], -weight[used]]                          # +w on f_j, -w on f_i
    matrix = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(nel * n, nel))
    matrix.sum_duplicates()
    matrix.eliminate_zeros()                                           # own ghosts cancel exactly
    return matrix


def _unmixed_sum(derivative_matrix, dim) -> sp.csr_matrix:
    """Lambda_f = sum of the unmixed second derivatives, Eq. (6.72)-(6.74), as one (nel, nel) matrix."""
    n = len(taylor_terms(dim))
    nel = derivative_matrix.shape[0] // n
    unmixed = np.arange(n - dim, n)
    rows = np.repeat(np.arange(nel), dim)
    cols = (np.arange(nel)[:, None] * n + unmixed).ravel()
    pick = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(nel, nel * n))
    return (pick @ derivative_matrix).tocsr()



@number_arguments
def unit_cube_mesh(kind: str, n: int, *, grading: str = "none", perturb: float = 0.0, seed: int = 0):
    """Tensor-product test mesh of the unit interval/square/cube with ``n`` cells per side (tests, demo, benchmark).

    kind: "line", "tri", "quad", "tet" or "hex". grading: "none", "side" (x -> x**2: refined towards x = 0) or
    "corner" (every axis: refined towards the origin). perturb: nodes move by up to this fraction of 1/n in each
    coordinate; a node on a wall keeps that coordinate, so it slides along the wall and the boundary stays straight.
    """
    meshes = {"line": skfem.MeshLine1, "tri": skfem.MeshTri, "quad": skfem.MeshQuad, "tet": skfem.MeshTet,
              "hex": skfem.MeshHex}
    check_option("kind", kind, meshes)
    check_option("grading", grading, ("none", "side", "corner"))
    check_range("perturb", perturb, 0.0, 0.5, high_open=True)
    if isinstance(n, bool) or int(n) != n or n < 1:
        raise ValueError(f"n must be a positive integer, got {n!r}")
    dim = {"line": 1, "tri": 2, "quad": 2, "tet": 3, "hex": 3}[kind]
    axes = [np.linspace(0.0, 1.0, int(n) + 1) for _ in range(dim)]
    if grading == "side":
        axes[0] = axes[0] ** 2
    elif grading == "corner":
        axes = [a**2 for a in axes]
    mesh = meshes[kind].init_tensor(*axes)
    if perturb:
        movable = (mesh.p > 0.0) & (mesh.p < 1.0)
        shift = np.random.default_rng(seed).uniform(-perturb / n, perturb / n, mesh.p.shape)
        mesh = type(mesh)(mesh.p + movable * shift, mesh.t)
    return mesh
