"""Groove metrics of a single scratch (Sec. 8.2.2, Fig. 8.7): areas, width, depth, f_ab (Eq. 8.5), D_p (Eq. 8.6).

A cross-section profile (x, y) of the scratched surface is read as in the seed's Fig. 8.7: y = 0 is the original
surface, negative y lies below it. The profile is taken as piecewise linear between its samples (the trace of a
linear finite element surface), and every integral below is exact for such a profile:

* groove: the connected stretch of the profile below y = 0 that contains its deepest point; its end points, where
  the profile crosses y = 0, bound the groove. A_g is the area between y = 0 and the profile there;
* shoulders: on each side, the stretch above y = 0 that starts at the groove's edge and ends where the profile
  returns to y ≤ 0 (or the profile ends). A_s is their area above y = 0. Undulations farther out (the far field
  of an elastic block) belong to neither; a noise floor ``tol`` sets |y| ≤ tol to zero before the analysis;
* width w: the distance between the two y = 0 crossings that bound the groove, i.e. the groove's opening at the
  original surface. The seed defines D_p = 2d/w as the depth over the half-width of the groove, after Hokkirigawa
  and Kato, whose half-width is the radius of the contact (the groove opening under the tip), and Fig. 8.7 draws
  w across the groove; the crest-to-crest distance of the shoulders is reported too, as ``crest_width``;
* depth d: the deepest point below y = 0. The seed's D_p uses the indentation depth, which equals the groove depth
  with the tip in contact; pass ``depth=`` to use another value (e.g. the prescribed depth after unloading).

Half profiles (the half model's section, x ≥ 0 with the symmetry plane at x = 0) are declared with ``half=True``:
the groove must touch x = 0, areas and widths are doubled. Units: whatever the profile has (mm in the scene).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from abrakit.validation import check_finite, check_option, check_positive, check_shape, number_arguments


class GrooveMetrics(NamedTuple):
    """Metrics of one groove cross-section (full-section values also for half profiles).

    groove_area A_g, shoulder_area A_s (both shoulders), width w (groove opening at y = 0), depth d (used in D_p),
    degree_of_wear f_ab = (A_g − A_s)/A_g (Eq. 8.5), degree_of_penetration D_p = 2d/w (Eq. 8.6), regime
    ("plowing", "wedging", "cutting"), crest_width (distance between the shoulder crests; None unless both sides
    have a shoulder) and shoulder_height (highest shoulder point, 0 without shoulders). Areas in length², lengths
    in the profile's unit.
    """

    groove_area: float
    shoulder_area: float
    width: float
    depth: float
    degree_of_wear: float
    degree_of_penetration: float
    regime: str
    crest_width: float | None
    shoulder_height: float


def _positive_part_integrals(x, y):
    """∫ max(y, 0) dx over each segment of the piecewise linear profile, exact (split at the zero crossing)."""
    h = np.diff(x)
    a, b = y[:-1], y[1:]
    ap, bp = np.maximum(a, 0.0), np.maximum(b, 0.0)
    crossing = (a > 0.0) != (b > 0.0)
    span = np.where(crossing, np.abs(a - b), 1.0)
    # on a crossing segment only the triangle on the positive side counts: h a₊² / |a − b| / 2 (or with b₊)
    return np.where(crossing, 0.5 * h * (ap**2 + bp**2) / span, 0.5 * h * (ap + bp))


def _crossing(x, y, i):
    """x where the segment i → i+1 meets y = 0 (linear interpolation; the sample itself if it is 0)."""
    a, b = y[i], y[i + 1]
    return x[i] + (x[i + 1] - x[i]) * a / (a - b)


def _crest(x, y):
    """Position and height of the highest sample of a shoulder whose samples are ordered outward from the groove
    (ties go to the sample nearest the groove); (None, 0.0) when it never rises above y = 0."""
    if y.size == 0 or y.max() <= 0.0:
        return None, 0.0
    k = int(np.argmax(y))
    return float(x[k]), float(y[k])


def groove_metrics(x, y, *, half: bool, depth=None, tol: float = 0.0) -> GrooveMetrics:
    """Groove area, shoulder area, width, depth, f_ab (Eq. 8.5), D_p (Eq. 8.6) and regime of a profile.

    ``x`` (strictly increasing) and ``y`` are the samples of the cross-section, y = 0 the original surface and
    y < 0 below it. ``half`` must be given: True for a half profile on x ≥ 0 starting at the symmetry plane
    x = 0 (areas and widths are doubled), False for a full profile. ``depth`` overrides the measured groove depth
    in D_p; ``tol`` (≥ 0) is a noise floor: |y| ≤ tol counts as the original surface. See the module docstring
    for the definitions.
    """
    x = check_finite("x", np.asarray(x, dtype=float))
    y = check_finite("y", np.asarray(y, dtype=float))
    check_shape("x", x, (None,))
    check_shape("y", y, x.shape)
    if x.size < 3:
        raise ValueError(f"a profile needs at least 3 samples, got {x.size}")
    if np.any(np.diff(x) <= 0.0):
        raise ValueError("x must be strictly increasing (sort the profile by x)")
    tol = check_positive("tol", tol, allow_zero=True)
    if half and abs(x[0]) > 1e-12 * max(1.0, np.ptp(x)):
        raise ValueError(f"a half profile starts at the symmetry plane x = 0, got x[0] = {x[0]:g}")

    y = np.where(np.abs(y) <= tol, 0.0, y)
    deepest = int(np.argmin(y))
    if y[deepest] >= 0.0:
        raise ValueError("the profile has no groove: no point lies below the original surface y = 0")

    above_left = np.flatnonzero(y[:deepest] >= 0.0)
    above_right = deepest + 1 + np.flatnonzero(y[deepest + 1:] >= 0.0)
    if above_right.size == 0:
        raise ValueError("the groove does not close on the right: the profile ends below y = 0; extend the section")
    i_right = int(above_right[0])                            # first sample at or above y = 0 right of the groove
    if half:
        if above_left.size:
            raise ValueError(
                "the groove of a half profile must touch the symmetry plane x = 0, but the profile rises to y >= 0 "
                f"at x = {x[above_left[-1]]:g} between x = 0 and the deepest point"
            )
        i_left, x_left = 0, 0.0
    else:
        if above_left.size == 0:
            raise ValueError(
                "the groove does not close on the left: the profile starts below y = 0; extend the section, or "
                "pass half=True for a half profile starting at the symmetry plane"
            )
        i_left = int(above_left[-1])
        x_left = _crossing(x, y, i_left)
    x_right = _crossing(x, y, i_right - 1)

    negative = _positive_part_integrals(x, -y)
    positive = _positive_part_integrals(x, y)
    n = x.size
    groove_area = float(negative[i_left:i_right].sum())

    # right shoulder: samples i_right .. j_end − 1, up to the first later sample back at y <= 0
    later = i_right + 1 + np.flatnonzero(y[i_right + 1:] <= 0.0)
    j_end = int(later[0]) if later.size else n
    area_right = float(positive[i_right - 1:min(j_end, n - 1)].sum())
    x_crest_right, height_right = _crest(x[i_right:j_end], y[i_right:j_end])

    if half:
        A_g, A_s = 2.0 * groove_area, 2.0 * area_right
        width = 2.0 * x_right
        crest_width = None if x_crest_right is None else 2.0 * x_crest_right
        shoulder_height = height_right
    else:
        # left shoulder: samples j_start + 1 .. i_left, back to the last earlier sample at y <= 0
        earlier = np.flatnonzero(y[:i_left] <= 0.0)
        j_start = int(earlier[-1]) if earlier.size else -1
        area_left = float(positive[max(j_start, 0):i_left + 1].sum())
        x_crest_left, height_left = _crest(x[j_start + 1:i_left + 1][::-1], y[j_start + 1:i_left + 1][::-1])
        A_g, A_s = groove_area, area_left + area_right
        width = x_right - x_left
        both = x_crest_left is not None and x_crest_right is not None
        crest_width = x_crest_right - x_crest_left if both else None
        shoulder_height = max(height_left, height_right)
    d = float(-y[deepest]) if depth is None else check_positive("depth", depth, allow_zero=True)

    from abrakit.wear import degree_of_penetration, degree_of_wear, wear_regime

    if A_s > A_g:
        raise ValueError(
            f"the shoulders hold more material than the groove lost (A_s = {A_s:g} > A_g = {A_g:g}): f_ab of "
            "Eq. (8.5) is undefined; check the reference level y = 0 of the profile and the section's extent"
        )
    f_ab = degree_of_wear(A_g, A_s)                                          # Eq. (8.5)
    return GrooveMetrics(
        groove_area=float(A_g),
        shoulder_area=float(A_s),
        width=float(width),
        depth=d,
        degree_of_wear=float(f_ab),
        degree_of_penetration=float(degree_of_penetration(d, width)),        # Eq. (8.6)
        regime=wear_regime(f_ab),
        crest_width=None if crest_width is None else float(crest_width),
        shoulder_height=float(shoulder_height),
    )


# --- from the finite element model ------------------------------------------------------------------------


class Profile(NamedTuple):
    """Deformed surface section, ordered by the reference x of its node lines: x, y (y = 0 the original surface)
    and z of the section points (all equal to the section's z for a spatial section)."""

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray


def _layers(values, tol):
    """Cluster sorted-unique coordinates within ``tol``: returns (layer values, layer index of each entry)."""
    order = np.argsort(values)
    starts = np.concatenate([[True], np.diff(values[order]) > tol])
    label_sorted = np.cumsum(starts) - 1
    labels = np.empty_like(label_sorted)
    labels[order] = label_sorted
    return values[order][starts], labels


def profile_from_surface_nodes(points, displacement, z_section, *, top: float = 0.0, tol=None,
                               section: str = "spatial") -> Profile:
    """Deformed cross-section of the top surface at ``z_section`` from the nodes of a hexahedral mesh.

    ``points`` (n, 3) are the reference node coordinates, ``displacement`` (n, 3) the nodal displacements, lengths
    in mm. The surface nodes are those with |Y − top| ≤ ``tol`` (default 1e-9 × the mesh size); they must form a
    tensor grid of node lines X = const × layers Z = const, as a graded tensor-product mesh (``MeshHex.init_tensor``)
    has. Along each node line the surface edge is a straight segment between layers in the deformed configuration
    too (trilinear elements), so interpolating along it is exact:

    * ``section="spatial"`` (default): the point of each deformed line at z = ``z_section`` (the cut a microscope
      takes, Fig. 8.5b), found between the two layers that bracket it;
    * ``section="material"``: the deformed image of the reference line Z = ``z_section`` (the points that sat in
      that plane before the scratch; they are dragged along z by friction).

    Returns a :class:`Profile` with y measured from the original surface (y − top), ready for
    :func:`groove_metrics` (``half=True`` for the half model, whose lines start at the symmetry plane X = 0).
    """
    points = check_shape("points", check_finite("points", points), (None, 3))
    displacement = check_shape("displacement", check_finite("displacement", displacement), points.shape)
    z_section = check_finite("z_section", z_section)
    check_option("section", section, ("spatial", "material"))
    size = float(np.ptp(points, axis=0).max()) or 1.0
    tol = 1e-9 * size if tol is None else check_positive("tol", tol)

    on_top = np.abs(points[:, 1] - top) <= tol
    if not np.any(on_top):
        raise ValueError(f"no node lies on the top surface Y = {top:g} (tol {tol:g})")
    X, Z = points[on_top, 0], points[on_top, 2]
    xs, ix = _layers(X, tol)
    zs, iz = _layers(Z, tol)
    if xs.size * zs.size != X.size or np.unique(ix * zs.size + iz).size != X.size:
        raise ValueError(
            f"the top surface nodes do not form a tensor grid ({X.size} nodes on {xs.size} lines x {zs.size} "
            "layers): profile_from_surface_nodes needs a tensor-product hexahedral mesh"
        )
    if zs.size < 2:
        raise ValueError("the top surface has a single layer in z: nothing to interpolate between")
    grid = np.empty((xs.size, zs.size, 3))
    grid[ix, iz] = points[on_top] + displacement[on_top]             # deformed positions, lines × layers

    if section == "material":
        if not zs[0] <= z_section <= zs[-1]:
            raise ValueError(f"z_section = {z_section:g} lies outside the surface's layers [{zs[0]:g}, {zs[-1]:g}]")
        k = np.clip(np.searchsorted(zs, z_section) - 1, 0, zs.size - 2)
        t = (z_section - zs[k]) / (zs[k + 1] - zs[k])
        section_points = (1.0 - t) * grid[:, k] + t * grid[:, k + 1]
    else:
        z_def = grid[:, :, 2]
        if np.any(np.diff(z_def, axis=1) <= 0.0):
            raise ValueError("the deformed surface folds along z (node layers out of order): no spatial section")
        k = (z_def <= z_section).sum(axis=1) - 1
        if np.any(k < 0) or np.any(z_def[:, -1] < z_section):
            raise ValueError(f"z_section = {z_section:g} lies outside the deformed surface on some node lines")
        k = np.minimum(k, zs.size - 2)
        lines = np.arange(xs.size)
        lo, hi = grid[lines, k], grid[lines, k + 1]
        t = (z_section - lo[:, 2]) / (hi[:, 2] - lo[:, 2])
        section_points = lo + t[:, None] * (hi - lo)
    return Profile(section_points[:, 0], section_points[:, 1] - top, section_points[:, 2])


class RemovedMaterial(NamedTuple):
    """Material removed where damage reached its cap (reported apart from A_g and A_s).

    volume: removed volume (full model for ``half=True``), mm³; count: number of removed elements (in the mesh
    given); mask: (n_elements,) bool, the removed elements; area: mean removed cross-section area over the z
    window, volume / window length, mm² (None without a window).
    """

    volume: float
    count: int
    mask: np.ndarray
    area: float | None


def at_cap(damage, cap: float, rtol: float = 1e-9) -> np.ndarray:
    """Where ``damage`` has reached the ``cap`` (within ``rtol``): the removal criterion of
    :func:`removed_material` and of the scratch's volume audit."""
    return np.asarray(damage) >= cap * (1.0 - rtol)


@number_arguments
def removed_material(volumes: ArrayLike, damage: ArrayLike, cap: float, *, half: bool, centres=None, z_range=None,
                     rtol: float = 1e-9) -> RemovedMaterial:
    """Elements whose damage reached the cap, their volume and the removed cross-section area.

    ``volumes`` (n,) element volumes in mm³, ``damage`` (n,) one damage value per element (reduce quadrature
    point values before, e.g. by the mean), ``cap`` the damage cap in (0, 1] (the model's maximum damage); an
    element counts as removed when damage ≥ cap (1 − ``rtol``). With ``centres`` (n, 3) and ``z_range``
    (z0, z1) only elements whose centre lies in z0 ≤ z ≤ z1 count, and ``area`` = volume / (z1 − z0) is the mean
    removed cross-section area there, comparable to A_g. ``half=True`` doubles volume and area (half model).
    """
    volumes = check_positive("volumes", np.atleast_1d(volumes), allow_zero=True)
    damage = check_shape("damage", check_finite("damage", np.atleast_1d(damage)), volumes.shape)
    check_shape("volumes", volumes, (None,))
    cap = float(np.asarray(check_positive("cap", cap)))
    if cap > 1.0:
        raise ValueError(f"cap must lie in (0, 1], got {cap!r}")
    mask = at_cap(damage, cap, rtol)
    area = None
    if z_range is not None:
        if centres is None:
            raise ValueError("z_range needs the element centres")
        centres = check_shape("centres", check_finite("centres", centres), (volumes.size, 3))
        z0, z1 = (float(v) for v in check_finite("z_range", z_range))
        if not z0 < z1:
            raise ValueError(f"z_range must satisfy z0 < z1, got ({z0:g}, {z1:g})")
        mask &= (centres[:, 2] >= z0) & (centres[:, 2] <= z1)
    factor = 2.0 if half else 1.0
    volume = factor * float(volumes[mask].sum())
    if z_range is not None:
        area = volume / (z1 - z0)
    return RemovedMaterial(volume, int(mask.sum()), mask, area)
