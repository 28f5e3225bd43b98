"""Volume audit of a scratch: where the displaced material went, closed to round-off at any step.

With the vector field (0, y, 0), whose divergence is 1, the divergence theorem on the deformed body gives its
volume as a boundary integral, V = ∮ y n_y da, and on the undeformed one V_0 = ∮ Y N_y dA. Hence

    ∫ (J − 1) dV_0  =  Σ_faces [ ∫ y n_y da − ∫ Y N_y dA ],        J = det F = det(I + ∇u).

On the top face (Y = 0) the integrand y n_y da is the signed height of the deformed surface over the plane y = 0
times its projected area, so splitting its quadrature points by the sign of y (below/above the original surface)
and by their position behind or ahead of the tip's apex (z ≤ z_tip or z > z_tip) partitions the top's
contribution into

    groove    volume below y = 0 behind the apex (the groove and the rear half of the imprint), counted > 0
    shoulders volume above y = 0 behind the apex (the side ridges)
    prow      volume above y = 0 ahead of the apex (the bow pushed along)
    sink      volume below y = 0 ahead of the apex (the front of the imprint and any sinking-in), counted > 0

and the other faces give ``faces``, the volume that left the block through its sides, bottom and ends (zero where
they are fixed or slide in their own plane, as the symmetry plane does). The budget

    shoulders + prow + faces + removed − groove − sink = ∫ (J − 1) dV_0                       (closes exactly)

holds for any displacement field, so ``residual`` measures round-off only. ``removed`` is the undeformed volume
∫ dV_0 of the elements counted as removed (eroded, or Model II's damage at its cap): the material that left as
wear debris, however the residual stiffness of an eroded element lets its neighbours squeeze it. Removed material
above y = 0 leaves the shoulders (behind the apex) or the prow (ahead of it) with its current volume ∫ J dV_0;
removed material below y = 0 deepens the groove or the sink; each split is by the quadrature points' current
positions; ``volume_change`` is then ∫ (J − 1) dV_0 over the material that remains, so the identity above stays
exact and Eq. (8.5) in these terms, f_ab = 1 − shoulders/groove, counts removed material as worn. Without removal
``removed`` is zero and the other terms are those of a plowing scratch. It is exact for trilinear hexahedra on
an axis-parallel reference mesh: det(∂x/∂ξ) and y (x_ξ × x_η)_y are polynomials of degree ≤ 2 in each reference
coordinate, which the 2 × 2 (× 2) Gauss rule integrates exactly.

Physics: plastic flow conserves volume, so at finite strain ∫ (J − 1) dV_0 is the elastic volume change alone,
∫ (exp(tr τ / 3K) − 1) dV_0 with the Kirchhoff mean stress (ln J = tr ε_e); ideal micro-plowing puts the groove into
shoulders and a bounded prow. Small-strain kinematics conserve tr ε, not J: their ∫ (J − 1) dV_0 is the
second-order volume error of the displacement field. Volumes for the whole grain (``symmetry_factor`` × the
half model), mm³.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from abrakit.validation import check_finite, number_arguments

_GAUSS = np.array([-1.0, 1.0]) / np.sqrt(3.0)


class VolumeBudget(NamedTuple):
    """The terms of the audit (mm³, whole grain; see the module docstring)."""

    groove: float
    shoulders: float
    prow: float
    sink: float
    faces: float
    volume_change: float
    residual: float
    removed: float = 0.0

    @property
    def displaced(self) -> float:
        """Material moved above the original surface or out of the block: shoulders + prow + faces."""
        return self.shoulders + self.prow + self.faces

    def as_dict(self, scale: float = 1.0, prefix: str = "") -> dict:
        return {f"{prefix}{k}": float(v) * scale for k, v in self._asdict().items()}


class BoundaryFaces:
    """The boundary quadrilaterals of a hexahedral mesh, outward and cyclically ordered, ready for the audit.

    ``top`` names the boundary (of ``mesh.boundaries``) that is the original surface y = 0; every other boundary
    facet counts as a face of the block.
    """

    def __init__(self, mesh, top: str = "top"):
        if type(mesh).__name__ != "MeshHex1":
            raise TypeError(f"the volume audit needs a hexahedral mesh (MeshHex1), got {type(mesh).__name__}")
        if mesh.boundaries is None or top not in mesh.boundaries:
            raise ValueError(f"top must name a tagged boundary of the mesh, got {top!r}")
        facets = mesh.boundary_facets()
        nodes = mesh.facets[:, facets].T                                     # (nf, 4), any order
        X = mesh.p[:, nodes]                                                 # (3, nf, 4)
        centre = X.mean(axis=2)
        normal_axis = np.argmin(np.ptp(X, axis=2), axis=0)                   # axis-parallel faces
        in_plane = np.array([[1, 2], [0, 2], [0, 1]])[normal_axis]            # (nf, 2)
        idx = np.arange(facets.size)
        a = X[in_plane[:, 0], idx] - centre[in_plane[:, 0], idx][:, None]
        b = X[in_plane[:, 1], idx] - centre[in_plane[:, 1], idx][:, None]
        order = np.argsort(np.arctan2(b, a), axis=1)                         # cyclic around the centre
        nodes = np.take_along_axis(nodes, order, axis=1)
        # outward: the facet's normal points away from its element's centre
        element = mesh.f2t[0, facets]
        inward = mesh.p[:, mesh.t[:, element]].mean(axis=1) - centre
        X = mesh.p[:, nodes]
        n = np.cross((X[:, :, 1] - X[:, :, 0]).T, (X[:, :, 3] - X[:, :, 0]).T)
        flip = np.einsum("fi,if->f", n, inward) > 0
        nodes[flip] = nodes[flip][:, ::-1]
        self.nodes = nodes
        self.is_top = np.isin(facets, mesh.boundaries[top])
        self.reference_weights = self.integrand(mesh.p)[0]                  # ∫ Y N_y dA, once per mesh

    def integrand(self, x: np.ndarray):
        """y (x_ξ × x_η)_y and the point positions at the 2 × 2 Gauss points of every face, for nodal
        positions ``x`` (3, npoints): returns (weights (nf, 4), points (nf, 4, 3)); the weights sum to ∫ y n_y da."""
        corners = x[:, self.nodes].transpose(1, 2, 0)                        # (nf, 4, 3), cyclic
        xi, eta = np.meshgrid(_GAUSS, _GAUSS, indexing="ij")
        xi, eta = xi.ravel(), eta.ravel()
        s = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)      # corner signs on the square
        N = 0.25 * (1 + xi[:, None] * s[:, 0]) * (1 + eta[:, None] * s[:, 1])     # (4 gp, 4 corners)
        dN_dxi = 0.25 * s[:, 0] * (1 + eta[:, None] * s[:, 1])
        dN_deta = 0.25 * s[:, 1] * (1 + xi[:, None] * s[:, 0])
        points = np.einsum("gc,fci->fgi", N, corners)
        x_xi = np.einsum("gc,fci->fgi", dN_dxi, corners)
        x_eta = np.einsum("gc,fci->fgi", dN_deta, corners)
        n_y = x_xi[..., 2] * x_eta[..., 0] - x_xi[..., 0] * x_eta[..., 2]   # (x_ξ × x_η)_y, Gauss weights 1
        return points[..., 1] * n_y, points


def volume_budget(faces: BoundaryFaces, kinematics, points: np.ndarray, u: np.ndarray, z_tip: float,
                  symmetry_factor: float = 2.0, removed=None) -> VolumeBudget:
    """:class:`VolumeBudget` of the displacement ``u`` (basis DOFs) on the mesh with vertices ``points`` (3, n),
    split at the apex position ``z_tip`` (mm); ``kinematics`` is the mesh's
    :class:`~abrakit.fem.Kinematics` (for J at its quadrature points); ``removed`` (nel,) bool: the elements
    counted as removed (module docstring), None for none."""
    nodal = np.asarray(kinematics.basis.nodal_dofs)
    x = points + u[nodal]
    w, q = faces.integrand(x)
    w0 = faces.reference_weights
    top = faces.is_top[:, None] & np.ones_like(w, dtype=bool)
    below, ahead = q[..., 1] < 0.0, q[..., 2] > z_tip
    k = symmetry_factor

    def part(mask):
        return k * float(np.sum(w[mask]))

    grad = kinematics.displacement_gradient(u)
    J = np.linalg.det(np.eye(3) + grad)
    volume_change = k * float(np.sum((J - 1.0) * kinematics.dx))
    groove = -part(top & below & ~ahead)
    shoulders = part(top & ~below & ~ahead)
    prow = part(top & ~below & ahead)
    sink = -part(top & below & ahead)
    side = ~faces.is_top
    face_flux = k * float(np.sum(w[side]) - np.sum(w0[side]))
    removed_volume = 0.0
    if removed is not None and np.any(removed):
        removed = np.asarray(removed, dtype=bool)
        if removed.shape != (kinematics.nel,):
            raise ValueError(f"removed must be one flag per element, shape ({kinematics.nel},), got {removed.shape}")
        x = kinematics.quadrature_points[:, removed] + np.moveaxis(kinematics.displacement_at_points(u)[removed], -1, 0)
        v = k * J[removed] * kinematics.dx[removed]                    # current volume of each point's share
        up, front = x[1] > 0.0, x[2] > z_tip
        shoulders -= float(np.sum(v[up & ~front]))
        prow -= float(np.sum(v[up & front]))
        groove += float(np.sum(v[~up & ~front]))
        sink += float(np.sum(v[~up & front]))
        removed_volume = k * float(np.sum(kinematics.dx[removed]))     # the material that left: its own volume
        volume_change -= float(np.sum(v)) - removed_volume             # the debris' J − 1 is not the body's
    residual = shoulders + prow + face_flux + removed_volume - groove - sink - volume_change
    return VolumeBudget(groove, shoulders, prow, sink, face_flux, volume_change, residual, removed_volume)


class SteadyRates(NamedTuple):
    """Growth of each budget term per unit slide over the steady part of a scratch (mm³/mm = mm², whole grain):
    the cross-sections a long groove settles to. ``removal_fraction`` = removed/groove is the f_ab the wear chain
    takes (Eq. 8.13): the share of the groove that left as debris. ``degree_of_wear`` = 1 − shoulders/groove is
    Eq. (8.5) in rates: it also counts the groove volume that went into elastic compaction, the prow and the
    sink, none of which is wear."""

    groove: float
    shoulders: float
    prow: float
    sink: float
    faces: float
    volume_change: float
    removed: float
    from_slide: float

    @property
    def degree_of_wear(self) -> float:
        return 1.0 - self.shoulders / self.groove

    @property
    def removal_fraction(self) -> float:
        return self.removed / self.groove


@number_arguments
def steady_rates(curves: dict, from_slide: float | None = None, to_slide: float | None = None) -> SteadyRates:
    """Least-squares slopes d V / d slide of the budget columns of a scratch's ``curves`` (``forces.csv``) over
    the sliding increments with ``from_slide`` ≤ slide ≤ ``to_slide`` (default: the second half of the slide, to
    its end), mm²."""
    sliding = np.asarray(curves["phase"]) == 1
    s = np.asarray(curves["slide"])[sliding]
    if s.size < 3:
        raise ValueError("steady_rates needs at least three sliding increments")
    for name, value in (("from_slide", from_slide), ("to_slide", to_slide)):
        if value is not None:
            check_finite(name, value)
    start = 0.5 * s.max() if from_slide is None else from_slide
    window = (s >= start) & (s <= (np.inf if to_slide is None else to_slide))
    if window.sum() < 3:
        end = "the end of the slide" if to_slide is None else f"{to_slide:g} mm"
        raise ValueError(f"the window from from_slide = {start:g} mm to to_slide = {end} leaves fewer than three "
                         "sliding increments")

    def rate(name):
        if f"V_{name}" not in curves:                  # records written before the removed term: none removed
            return 0.0
        return float(np.polyfit(s[window], np.asarray(curves[f"V_{name}"])[sliding][window], 1)[0])

    return SteadyRates(*(rate(n) for n in SteadyRates._fields[:-1]), from_slide=float(start))


def plateau_onset(slide: np.ndarray, values: np.ndarray, tolerance: float = 0.05) -> float:
    """First slide distance from which ``values`` stay within ``tolerance`` (relative) of their mean over the last
    quarter of the slide; NaN if even the last quarter varies by more (no plateau reached)."""
    slide, values = np.asarray(slide, dtype=float), np.asarray(values, dtype=float)
    last = slide >= slide.min() + 0.75 * (slide.max() - slide.min())
    level = values[last].mean()
    inside = np.abs(values / level - 1.0) <= tolerance
    if not np.all(inside[last]):
        return float("nan")
    outside = np.flatnonzero(~inside)
    return float(slide[outside[-1] + 1] if outside.size else slide[0])


class PlasticStrainRemoval(NamedTuple):
    """Material counted as removed by a critical plastic strain, per unit length of the wake (mm², whole grain).

    thresholds: the critical accumulated plastic strains ε_c; removed: for each, the volume per unit length of
    material above the original surface (shoulders) with α_p > ε_c, in the current configuration."""

    thresholds: np.ndarray
    removed: np.ndarray


def removal_by_plastic_strain(kinematics, u: np.ndarray, alpha_p: np.ndarray, J: np.ndarray | None,
                              thresholds, z_range: tuple[float, float],
                              symmetry_factor: float = 2.0) -> PlasticStrainRemoval:
    """A removal criterion as a study, not as a model: quadrature points of the final state that lie above the
    original surface (current y > 0) within ``z_range`` (reference z, mm) and whose accumulated plastic strain
    ``alpha_p`` (nel, nqp) exceeds ε_c are counted as chips. Their current volume (J dV_0; ``J=None``: small
    strain, dV_0) per unit length of the range, for every ε_c in ``thresholds``."""
    z_lo, z_hi = z_range
    if not z_hi > z_lo:
        raise ValueError(f"z_range must be increasing, got {z_range}")
    alpha_p = np.asarray(alpha_p, dtype=float)
    if alpha_p.shape != kinematics.dx.shape:
        raise ValueError(f"alpha_p must have shape {kinematics.dx.shape} (nel, nqp), got {alpha_p.shape}")
    X = kinematics.quadrature_points                                       # (3, nel, nqp)
    u_q = np.asarray(kinematics.basis.interpolate(u).value)                # (3, nel, nqp)
    above = (X[1] + u_q[1] > 0.0) & (X[2] >= z_lo) & (X[2] <= z_hi)
    volume = kinematics.dx * (1.0 if J is None else np.asarray(J))
    thresholds = np.atleast_1d(np.asarray(thresholds, dtype=float))
    removed = np.array([symmetry_factor * np.sum(volume[above & (alpha_p > t)]) for t in thresholds])
    return PlasticStrainRemoval(thresholds, removed / (z_hi - z_lo))
