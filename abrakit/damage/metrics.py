r"""Mesh independence as numbers (Ch. 7): peak force, distance between curves, dissipated energy, band width.

A regularised model is mesh-independent when these stay put as the mesh is refined; a local one shows it by the
opposite. Every metric is exact on its own terms (tests check them on synthetic curves and fields):

**Curves** (force F against displacement u, both piecewise linear between the recorded steps):

- :func:`peak` -- ``(F_max, u at F_max)``;
- :func:`relative_spread` -- ``(max - min) / |mean|`` of a quantity across meshes (e.g. peak forces);
- :func:`curve_distance` -- relative L2 distance over the common displacement range ``[u0, u1]``,

  .. math:: e_{L2} = \frac{1}{\max|F_\text{ref}|}\sqrt{\frac{1}{u_1-u_0}\int_{u_0}^{u_1} (F - F_\text{ref})^2\,du},

  evaluated exactly for the two piecewise-linear curves (on the union of their nodes the difference is linear
  on every interval, and ``int g^2 = h (g_0^2 + g_0 g_1 + g_1^2)/3``);
- :func:`work` -- ``int F du`` (trapezoidal, exact for a piecewise-linear curve), optionally up to a displacement;
- :func:`softening_displacement` -- how far past the peak the force falls to a fraction of it (steep vs smooth
  drop), by linear interpolation;
- :func:`largest_drop` -- the largest force drop of one step after the peak (a jump keeps it under step
  refinement, a force continuous in u halves it with the step);
- :func:`steepest_softening` -- the steepest secant slope of a step after the peak (converges under step
  refinement for a force continuous in u, doubles with each halving at a jump).

**Damage fields** (one value per element of a 2D mesh, e.g. the stiffness loss ``1 - f``):

- :func:`band_width` -- the damaged set ``{value >= threshold}`` has area ``A`` and, along its principal axis
  (area-weighted second moments of the element centres), length ``L`` = extent of its elements' vertices;
  ``width = mirror * A / L`` (``mirror = 2`` when the band lies on a symmetry line of a half/quarter model,
  or give the band's nominal ``length``). Exact for a straight band of elements; for a curved band it is the
  mean width over its chord length. The principal ``angle`` (degrees from the x axis) tells a diagonal
  ("S") band from a horizontal or a vertical one; ``within`` restricts the measurement to a window;
- :func:`cut_width` -- the length of the damaged part of a straight cut line, exact for convex elements (the
  chord of the line through every damaged element, by Cyrus-Beck clipping);
- :func:`transition_ratio` -- ``band_width(low) / band_width(high)``: close to 1 for a sharp transition between
  damaged and intact material, large for a smooth one;
- :func:`damaged_components` -- how many separate pieces the damaged set has (two cracks or one merged band;
  elements touching at a vertex belong to the same piece).

:func:`specimen_metrics` evaluates them for one run on a :class:`~abrakit.damage.specimens.DamageSpecimen`;
:func:`mesh_study` gathers them for a family of meshes against the finest one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..validation import check_finite, check_range, number_arguments


def _curve(u, F, name="curve"):
    u, F = np.asarray(u, dtype=float), np.asarray(F, dtype=float)
    if u.ndim != 1 or u.shape != F.shape or u.size < 2:
        raise ValueError(f"{name}: u and F must be 1D arrays of the same length >= 2, got {u.shape}, {F.shape}")
    if not (np.all(np.isfinite(u)) and np.all(np.isfinite(F))):
        raise ValueError(f"{name}: u and F must be finite")
    if np.any(np.diff(u) < 0):
        raise ValueError(f"{name}: the displacement u must not decrease along the curve")
    return u, F


def peak(u, F) -> tuple[float, float]:
    """``(F_max, u at F_max)`` of a force–displacement curve (N, mm)."""
    u, F = _curve(u, F)
    i = int(np.argmax(F))
    return float(F[i]), float(u[i])


def relative_spread(values) -> float:
    """``(max - min) / |mean|`` of a quantity across meshes (0 for identical values)."""
    values = np.asarray(values, dtype=float)
    if values.size < 2 or not np.all(np.isfinite(values)):
        raise ValueError("relative_spread needs at least two finite values")
    mean = abs(values.mean())
    if mean == 0.0:
        raise ValueError("relative_spread: the mean is zero")
    return float((values.max() - values.min()) / mean)


def _integral_of_square(x, g) -> float:
    """``int g^2 dx`` of the piecewise-linear function with nodal values ``g`` at ``x`` (exact)."""
    h = np.diff(x)
    return float(np.sum(h * (g[:-1] ** 2 + g[:-1] * g[1:] + g[1:] ** 2) / 3.0))


@number_arguments
def curve_distance(u: ArrayLike, F: ArrayLike, u_ref: ArrayLike, F_ref: ArrayLike, *,
                   u_range: tuple[float, float] | None = None) -> float:
    """Relative L2 distance of curve (u, F) from (u_ref, F_ref) over their common displacement range.

    ``u_range`` narrows the range (it must lie inside the common one). Normalised by ``max |F_ref|`` on the range,
    so 0.05 means an RMS deviation of 5 % of the reference peak. Exact for piecewise-linear curves.
    """
    u, F = _curve(u, F, "curve")
    u_ref, F_ref = _curve(u_ref, F_ref, "reference")
    lo, hi = max(u[0], u_ref[0]), min(u[-1], u_ref[-1])
    if u_range is not None:
        lo = check_range("u_range[0]", u_range[0], lo, hi)
        hi = check_range("u_range[1]", u_range[1], lo, hi)
    if not hi > lo:
        raise ValueError(f"the curves share no displacement range (common range [{lo:g}, {hi:g}])")
    x = np.unique(np.concatenate(([lo, hi], u[(u > lo) & (u < hi)], u_ref[(u_ref > lo) & (u_ref < hi)])))
    g = np.interp(x, u, F) - np.interp(x, u_ref, F_ref)
    inside = (u_ref >= lo) & (u_ref <= hi)
    scale = max(np.max(np.abs(np.interp([lo, hi], u_ref, F_ref))), np.max(np.abs(F_ref[inside]), initial=0.0))
    if scale == 0.0:
        raise ValueError("the reference force is zero on the common range")
    return float(np.sqrt(_integral_of_square(x, g) / (hi - lo)) / scale)


def work(u, F, upto: float | None = None) -> float:
    """``int F du`` along the curve (N mm), trapezoidal -- exact for the piecewise-linear curve -- up to ``upto``."""
    u, F = _curve(u, F)
    if upto is not None:
        upto = check_range("upto", upto, u[0], u[-1])
        keep = u < upto
        F = np.concatenate((F[keep], [np.interp(upto, u, F)]))
        u = np.concatenate((u[keep], [upto]))
    return path_work(u, F)


def path_work(u, F) -> float:
    """``sum 1/2 (F_m + F_m+1) (u_m+1 - u_m)`` along a recorded path (N mm), which may turn back (a snap-back's
    decreasing u): the external work of a path-followed run. :func:`work` is its checked form for curves in u."""
    u, F = check_finite("u", u), check_finite("F", F)
    if np.shape(u) != np.shape(F) or np.ndim(u) != 1:
        raise ValueError(f"u and F must be 1D arrays of the same length, got shapes {np.shape(u)} and {np.shape(F)}")
    return float(np.sum(0.5 * (F[1:] + F[:-1]) * np.diff(u)))


def largest_drop(u, F) -> float:
    """Largest force drop of one recorded step after the peak, as a fraction of the peak (0 if the force never
    falls).

    Under displacement control it tells a force continuous in u from a jump: refining the steps shrinks it in
    proportion to the step where the curve is a graph over u, and leaves it where the structure snaps back or
    drops vertically (the step jumps over a branch that displacement control cannot compute).
    """
    u, F = _curve(u, F)
    i = int(np.argmax(F))
    drops = F[i:-1] - F[i + 1:]
    return float(max(drops.max(initial=0.0), 0.0) / F[i])


def steepest_softening(u, F) -> float:
    """Steepest secant slope of one recorded step after the peak, ``max (F_m - F_m+1) / (u_m+1 - u_m)``, as a
    fraction of the peak per mm (0 if the force never falls; for a curve in u, whose steps have ``du > 0``).

    Under step refinement it converges where the force is continuous in u and doubles with every halving of the
    step where the curve jumps; unlike :func:`largest_drop` it does not depend on where cutbacks shortened a step.
    """
    u, F = _curve(u, F)
    i = int(np.argmax(F))
    du = np.diff(u[i:])
    if np.any(du <= 0.0):
        raise ValueError("steepest_softening needs a displacement that grows in every step after the peak")
    return float(max(((F[i:-1] - F[i + 1:]) / du).max(initial=0.0), 0.0) / F[i])


def softening_displacement(u, F, fraction: float = 0.5) -> float:
    """Displacement from the peak to where the force has first fallen to ``fraction * F_max`` (mm), ``inf`` if never.

    Small means a steep force drop, large a smooth one; by linear interpolation between the recorded steps.
    """
    u, F = _curve(u, F)
    fraction = check_range("fraction", fraction, 0.0, 1.0, low_open=True, high_open=True)
    i = int(np.argmax(F))
    target = fraction * F[i]
    below = np.flatnonzero(F[i:] <= target)
    if below.size == 0:
        return float("inf")
    j = i + int(below[0])
    u_cross = u[j - 1] + (target - F[j - 1]) * (u[j] - u[j - 1]) / (F[j] - F[j - 1])
    return float(u_cross - u[i])


# ---- damage fields ---------------------------------------------------------------------------------------------
def element_areas(mesh) -> np.ndarray:
    """Areas of the straight-sided polygons of a 2D mesh (shoelace formula), mm^2."""
    x, y = mesh.p[0, mesh.t], mesh.p[1, mesh.t]  # (corners, nel)
    return 0.5 * np.abs(np.sum(x * np.roll(y, -1, axis=0) - np.roll(x, -1, axis=0) * y, axis=0))


@dataclass(frozen=True)
class BandWidth:
    """Result of :func:`band_width`: ``width`` (mm), ``area`` (mm^2), ``length`` (mm), principal ``angle``
    (degrees in [0, 180) from the x axis), number of damaged ``elements``."""

    width: float
    area: float
    length: float
    angle: float
    elements: int


def _check_field(mesh, values, name: str = "values"):
    if mesh.p.shape[0] != 2:
        raise ValueError("damage-field metrics need a 2D mesh (use the specimen's plane_mesh)")
    values = np.asarray(values, dtype=float)
    if values.shape != (mesh.t.shape[1],):
        raise ValueError(f"{name} must have one entry per element ({mesh.t.shape[1]}), got shape {values.shape}")
    return values


def _check_band(threshold, length, mirror) -> None:
    """The band's ``threshold`` (a level of a non-negative field, >= 0), its nominal ``length`` (> 0, or None) and
    ``mirror`` (> 0: 2 for a half model)."""
    check_range("threshold", threshold, 0.0, None)
    if length is not None:
        check_range("length", length, 0.0, None, low_open=True)
    check_range("mirror", mirror, 0.0, None, low_open=True)


def band_width(mesh, values, threshold: float = 0.5, *, length: float | None = None, mirror: float = 1.0,
               within: tuple[float, float, float, float] | None = None) -> BandWidth:
    """Width of the damaged band ``{values >= threshold}``: ``mirror * area / length`` (see the module docstring).

    ``length``: the band's nominal length (mm); default: the extent of the damaged elements along their principal
    axis. ``within = (x0, x1, y0, y1)`` keeps only elements whose centre lies in that box. No damaged element
    gives width 0 (and angle NaN: an empty band has no axis). ``values``: a damage field, non-negative.
    """
    values = check_range("values", _check_field(mesh, values), 0.0, None)
    _check_band(threshold, length, mirror)
    centre = mesh.p[:, mesh.t].mean(axis=1)
    damaged = values >= threshold
    if within is not None:
        x0, x1, y0, y1 = within
        damaged &= (centre[0] >= x0) & (centre[0] <= x1) & (centre[1] >= y0) & (centre[1] <= y1)
    if not np.any(damaged):
        return BandWidth(0.0, 0.0, 0.0, float("nan"), 0)
    area_e = element_areas(mesh)[damaged]
    area = float(area_e.sum())
    c = centre[:, damaged]
    mean = c @ area_e / area
    d = c - mean[:, None]
    moments = (d * area_e) @ d.T / area
    _, vectors = np.linalg.eigh(moments)
    axis = vectors[:, -1]
    angle = float(np.degrees(np.arctan2(axis[1], axis[0])) % 180.0)
    if length is None:
        corners = mesh.p[:, mesh.t[:, damaged]].reshape(2, -1)
        s = axis @ corners
        length = float(s.max() - s.min())
    else:
        length = float(check_range("length", length, 0.0, None, low_open=True))
    return BandWidth(mirror * area / length, area, length, angle, int(damaged.sum()))


def cut_width(mesh, values, threshold: float, point, direction, *, mirror: float = 1.0) -> float:
    """Length (mm) of the part of the line ``point + s * direction`` inside elements with ``values >= threshold``.

    Exact for convex straight-sided elements: each damaged element contributes the chord of the line through it
    (Cyrus-Beck clipping against its edges), times ``mirror``.
    """
    values = _check_field(mesh, values)
    n = np.asarray(direction, dtype=float)
    if n.shape != (2,) or not np.linalg.norm(n) > 0:
        raise ValueError(f"direction must be a non-zero 2-vector, got {direction!r}")
    n = n / np.linalg.norm(n)
    p0 = np.asarray(point, dtype=float)
    damaged = np.flatnonzero(values >= threshold)
    if damaged.size == 0:
        return 0.0
    v = mesh.p[:, mesh.t[:, damaged]]  # (2, corners, m)
    x, y = v[0], v[1]
    orientation = np.sign(np.sum(x * np.roll(y, -1, axis=0) - np.roll(x, -1, axis=0) * y, axis=0))
    s_in = np.full(damaged.size, -np.inf)
    s_out = np.full(damaged.size, np.inf)
    empty = np.zeros(damaged.size, dtype=bool)
    for k in range(v.shape[1]):
        a, b = v[:, k], v[:, (k + 1) % v.shape[1]]
        edge = b - a
        outward = orientation * np.array([edge[1], -edge[0]])  # right normal of a counter-clockwise polygon
        num = np.einsum("im,im->m", outward, p0[:, None] - a)  # > 0: the point is outside this edge
        den = outward.T @ n
        parallel = np.abs(den) < 1e-14 * np.linalg.norm(edge, axis=0)
        empty |= parallel & (num > 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = -num / den
        s_out = np.where(~parallel & (den > 0), np.minimum(s_out, s), s_out)
        s_in = np.where(~parallel & (den < 0), np.maximum(s_in, s), s_in)
    chord = np.where(empty, 0.0, np.maximum(s_out - s_in, 0.0))
    return float(mirror * chord.sum())


def transition_ratio(mesh, values, low: float = 0.1, high: float = 0.9, **options) -> float:
    """``band_width(low) / band_width(high)`` with the same ``length``/``mirror``/``within`` (``inf`` if no element
    reaches ``high``): about 1 for a sharp damaged/intact transition, larger for a smooth one."""
    wide = band_width(mesh, values, low, **options)
    core = band_width(mesh, values, high, **options)
    return float(wide.area / core.area) if core.area > 0 else float("inf")


def damaged_components(mesh, values, threshold: float = 0.9, *, min_fraction: float = 0.0, labels: bool = False):
    """Number of connected pieces of ``{values >= threshold}``: two separate cracks give 2, bands that merged
    give 1. Elements sharing a vertex are connected (a band running diagonally through a grid is a staircase of
    elements touching at corners). Pieces smaller than ``min_fraction`` of the damaged area (e.g. a spot at a
    clamped corner) are not counted. ``labels=True`` also returns the piece of every element (-1 where intact),
    the pieces numbered by decreasing area."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components

    values = _check_field(mesh, values)
    damaged = np.flatnonzero(values >= threshold)
    if damaged.size == 0:
        return (0, np.full(values.size, -1)) if labels else 0
    t = mesh.t[:, damaged]
    incidence = csr_matrix((np.ones(t.size), (np.repeat(np.arange(damaged.size), t.shape[0]), t.T.ravel())),
                           shape=(damaged.size, mesh.p.shape[1]))
    count, piece = connected_components(incidence @ incidence.T, directed=False)
    area = np.bincount(piece, element_areas(mesh)[damaged], minlength=count)
    significant = int(np.sum(area >= min_fraction * area.sum()))
    if not labels:
        return significant
    rank = np.empty(count, dtype=int)
    rank[np.argsort(-area, kind="stable")] = np.arange(count)
    out = np.full(values.size, -1)
    out[damaged] = rank[piece]
    return significant, out


def mesh_study(curves: dict, fields: dict | None = None, *, reference=None, threshold: float = 0.5,
               length: float | None = None, mirror: float = 1.0) -> dict:
    """Mesh-independence numbers of a family of runs against the ``reference`` (default: the last key).

    ``curves``: ``{label: (u, F)}``; ``fields``: ``{label: (mesh, values)}`` (optional). Returns per label the
    peak force, its error against the reference, the curve distance, the work and the band width, and overall
    the peak-force spread, the largest curve distance, the energy spread and the band-width spread.
    """
    _check_band(threshold, length, mirror)
    labels = list(curves)
    reference = labels[-1] if reference is None else reference
    u_ref, F_ref = curves[reference]
    u_common = min(float(np.max(u)) for u, _ in curves.values())
    rows = {}
    for label in labels:
        u, F = curves[label]
        F_max, u_peak = peak(u, F)
        row = {"peak_force": F_max, "u_at_peak": u_peak, "work_common": work(u, F, upto=u_common),
               "curve_distance": curve_distance(u, F, u_ref, F_ref)}
        if fields is not None and label in fields:
            mesh, values = fields[label]
            row["band_width"] = band_width(mesh, values, threshold, length=length, mirror=mirror).width
        rows[label] = row
    F_ref_max = rows[reference]["peak_force"]
    for row in rows.values():
        row["peak_error"] = abs(row["peak_force"] - F_ref_max) / F_ref_max
    summary = {"reference": reference, "common_u": u_common,
               "peak_spread": relative_spread([r["peak_force"] for r in rows.values()]),
               "max_curve_distance": max(r["curve_distance"] for k, r in rows.items() if k != reference),
               "work_spread": relative_spread([r["work_common"] for r in rows.values()])}
    widths = [r["band_width"] for r in rows.values() if "band_width" in r]
    if len(widths) >= 2 and min(widths) > 0:
        summary["band_width_spread"] = relative_spread(widths)
    return {"runs": rows, **summary}


def specimen_metrics(specimen, u, F, stiffness_loss, *, threshold: float = 0.5) -> dict:
    """The curve and band metrics of one run on a specimen of :mod:`abrakit.damage.specimens`.

    ``stiffness_loss``: ``1 - f`` (Model I) or ``1 - f_bar`` (Model II) per element. Returns ``peak_force_N``,
    ``u_at_peak_mm``, ``softening_mm`` (peak to half the peak force) and ``softening_relative`` (divided by the
    displacement at the peak), ``work_Nmm``, ``band_width_mm`` (``threshold``; the specimen's ``band_length``
    and ``band_mirror``), ``damaged_pieces`` (stiffness loss >= 0.9, pieces of at least 5 % of the damaged
    area), ``band_angle_deg`` (principal angle of the largest piece) and ``transition_ratio`` (band area at 0.1
    over that at 0.9).
    """
    mesh = specimen.plane_mesh
    _check_field(mesh, check_range("stiffness_loss", stiffness_loss, 0.0, None), "stiffness_loss")
    _check_band(threshold, None, 1.0)
    F_max, u_peak = peak(u, F)
    softening = softening_displacement(u, F, 0.5)
    band = band_width(mesh, stiffness_loss, threshold, length=specimen.band_length, mirror=specimen.band_mirror)
    pieces, labels = damaged_components(mesh, stiffness_loss, 0.9, min_fraction=0.05, labels=True)
    largest = band_width(mesh, np.where(labels == 0, 1.0, 0.0), 0.5) if pieces else None
    return {"peak_force_N": F_max, "u_at_peak_mm": u_peak, "softening_mm": softening,
            "softening_relative": softening / u_peak if u_peak > 0 else float("inf"), "work_Nmm": work(u, F),
            "band_width_mm": band.width, "damaged_pieces": pieces,
            "band_angle_deg": largest.angle if largest is not None else float("nan"),
            "transition_ratio": transition_ratio(mesh, stiffness_loss, 0.1, 0.9, length=specimen.band_length,
                                                 mirror=specimen.band_mirror)}
