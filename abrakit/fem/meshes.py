"""Structured, graded meshes of the specimens in Ch. 7–8, built with numpy and scikit-fem only.

All lengths in mm. The seed's figures do not give all the dimensions of its specimens, so the defaults below are
choices, stated in each docstring and in the book's FEM chapter; every generator takes the dimensions as arguments.

- :func:`plate_with_hole` — quarter of a plate with a central circular hole, graded towards the hole (Ch. 7.1.1).
- :func:`double_notched_specimen` — strip with two asymmetric edge notches (Ch. 7.1.2, 7.2.2).
- :func:`sharp_notch_specimen` — half of a 50 x 40 mm specimen with a 25 mm sharp notch (Ch. 7.2.1).
- :func:`ring_sector` — quarter of a thick cylinder (verification against the elastic–plastic solution).
- :func:`graded_block` — 3D hex block graded towards a point, e.g. under a scratch tip (Ch. 8).
- :func:`extrude` — a quad mesh swept into hexes through a thickness (the seed's 3 mm, one element).

Every generator tags its boundaries (``mesh.boundaries``) and :func:`element_quality` reports aspect ratios and
Jacobians; :func:`check_quality` raises for inverted elements and warns for badly shaped ones.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import skfem

from ..validation import check_positive, check_range, number_arguments

_TOL = 1e-9


def graded(n: int, ratio: float = 1.0) -> np.ndarray:
    """``n + 1`` points on [0, 1] whose element sizes grow geometrically; ``ratio`` = last size / first size."""
    n = int(check_range("n", n, 1, None))
    ratio = check_positive("ratio", ratio)
    if n == 1 or abs(ratio - 1.0) < 1e-12:
        return np.linspace(0.0, 1.0, n + 1)
    q = ratio ** (1.0 / (n - 1))
    sizes = q ** np.arange(n)
    return np.concatenate(([0.0], np.cumsum(sizes) / sizes.sum()))


@number_arguments
def graded_towards(a: float, b: float, n: int, fine_at: float | None = None, ratio: float = 1.0) -> np.ndarray:
    """Points from ``a`` to ``b`` with about ``n`` elements, finest at ``fine_at`` (a node), coarsening by ``ratio``."""
    if fine_at is None or ratio == 1.0:
        return a + (b - a) * graded(n, ratio if fine_at == a else 1.0)
    fine_at = check_range("fine_at", fine_at, a, b)
    left, right = fine_at - a, b - fine_at
    n_left = int(round(n * left / (b - a))) if left > 0 else 0
    n_right = n - n_left
    parts = []
    if n_left:
        parts.append(fine_at - left * graded(max(n_left, 1), ratio)[::-1])
    if n_right:
        parts.append(fine_at + right * graded(max(n_right, 1), ratio)[1 if n_left else 0:])
    return np.concatenate(parts)


def _tag(mesh, **boundaries):
    return mesh.with_boundaries(boundaries)


@number_arguments
def plate_with_hole(width: float = 50.0, height: float = 50.0, radius: float = 10.0, n_angular: int = 16,
                    n_radial: int = 12, grading: float = 4.0, triangles: bool = False, angles=None, order: int = 1):
    """Quarter of a plate with a central hole: [0, width] x [0, height] minus the disc of ``radius`` at 0.

    Defaults (seed Fig. 7.1 missing): plate 100 x 100 mm, hole diameter 20 mm, i.e. the quarter 50 x 50 mm.
    Rays from the hole to the outer edges with ``n_angular`` elements around the quarter hole and
    ``n_radial`` elements along each ray, ``grading`` = outer / inner radial element size.
    ``angles`` (optional) are the ray angles from 0 to pi/2 including the corner ray atan2(height, width),
    e.g. graded towards a ligament; by default ``n_angular`` uniform steps on each side of the corner.
    Boundaries: ``hole``, ``left`` (x = 0, symmetry), ``bottom`` (y = 0, symmetry), ``right``, ``top``.

    ``order=2`` gives a 9-node ``MeshQuad2`` (for Q8/Q9 fields) whose mid-side and centre nodes are placed by the same
    map as the vertices, ray angle interpolated between the rays: the hole's edges are then curved (their nodes lie
    on the circle), the outer edges stay straight.
    """
    width, height = check_positive("width", width), check_positive("height", height)
    radius = check_range("radius", radius, 0.0, min(width, height), low_open=True, high_open=True)
    check_positive("grading", grading)
    corner = np.arctan2(height, width)
    if angles is None:
        n1 = int(np.clip(round(n_angular * corner / (np.pi / 2)), 1, n_angular - 1))
        theta = np.concatenate((np.linspace(0, corner, n1 + 1),
                                np.linspace(corner, np.pi / 2, n_angular - n1 + 1)[1:]))
    else:
        theta = np.asarray(angles, dtype=float)
        if theta.ndim != 1 or not np.isclose(theta[0], 0.0) or not np.isclose(theta[-1], np.pi / 2) \
                or np.any(np.diff(theta) <= 0) \
                or not np.any(np.isclose(theta, corner, rtol=0.0, atol=1e-14)):
            raise ValueError("angles must increase from 0 to pi/2 and contain the corner ray atan2(height, width)")
    if order not in (1, 2):
        raise ValueError(f"order must be 1 (bilinear geometry) or 2 (biquadratic, curved hole), got {order!r}")
    if order == 2 and triangles:
        raise ValueError("order=2 is for quadrilaterals: triangles=True takes order=1")
    s = graded(n_radial, grading)
    mesh = skfem.MeshQuad.init_tensor(s, np.arange(theta.size, dtype=float))     # parameter plane (S, ray index)
    if order == 2:
        mesh = skfem.MeshQuad2.from_mesh(mesh)
    S, k = mesh.doflocs
    th = np.interp(k, np.arange(theta.size), theta)
    inner = radius * np.stack((np.cos(th), np.sin(th)))
    outer = np.where(th <= corner + 1e-14,
                     np.stack((np.full_like(th, width), width * np.tan(th))),
                     np.stack((height / np.tan(np.maximum(th, 1e-300)), np.full_like(th, height))))
    outer[0, np.isclose(th, np.pi / 2)] = 0.0
    p = inner + S * (outer - inner)
    mesh = type(mesh)(p, mesh.t)
    if triangles:
        mesh = mesh.to_meshtri()
    return _tag(mesh,
                hole=lambda x: np.hypot(x[0], x[1]) < radius * (1 + _TOL),
                left=lambda x: x[0] < _TOL * width,
                bottom=lambda x: x[1] < _TOL * height,
                right=lambda x: x[0] > width * (1 - _TOL),
                top=lambda x: x[1] > height * (1 - _TOL))


@number_arguments
def ring_sector(inner: float = 10.0, outer: float = 20.0, n_radial: int = 10, n_angular: int = 12,
                angle: float = np.pi / 2, grading: float = 1.0):
    """Sector ``inner <= r <= outer``, ``0 <= theta <= angle`` of a thick cylinder (plane strain cross-section).

    Boundaries: ``inner``, ``outer``, ``bottom`` (theta = 0), ``side`` (theta = angle).
    """
    inner = check_positive("inner", inner)
    outer = check_range("outer", outer, inner, None, low_open=True)
    mesh = skfem.MeshQuad.init_tensor(inner + (outer - inner) * graded(n_radial, grading),
                                      np.linspace(0.0, angle, n_angular + 1))
    r, th = mesh.p
    mesh = skfem.MeshQuad(np.stack((r * np.cos(th), r * np.sin(th))), mesh.t)
    c, s = np.cos(angle), np.sin(angle)
    return _tag(mesh,
                inner=lambda x: np.hypot(x[0], x[1]) < inner * (1 + _TOL),
                outer=lambda x: np.hypot(x[0], x[1]) > outer * np.cos(angle / n_angular / 2) * (1 - _TOL),
                bottom=lambda x: np.abs(x[1]) < _TOL * outer,
                side=lambda x: np.abs(x[0] * s - x[1] * c) < _TOL * outer)


def _tensor_without(xs, ys, holes):
    """Quad mesh of the grid xs x ys without the elements whose centre lies in any rectangle of ``holes``."""
    mesh = skfem.MeshQuad.init_tensor(xs, ys)
    centre = mesh.p[:, mesh.t].mean(axis=1)
    keep = np.ones(mesh.t.shape[1], dtype=bool)
    for x0, x1, y0, y1 in holes:
        keep &= ~((centre[0] > x0) & (centre[0] < x1) & (centre[1] > y0) & (centre[1] < y1))
    t = mesh.t[:, keep]
    used, t = np.unique(t, return_inverse=True)
    return skfem.MeshQuad(np.ascontiguousarray(mesh.p[:, used]), np.ascontiguousarray(t.reshape(4, -1)))


@number_arguments
def double_notched_specimen(width: float = 50.0, height: float = 100.0, notch_depth: float = 10.0,
                            notch_width: float = 2.0, offset: float = 10.0, h_fine: float = 1.0,
                            grading: float = 5.0):
    """Strip ``width`` x ``height`` with two rectangular edge notches at mid-height, shifted by +/- ``offset``.

    Defaults (seed Fig. 7.8 missing): 50 x 100 mm, notches 10 mm deep and 2 mm wide, the left one 10 mm above
    and the right one 10 mm below mid-height. The mesh is finest (``h_fine``) in the band between the notches
    and coarsens by ``grading`` towards the loaded ends. Boundaries: ``bottom``, ``top``, ``left``, ``right``,
    ``notches``.
    """
    width, height = check_positive("width", width), check_positive("height", height)
    check_range("notch_depth", notch_depth, 0.0, width / 2, low_open=True, high_open=True)
    check_range("notch_width", notch_width, 0.0, height, low_open=True, high_open=True)
    check_range("offset", offset, -height / 2, height / 2, low_open=True, high_open=True)
    check_range("h_fine", h_fine, 0.0, height, low_open=True, high_open=True)
    check_range("grading", grading, 1.0, None)
    mid = height / 2
    y_left, y_right = mid + offset, mid - offset
    band = (y_right - notch_width / 2 - 2 * h_fine, y_left + notch_width / 2 + 2 * h_fine)
    ny_band = max(2, int(round((band[1] - band[0]) / h_fine)))
    n_end = max(2, int(round(np.log(grading) / np.log(1.2)) + 2))
    ys = np.unique(np.round(np.concatenate((
        band[0] - (band[0]) * graded(n_end, grading)[::-1],
        np.linspace(*band, ny_band + 1),
        band[1] + (height - band[1]) * graded(n_end, grading),
        [y_left - notch_width / 2, y_left + notch_width / 2, y_right - notch_width / 2, y_right + notch_width / 2],
    )), 12))
    xs = np.unique(np.round(np.concatenate((np.linspace(0, width, max(2, int(round(width / h_fine))) + 1),
                                            [notch_depth, width - notch_depth])), 12))
    holes = [(-1, notch_depth, y_left - notch_width / 2, y_left + notch_width / 2),
             (width - notch_depth, width + 1, y_right - notch_width / 2, y_right + notch_width / 2)]
    mesh = _tensor_without(xs, ys, holes)

    def in_notch(x):
        return np.any([(x[0] >= a - _TOL) & (x[0] <= b + _TOL) & (x[1] >= c - _TOL) & (x[1] <= d + _TOL)
                       for a, b, c, d in holes], axis=0)

    return _tag(mesh,
                bottom=lambda x: x[1] < _TOL * height,
                top=lambda x: x[1] > height * (1 - _TOL),
                notches=in_notch,
                left=lambda x: (x[0] < _TOL * width) & ~in_notch(x),
                right=lambda x: (x[0] > width * (1 - _TOL)) & ~in_notch(x))


@number_arguments
def sharp_notch_specimen(width: float = 50.0, height: float = 40.0, notch: float = 25.0, n_x: int = 40,
                         n_y: int = 16, grading: float = 6.0):
    """Upper half of the ``width`` x ``height`` specimen with a sharp horizontal notch of length ``notch``.

    The seed's specimen (Ch. 7.2.1): 50 x 40 mm, 25 mm notch from the left edge at mid-height; by symmetry the
    half model [0, width] x [0, height/2] has the notch faces (free) on y = 0, x < notch and the ligament
    (symmetry, u_y = 0) on y = 0, x > notch. Elements are finest at the notch tip and along the ligament.
    Boundaries: ``notch``, ``ligament``, ``top``, ``left``, ``right``.
    """
    width, height = check_positive("width", width), check_positive("height", height)
    notch = check_range("notch", notch, 0.0, width, low_open=True, high_open=True)
    check_positive("grading", grading)
    xs = graded_towards(0.0, width, n_x, notch, grading)
    ys = (height / 2) * graded(n_y, grading)
    mesh = skfem.MeshQuad.init_tensor(xs, ys)
    return _tag(mesh,
                notch=lambda x: (x[1] < _TOL * height) & (x[0] < notch),
                ligament=lambda x: (x[1] < _TOL * height) & (x[0] > notch),
                top=lambda x: x[1] > height / 2 * (1 - _TOL),
                left=lambda x: x[0] < _TOL * width,
                right=lambda x: x[0] > width * (1 - _TOL))


def graded_block(size=(200.0, 100.0, 15.0), divisions=(20, 10, 6), fine_at=(None, None, None),
                 grading=(1.0, 1.0, 1.0)):
    """Hex block [0, Lx] x [0, Ly] x [0, Lz], graded per axis towards the coordinate ``fine_at[i]``.

    Defaults: the seed's scratch specimen 200 x 100 x 15 (µm written as mm, Ch. 8), uniform. Boundaries:
    ``xmin``, ``xmax``, ``ymin``, ``ymax``, ``zmin``, ``zmax``.
    """
    axes = [graded_towards(0.0, float(check_positive("size", L)), int(n), f, float(g))
            for L, n, f, g in zip(size, divisions, fine_at, grading, strict=True)]
    mesh = skfem.MeshHex.init_tensor(*axes)
    lx, ly, lz = size
    return _tag(mesh,
                xmin=lambda x: x[0] < _TOL * lx, xmax=lambda x: x[0] > lx * (1 - _TOL),
                ymin=lambda x: x[1] < _TOL * ly, ymax=lambda x: x[1] > ly * (1 - _TOL),
                zmin=lambda x: x[2] < _TOL * lz, zmax=lambda x: x[2] > lz * (1 - _TOL))


def extrude(mesh: skfem.MeshQuad, thickness: float = 3.0, layers: int = 1):
    """Sweep a quad mesh along z into hexes (``layers`` elements through ``thickness``; the seed uses 3 mm, 1).

    2D boundary tags carry over to the side faces; ``front`` (z = 0) and ``back`` (z = thickness) are added.
    """
    thickness = check_positive("thickness", thickness)
    z = np.linspace(0.0, thickness, int(layers) + 1)
    n = mesh.p.shape[1]
    p = np.vstack((np.tile(mesh.p, (1, z.size)), np.repeat(z, n)[None, :]))
    ref = skfem.ElementHex1().doflocs  # scikit-fem's local node order of a hex, reference coordinates
    quad_index = {(0, 0): 0, (1, 0): 1, (1, 1): 2, (0, 1): 3}
    t = np.vstack([mesh.t[quad_index[(int(xi), int(eta))]][None, :] + n * int(zeta) for xi, eta, zeta in ref])
    t = np.hstack([t + n * layer for layer in range(int(layers))])
    hexes = skfem.MeshHex(p, t)
    sides = {}
    for name, facets in (mesh.boundaries or {}).items():
        sides[name] = _on_points(mesh.p[:, mesh.facets[:, facets]].mean(axis=1))
    return hexes.with_boundaries({
        **sides,
        "front": lambda x: x[2] < _TOL * thickness,
        "back": lambda x: x[2] > thickness * (1 - _TOL),
    })


def _on_points(points: np.ndarray):
    """Predicate on 3D facet midpoints: does (x, y) coincide with one of the 2D ``points`` ``(2, m)``?"""
    from scipy.spatial import cKDTree

    tree = cKDTree(points.T)
    scale = max(float(np.ptp(points)), 1.0)
    return lambda x: tree.query(np.asarray(x)[:2].T)[0] < 1e-9 * scale


# ---- quality ---------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class MeshQuality:
    """Per-element shape measures and their extremes.

    ``aspect_ratio``: longest / shortest element edge. ``jacobian_ratio``: smallest det J at the element's corners
    over its mean det J (1 for parallelograms, <= 0 for inverted or degenerate elements).
    """

    aspect_ratio: np.ndarray
    jacobian_ratio: np.ndarray
    min_det_jacobian: float

    @property
    def worst_aspect_ratio(self) -> float:
        return float(self.aspect_ratio.max())

    @property
    def worst_jacobian_ratio(self) -> float:
        return float(self.jacobian_ratio.min())

    def summary(self) -> str:
        n = self.aspect_ratio.size
        return (f"{n} elements: aspect ratio max {self.worst_aspect_ratio:.2f} "
                f"(median {np.median(self.aspect_ratio):.2f}), corner Jacobian ratio min "
                f"{self.worst_jacobian_ratio:.3f}, min det J {self.min_det_jacobian:.3g}")


def _edges(mesh) -> np.ndarray:
    """Local node pairs of the element edges."""
    if isinstance(mesh, skfem.MeshQuad1):
        return np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    if isinstance(mesh, skfem.MeshHex1):
        ref = skfem.ElementHex1().doflocs
        d = np.abs(ref[:, None, :] - ref[None, :, :]).sum(axis=-1)
        return np.argwhere(np.triu(d == 1))
    k = mesh.t.shape[0]
    return np.array([[i, j] for i in range(k) for j in range(i + 1, k)])


def element_quality(mesh) -> MeshQuality:
    """Aspect ratio and corner-Jacobian ratio of every element of a linear scikit-fem mesh."""
    edges = _edges(mesh)
    length = np.linalg.norm(mesh.p[:, mesh.t[edges[:, 0]]] - mesh.p[:, mesh.t[edges[:, 1]]], axis=0)
    aspect = length.max(axis=0) / np.maximum(length.min(axis=0), 1e-300)
    corners = _scalar(mesh).doflocs.T  # reference coordinates of the element's nodes
    det = np.asarray(mesh._mapping().detDF(corners))
    det = det * np.sign(det.sum(axis=1, keepdims=True))  # scikit-fem accepts either orientation
    mean = det.mean(axis=1)
    return MeshQuality(aspect, det.min(axis=1) / np.maximum(mean, 1e-300), float(det.min()))


def _scalar(mesh):
    from .kinematics import LINEAR_ELEMENT

    return LINEAR_ELEMENT[type(mesh).__name__]()


def check_quality(mesh, max_aspect_ratio: float = 20.0, min_jacobian_ratio: float = 0.2) -> MeshQuality:
    """Raise ``ValueError`` for inverted/degenerate elements; warn for badly shaped ones. Returns the report."""
    check_range("max_aspect_ratio", max_aspect_ratio, 1.0, None)
    check_range("min_jacobian_ratio", min_jacobian_ratio, 0.0, 1.0)
    q = element_quality(mesh)
    bad = np.flatnonzero(q.jacobian_ratio <= 0.0)
    if bad.size:
        raise ValueError(f"{bad.size} inverted or degenerate elements (det J <= 0), e.g. elements {bad[:5]}; "
                         "check the node order and the geometry")
    n_aspect = int(np.sum(q.aspect_ratio > max_aspect_ratio))
    n_skew = int(np.sum(q.jacobian_ratio < min_jacobian_ratio))
    if n_aspect or n_skew:
        warnings.warn(f"badly shaped elements: {n_aspect} with aspect ratio > {max_aspect_ratio:g}, {n_skew} with "
                      f"corner Jacobian ratio < {min_jacobian_ratio:g} ({q.summary()})", stacklevel=2)
    return q
