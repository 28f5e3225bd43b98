"""Rigid indenters of the single scratch test (Sec. 8.2.1) as analytic surfaces, and the indenter path.

The tip is not meshed: a rigid grain is a surface of revolution whose signed distance, outward normal, closest
point and normal gradient are closed-form, so the contact search of Sec. 8.1.1 ("a search for the closest point")
is one vectorised evaluation per surface point.

Axes (Fig. 8.1): the specimen's top surface is the plane y = 0 with the block below (y < 0); the tip indents
along −y and slides along +z; the half model's symmetry plane is x = 0. Indenters keep their axis parallel to y
and are placed by their apex ``tip`` (the lowest point of the tip, shape (3,)). Units: mm (µm values as mm).

Sign convention shared with :mod:`abrakit.scratch.contact`: the gap g_N is the signed distance of a specimen
point from the indenter surface, positive when open, negative when the point penetrates the tip; the normal n
is the indenter's outward unit normal at the closest point, so a penetrating point is pushed along +n and
``x = closest + g_N n``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from abrakit.validation import check_finite, check_number_fields, check_positive, check_range, check_shape

E_Y = np.array([0.0, 1.0, 0.0])
"""Indenter axis (pointing up, away from the block)."""


class SurfaceGap(NamedTuple):
    """Closest-point data of specimen points against a rigid indenter, all arrays over the n points.

    gap: (n,) signed normal gap g_N in mm (> 0 open, < 0 penetration);
    normal: (n, 3) outward unit normal of the indenter at the closest point (the gradient of g_N);
    closest: (n, 3) closest point on the indenter surface, ``points = closest + gap * normal``;
    normal_gradient: (n, 3, 3) ∂n/∂x in 1/mm (symmetric; the curvature term of the contact tangent).
    """

    gap: np.ndarray
    normal: np.ndarray
    closest: np.ndarray
    normal_gradient: np.ndarray


def _points_and_tip(points, tip):
    points = check_shape("points", check_finite("points", np.atleast_2d(points)), (None, 3))
    tip = check_shape("tip", check_finite("tip", tip), (3,))
    return points, tip


def _refuse_deep_penetration(gap, radius):
    """A point deeper than the tip radius has no meaningful closest point (the sphere centre, the cone axis)."""
    if np.any(gap <= -radius):
        worst = float(gap.min())
        raise ValueError(
            f"a point penetrates the indenter by {-worst:g} mm, at least the tip radius {radius:g} mm: the "
            "closest point is undefined; this configuration is unphysical (cut the load increment back)"
        )


@dataclass(frozen=True)
class SphericalIndenter:
    """Rigid sphere of radius ``radius`` (mm), the seed's default grain (R = 50 µm = 0.05 mm, Fig. 8.2)."""

    radius: float

    def __post_init__(self):
        check_number_fields(self)
        check_positive("radius", self.radius)

    def gap(self, points, tip) -> SurfaceGap:
        """Signed gap, normal, closest point and ∂n/∂x of ``points`` (n, 3) for the apex at ``tip`` (3,).

        g_N = |x − c| − R with the centre c = tip + R e_y, n = (x − c)/|x − c|, ∂n/∂x = (I − n⊗n)/|x − c|.
        """
        points, tip = _points_and_tip(points, tip)
        R = self.radius
        rel = points - (tip + R * E_Y)
        r = np.linalg.norm(rel, axis=1)
        gap = r - R
        _refuse_deep_penetration(gap, R)
        n = rel / r[:, None]
        dn = (np.eye(3) - n[:, :, None] * n[:, None, :]) / r[:, None, None]
        return SurfaceGap(gap, n, points - gap[:, None] * n, dn)

    def height(self, rho):
        """Height of the surface above the apex at radial distance ``rho`` from the axis, R − √(R² − ρ²), mm.

        Defined for 0 ≤ ρ ≤ R (the lower hemisphere).
        """
        rho = np.asarray(check_range("rho", rho, 0.0, self.radius))
        return _out(self.radius - np.sqrt(self.radius**2 - rho**2))

    def footprint_radius(self, depth):
        """Radius of the tip's section by the plane ``depth`` above the apex, √(2Rd − d²), mm (0 ≤ d ≤ R).

        The geometric contact radius of an indentation to depth d, ignoring sink-in and pile-up; Hertz's elastic
        contact radius is √(R d), smaller (:func:`abrakit.scratch.hertz.hertz_sphere`).
        """
        d = np.asarray(check_range("depth", depth, 0.0, self.radius))
        return _out(np.sqrt(2.0 * self.radius * d - d**2))


@dataclass(frozen=True)
class ConicalIndenter:
    """Rigid cone of half-angle ``half_angle`` (degrees, in (0, 90)) with a spherical tip of radius ``radius`` (mm).

    The sphere joins the cone tangentially on the circle at height R(1 − sin α) above the apex, radius R cos α,
    where α is the half-angle. The seed's tips of Fig. 8.10 have "the cone angle of 60°"; the figure itself is
    missing, and a cone angle names the included (apex) angle, so :meth:`from_included_angle` (default 60°,
    α = 30°) builds them. At the seed's depth d = 3 µm only the spherical cap touches the block for every radius
    of Fig. 8.10 (the cap reaches R(1 − sin 30°) = R/2 ≥ 12.5 µm); the cone matters for deeper scratches.
    """

    radius: float
    half_angle: float

    def __post_init__(self):
        check_number_fields(self)
        check_positive("radius", self.radius)
        check_range("half_angle", self.half_angle, 0.0, 90.0, low_open=True, high_open=True)

    @classmethod
    def from_included_angle(cls, radius: float, included_angle: float = 60.0) -> ConicalIndenter:
        """Cone given by its included (apex) angle in degrees, the "cone angle" of Fig. 8.10 (default 60°)."""
        check_range("included_angle", included_angle, 0.0, 180.0, low_open=True, high_open=True)
        return cls(radius, 0.5 * included_angle)

    @property
    def _alpha(self) -> float:
        return math.radians(self.half_angle)

    @property
    def cap_height(self) -> float:
        """Height above the apex where the spherical cap meets the cone, R(1 − sin α), mm."""
        return self.radius * (1.0 - math.sin(self._alpha))

    def gap(self, points, tip) -> SurfaceGap:
        """Signed gap, normal, closest point and ∂n/∂x of ``points`` (n, 3) for the apex at ``tip`` (3,).

        In the meridian half-plane (ρ, η) about the sphere centre c = tip + R e_y, the cap owns the points with
        ρ sin α + η cos α ≤ 0 (below the normal line through the tangency circle): g_N = |x − c| − R. The others
        see the cone generator: g_N = ρ cos α − η sin α − R, n = cos α e_ρ − sin α e_y and
        ∂n/∂x = cos α e_φ⊗e_φ / ρ. Both pieces agree in g_N and n on the tangency circle.
        """
        points, tip = _points_and_tip(points, tip)
        R, a = self.radius, self._alpha
        rel = points - (tip + R * E_Y)
        eta = rel[:, 1]
        radial = rel - eta[:, None] * E_Y
        rho = np.linalg.norm(radial, axis=1)
        on_cap = rho * math.sin(a) + eta * math.cos(a) <= 0.0

        r = np.linalg.norm(rel, axis=1)
        gap = np.where(on_cap, r - R, rho * math.cos(a) - eta * math.sin(a) - R)
        _refuse_deep_penetration(gap, R)

        # Off the cap rho > 0 holds (rho = 0 there means a penetration deeper than R, refused above).
        safe_rho = np.where(rho > 0.0, rho, 1.0)
        e_rho = radial / safe_rho[:, None]
        n_cap = rel / r[:, None]
        n_cone = math.cos(a) * e_rho - math.sin(a) * E_Y
        n = np.where(on_cap[:, None], n_cap, n_cone)

        eye = np.eye(3)
        dn_cap = (eye - n_cap[:, :, None] * n_cap[:, None, :]) / r[:, None, None]
        e_phi_phi = eye - E_Y[:, None] * E_Y[None, :] - e_rho[:, :, None] * e_rho[:, None, :]
        dn_cone = math.cos(a) * e_phi_phi / safe_rho[:, None, None]
        dn = np.where(on_cap[:, None, None], dn_cap, dn_cone)
        return SurfaceGap(gap, n, points - gap[:, None] * n, dn)

    def height(self, rho):
        """Height of the surface above the apex at radial distance ``rho`` (≥ 0) from the axis, mm.

        R − √(R² − ρ²) on the cap (ρ ≤ R cos α), R(1 − sin α) + (ρ − R cos α)/tan α on the cone.
        """
        rho = np.asarray(check_range("rho", rho, 0.0, None))
        R, a = self.radius, self._alpha
        rho_t = R * math.cos(a)
        cap = R - np.sqrt(np.maximum(R**2 - np.minimum(rho, rho_t) ** 2, 0.0))
        return _out(np.where(rho <= rho_t, cap, self.cap_height + (rho - rho_t) / math.tan(a)))

    def footprint_radius(self, depth):
        """Radius of the tip's section by the plane ``depth`` (≥ 0) above the apex, mm (no sink-in/pile-up).

        √(2Rd − d²) while d ≤ R(1 − sin α), then R cos α + (d − R(1 − sin α)) tan α.
        """
        d = np.asarray(check_range("depth", depth, 0.0, None))
        R, a = self.radius, self._alpha
        h_t = self.cap_height
        cap = np.sqrt(np.maximum(2.0 * R * np.minimum(d, h_t) - np.minimum(d, h_t) ** 2, 0.0))
        return _out(np.where(d <= h_t, cap, R * math.cos(a) + (d - h_t) * math.tan(a)))


def _out(x):
    x = np.asarray(x)
    return float(x) if x.ndim == 0 else x


@dataclass(frozen=True)
class ScratchPath:
    """Displacement-controlled path of the indenter apex (Sec. 8.2.1), driven by a pseudo-time τ.

    τ ∈ [0, 1] indentation: the apex moves along −y from ``clearance`` above the surface to ``depth`` below it;
    τ ∈ [1, 2] scratching: it slides by ``slide`` along +z at constant depth, from ``z_start`` to ``z_end``;
    τ ∈ [2, 3] unloading (if ``unload``): it lifts back to ``clearance`` at z_end, so the groove can be read
    both with the tip in contact (τ = 2) and after unloading (τ = 3), as the seed discusses.
    The apex stays on the symmetry plane x = 0. All lengths in mm, e.g. the seed's default scene
    ``ScratchPath(depth=0.002, slide=0.1, z_start=...)``.

    An indenter that starts inside the block (``clearance`` < 0) is refused.
    """

    depth: float
    slide: float
    z_start: float = 0.0
    clearance: float = 0.0
    unload: bool = True

    def __post_init__(self):
        check_number_fields(self)
        check_positive("depth", self.depth)
        check_positive("slide", self.slide, allow_zero=True)
        check_finite("z_start", self.z_start)
        clearance = check_finite("clearance", self.clearance)
        if clearance < 0.0:
            raise ValueError(
                f"the indenter starts inside the block: its apex is {-clearance:g} mm below the surface y = 0 "
                "(clearance must be >= 0)"
            )

    @property
    def z_end(self) -> float:
        """z of the apex at the end of the slide, mm."""
        return self.z_start + self.slide

    @property
    def end(self) -> float:
        """Last pseudo-time of the path: 3 with unloading, else 2."""
        return 3.0 if self.unload else 2.0

    def position(self, tau):
        """Apex position at pseudo-time ``tau`` (scalar or array of shape s) as an array of shape s + (3,), mm."""
        tau = np.asarray(check_range("tau", tau, 0.0, self.end))
        indent = np.clip(tau, 0.0, 1.0)
        lift = np.clip(tau - 2.0, 0.0, 1.0)
        y = self.clearance - (self.clearance + self.depth) * (indent - lift)
        z = self.z_start + self.slide * np.clip(tau - 1.0, 0.0, 1.0)
        return np.stack([np.zeros_like(y), y, z], axis=-1)

    def phase(self, tau):
        """``"indentation"``, ``"scratching"`` or ``"unloading"`` (a str, or an array of str for array input)."""
        tau = np.asarray(check_range("tau", tau, 0.0, self.end))
        phase = np.select([tau <= 1.0, tau <= 2.0], ["indentation", "scratching"], default="unloading")
        return str(phase) if phase.ndim == 0 else phase


class FineZone(NamedTuple):
    """The finely meshed zone under the scratch (Fig. 8.3), mm: z_min ≤ z ≤ z_max, |x| ≤ x_max, −depth ≤ y ≤ 0."""

    z_min: float
    z_max: float
    x_max: float = math.inf
    depth: float = math.inf


def check_path(path: ScratchPath, fine_zone, indenter=None) -> ScratchPath:
    """Refuse a path whose contact leaves the fine zone; return ``path`` unchanged when it fits.

    ``fine_zone`` is a :class:`FineZone` or a pair ``(z_min, z_max)``. With ``indenter`` given, the check covers
    the whole footprint: the apex path widened by the tip's geometric footprint radius at the scratch depth
    (``indenter.footprint_radius(path.depth)``) must lie in z_min ≤ z ≤ z_max and |x| ≤ x_max; without it, only
    the apex path is checked. The scratch depth must not exceed the zone's depth.
    """
    zone = FineZone(*fine_zone)
    if not zone.z_min < zone.z_max:
        raise ValueError(f"fine_zone must have z_min < z_max, got {zone.z_min!r}, {zone.z_max!r}")
    slack = 1e-12 * max(1.0, abs(zone.z_min), abs(zone.z_max))    # rounding of z_start + slide
    a = 0.0 if indenter is None else float(indenter.footprint_radius(path.depth))
    what = "the apex" if indenter is None else f"the contact footprint (radius {a:g} mm)"
    if path.z_end + a > zone.z_max + slack:
        raise ValueError(
            f"the scratch slides past the end of the fine zone: {what} reaches z = {path.z_end + a:g} mm, the fine "
            f"zone ends at z_max = {zone.z_max:g} mm; shorten the slide or extend the fine zone"
        )
    if path.z_start - a < zone.z_min - slack:
        raise ValueError(
            f"the scratch starts before the fine zone: {what} reaches back to z = {path.z_start - a:g} mm, the fine "
            f"zone begins at z_min = {zone.z_min:g} mm; move z_start or extend the fine zone"
        )
    if a > zone.x_max + slack:
        raise ValueError(f"{what} is wider than the fine zone's half-width x_max = {zone.x_max:g} mm")
    if path.depth > zone.depth:
        raise ValueError(f"the scratch depth {path.depth:g} mm exceeds the fine zone's depth {zone.depth:g} mm")
    return path
