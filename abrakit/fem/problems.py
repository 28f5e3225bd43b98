"""Ready-made boundary value problems used by the tests, the benchmark, the demo and the book.

- :func:`plate_with_hole_problem` — quarter plate with a hole pulled at the top edge (Ch. 7.1.1 set-up).
- :func:`thick_cylinder_problem` and :func:`thick_cylinder_solution` — internal pressure on a thick cylinder in
  plane strain, with the classical elastic–perfectly-plastic solution (Hill 1950) for verification.
- :func:`kirsch_displacement` and :func:`kirsch_stress` — elastic plate with a circular hole under remote
  uniaxial tension (Kirsch 1898), plane strain.

Units: N, mm, MPa. Plane-strain forces are per mm of thickness.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import skfem
from scipy.optimize import brentq

from ..materials import TABLE_7_1
from ..validation import (
    check_finite,
    check_number_fields,
    check_option,
    check_poisson,
    check_positive,
    check_range,
    number_arguments,
)
from . import meshes
from .boundary import Dirichlet, surface_load
from .kinematics import vector_basis
from .solver import Solver

#: The plasticity part of Table 7.1 (E, nu, r_p, K_H in MPa), for ``VonMisesPlasticity(**TABLE_7_1_PLASTICITY)``.
TABLE_7_1_PLASTICITY = {k: TABLE_7_1[k] for k in ("E", "nu", "r_p", "K_H")}


PLATE_ELEMENTS = {"Q4": skfem.ElementQuad1, "Q8": skfem.ElementQuadS2, "Q9": skfem.ElementQuad2}


def plate_with_hole_problem(material, *, width=50.0, height=50.0, radius=10.0, displacement=0.05, n_angular=16,
                            n_radial=12, grading=4.0, thickness: float | None = None, element: str = "Q4",
                            bbar: bool | None = None, **solver_options) -> Solver:
    """Quarter plate with a hole, symmetry on ``left``/``bottom``, top edge pulled by ``displacement`` (mm).

    ``thickness=None`` gives plane strain (forces per mm); a number extrudes the mesh into one layer of hexes
    of that thickness (the seed's 3 mm, one element) with ``front`` held in z. The reaction of the top edge is
    recorded as ``F_top`` and its displacement as ``u_top``. ``element``: ``"Q4"`` (bilinear), ``"Q8"``
    (serendipity) or ``"Q9"`` (biquadratic); the quadratic ones sit on the curved 9-node geometry of
    ``meshes.plate_with_hole(order=2)`` (hole edges on the circle). ``bbar`` defaults to True for Q4 (and its
    extruded hexahedra), whose full integration locks in isochoric plastic flow, and to False for Q8/Q9.
    """
    if element not in PLATE_ELEMENTS:
        raise ValueError(f"element must be one of {tuple(PLATE_ELEMENTS)}, got {element!r}")
    linear = element == "Q4"
    if thickness is not None and not linear:
        raise ValueError("thickness (one layer of hexahedra) needs element='Q4'")
    mesh = meshes.plate_with_hole(width, height, radius, n_angular, n_radial, grading, order=1 if linear else 2)
    if thickness is not None:
        mesh = meshes.extrude(mesh, thickness, 1)
    basis = vector_basis(mesh, None if linear else PLATE_ELEMENTS[element]())
    conditions = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y")]
    if thickness is not None:
        conditions.append(Dirichlet.on(basis, "front", "z"))
    conditions.append(Dirichlet.on(basis, "top", "y", displacement, name="top"))
    return Solver(basis, material, conditions, bbar=linear if bbar is None else bbar, **solver_options)


def thick_cylinder_problem(material, *, inner=10.0, outer=20.0, pressure=100.0, n_radial=12, n_angular=12,
                           bbar=True, **solver_options) -> Solver:
    """Quarter of a thick cylinder (plane strain) under internal ``pressure`` (MPa) at load factor 1.

    The radial displacement of the outer surface on the x axis is recorded as ``u_outer`` (mm). B-bar is on
    by default: fully plastic flow is isochoric and the standard bilinear quadrilateral locks.
    """
    mesh = meshes.ring_sector(inner, outer, n_radial, n_angular)
    basis = vector_basis(mesh)
    load = surface_load(basis, "inner", pressure=pressure)
    outer_x = np.intersect1d(Dirichlet.on(basis, "outer", "x").dofs, Dirichlet.on(basis, "bottom", "x").dofs)
    conditions = [Dirichlet.on(basis, "bottom", "y"), Dirichlet.on(basis, "side", "x")]
    return Solver(basis, material, conditions, external_force=lambda lam: lam * load, bbar=bbar,
                  monitors={"outer": outer_x}, **solver_options)


@dataclass(frozen=True)
class ThickCylinderSolution:
    """Elastic–perfectly-plastic thick cylinder, plane strain, von Mises with shear yield k = sigma_0 / sqrt(3).

    Hill's solution: the plastic zone a <= r <= c carries p = k (1 - c^2/b^2 + 2 ln(c/a)); the elastic zone
    c <= r <= b is a cylinder loaded at r = c by k (1 - c^2/b^2). Exact for an incompressible solid
    (nu -> 1/2), where sigma_z is the mean of sigma_r and sigma_theta; for nu < 1/2 the onset of yield differs
    by a term of relative size (1 - 2 nu)^2 (c/b)^4 / 3.
    """

    inner: float
    outer: float
    E: float
    nu: float
    yield_stress: float  # uniaxial sigma_0 (MPa); for the seed's model sigma_0 = sqrt(3/2) r_p

    @property
    def k(self) -> float:
        return self.yield_stress / np.sqrt(3.0)

    @property
    def yield_pressure(self) -> float:
        """First yield at the bore, p_e = k (1 - a^2/b^2) (MPa)."""
        return self.k * (1.0 - (self.inner / self.outer) ** 2)

    @property
    def limit_pressure(self) -> float:
        """Collapse pressure p_L = (2/sqrt(3)) sigma_0 ln(b/a) (MPa)."""
        return 2.0 * self.k * np.log(self.outer / self.inner)

    def plastic_radius(self, pressure: float) -> float:
        """Radius c of the elastic–plastic boundary at the given pressure (mm)."""
        a, b = self.inner, self.outer
        pressure = check_range("pressure", pressure, 0.0, self.limit_pressure)
        if pressure <= self.yield_pressure:
            return a
        return brentq(lambda c: self.k * (1 - c**2 / b**2 + 2 * np.log(c / a)) - pressure, a, b, xtol=1e-14)

    def outer_displacement(self, pressure: float) -> float:
        """Radial displacement of the outer surface (mm): elastic Lamé solution of the zone c <= r <= b."""
        a, b, E, nu = self.inner, self.outer, self.E, self.nu
        if pressure <= self.yield_pressure:
            return 2 * (1 - nu**2) * pressure * a**2 * b / (E * (b**2 - a**2))
        c = self.plastic_radius(pressure)
        return 2 * (1 - nu**2) * self.k * c**2 / (E * b)


@number_arguments
def thick_cylinder_solution(inner: float, outer: float, E: float, nu: float, yield_stress:
                            float) -> ThickCylinderSolution:
    check_positive("inner", inner)
    check_range("outer", outer, inner, None, low_open=True)
    return ThickCylinderSolution(inner, outer, check_positive("E", E), nu, check_positive("yield_stress", yield_stress))


def kirsch_displacement(x, y, *, remote_stress, radius, E, nu):
    """Plane-strain displacement (mm) of an infinite plate with a hole of ``radius`` under remote sigma_xx."""
    x, y, remote_stress = check_finite("x", x), check_finite("y", y), check_finite("remote_stress", remote_stress)
    radius, E, nu = check_positive("radius", radius), check_positive("E", E), check_poisson("nu", nu)
    mu, kappa = E / (2 * (1 + nu)), 3 - 4 * nu
    r, th = np.hypot(x, y), np.arctan2(y, x)
    s, a = remote_stress / (4 * mu), radius
    c2 = np.cos(2 * th)
    u_r = s * (r * ((kappa - 1) / 2 + c2) + a**2 / r * (1 + (1 + kappa) * c2) - a**4 / r**3 * c2)
    u_t = s * ((1 - kappa) * a**2 / r - r - a**4 / r**3) * np.sin(2 * th)
    return u_r * np.cos(th) - u_t * np.sin(th), u_r * np.sin(th) + u_t * np.cos(th)


def kirsch_stress(x, y, *, remote_stress, radius):
    """Kirsch stresses (sigma_xx, sigma_yy, sigma_xy) in MPa; sigma_xx = 3 sigma at (0, radius)."""
    x, y, remote_stress = check_finite("x", x), check_finite("y", y), check_finite("remote_stress", remote_stress)
    radius = check_positive("radius", radius)
    r, th = np.hypot(x, y), np.arctan2(y, x)
    s, q2, q4 = remote_stress / 2, (radius / r) ** 2, (radius / r) ** 4
    c2, s2 = np.cos(2 * th), np.sin(2 * th)
    s_rr = s * (1 - q2) + s * (1 - 4 * q2 + 3 * q4) * c2
    s_tt = s * (1 + q2) - s * (1 + 3 * q4) * c2
    s_rt = -s * (1 + 2 * q2 - 3 * q4) * s2
    c, sn = np.cos(th), np.sin(th)
    return (s_rr * c * c + s_tt * sn * sn - 2 * s_rt * sn * c,
            s_rr * sn * sn + s_tt * c * c + 2 * s_rt * sn * c,
            (s_rr - s_tt) * sn * c + s_rt * (c * c - sn * sn))


@number_arguments
def strip(length: float, n: int, dim: int = 2) -> skfem.Mesh:
    """A bar ``length`` × 1 (× 1 in 3D) mm of ``n`` bilinear (trilinear) elements along x, with the boundaries
    ``left`` (x = 0), ``right`` (x = length), ``bottom`` (y = 0) and, in 3D, ``back`` (z = 0)."""
    x, unit = np.linspace(0.0, length, n + 1), np.array([0.0, 1.0])
    mesh = skfem.MeshQuad.init_tensor(x, unit) if dim == 2 else skfem.MeshHex.init_tensor(x, unit, unit)
    faces = {"left": lambda p: np.isclose(p[0], 0.0), "right": lambda p: np.isclose(p[0], length),
             "bottom": lambda p: np.isclose(p[1], 0.0)}
    if dim == 3:
        faces["back"] = lambda p: np.isclose(p[2], 0.0)
    return mesh.with_boundaries(faces)


def element_opening(basis, element: int) -> tuple[np.ndarray, np.ndarray]:
    """(x-DOFs of the element's right nodes, of its left nodes): its opening, for path following by opening."""
    mesh = basis.mesh
    nodes = mesh.t[:, element]
    x = mesh.p[0, nodes]
    dofs = basis.nodal_dofs[0, nodes]
    return dofs[np.isclose(x, x.max())], dofs[np.isclose(x, x.min())]


@dataclass(frozen=True)
class SofteningBar:
    """A bar of ``n`` elements, length ``length`` (mm), unit cross-section, pulled at its right end, with the
    middle element weaker (peak strain ``eps_0``) than the others (``strength`` × ``eps_0``): the classical
    snap-back test of path following (:mod:`abrakit.fem.pathfollow`). Material
    :class:`~abrakit.materials.softening.LinearSofteningDamage` with ``nu = 0`` (so the plane-strain strip of
    ``n × 1`` bilinear elements is exactly one-dimensional).

    Closed form: up to the peak F = E v / L; after it the weak element (size h = L/n) softens while the others
    unload elastically, so with σ from f_t = E eps_0 down to 0

        v(σ) = h (eps_0 + (f_t − σ)(eps_f − eps_0)/f_t) + (L − h) σ / E,      F = σ,

    which turns back (snap-back) when h (eps_f − eps_0) / f_t < (L − h) / E. The energy dissipated to complete
    separation is G·A = ½ f_t eps_f h.
    """

    n: int
    length: float = 100.0
    E: float = 1000.0
    eps_0: float = 1e-3
    eps_f: float = 2e-2
    strength: float = 1.5

    def __post_init__(self):
        check_number_fields(self)
        check_range("n", self.n, 1, None)
        check_positive("length", self.length)
        check_positive("E", self.E)
        check_positive("eps_0", self.eps_0)
        check_range("eps_f", self.eps_f, self.eps_0, None, low_open=True)
        check_range("strength", self.strength, 1.0, None, low_open=True)

    @property
    def h(self) -> float:
        return self.length / self.n

    @property
    def f_t(self) -> float:
        return self.E * self.eps_0

    @property
    def snaps_back(self) -> bool:
        return self.h * (self.eps_f - self.eps_0) / self.f_t < (self.length - self.h) / self.E

    @property
    def fracture_energy(self) -> float:
        """G·A = ½ f_t eps_f h (N mm), the energy dissipated to complete separation."""
        return 0.5 * self.f_t * self.eps_f * self.h

    @property
    def peak_displacement(self) -> float:
        return self.eps_0 * self.length

    def softening_displacement(self, force):
        """v(F) on the softening branch (mm)."""
        return (self.h * (self.eps_0 + (self.f_t - force) * (self.eps_f - self.eps_0) / self.f_t)
                + (self.length - self.h) * force / self.E)

    def force(self, v, branch):
        """F(v) on the ``branch`` (array of "elastic", "softening" or "broken") of the closed form (N)."""
        v = np.asarray(v, dtype=float)
        slope = self.h * (self.eps_f - self.eps_0) / self.f_t - (self.length - self.h) / self.E   # dv/d(−F)
        branch = np.asarray(branch)
        return np.select([branch == "elastic", branch == "softening"],
                         [self.E * v / self.length, self.f_t - (v - self.peak_displacement) / slope], 0.0)

    def branch(self, v, F, tol: float = 1e-6):
        """The branch a computed point (v, F) lies on: elastic (on the line F = E v/L), broken (F ≈ 0 beyond the
        peak), otherwise softening."""
        v, F = np.asarray(v, dtype=float), np.asarray(F, dtype=float)
        elastic = np.abs(F - self.E * v / self.length) <= tol * self.f_t
        broken = ~elastic & (np.abs(F) <= tol * self.f_t)
        return np.select([elastic, broken], ["elastic", "broken"], "softening")

    def solver(self, *, displacement: float | None = None, load: str = "displacement", follow: bool = True,
               **options):
        """The bar as a :class:`~abrakit.fem.pathfollow.PathFollowingSolver` (``follow=True``, with the weak
        element's opening for ``method="opening"``) or a load-controlled :class:`Solver`. ``load="displacement"``:
        the right end is pulled to ``displacement`` (mm, default 2 eps_f h + the elastic stretch at the peak) at
        λ = 1; ``load="force"``: a force 2 f_t (N) pulls it at λ = 1. Its force and mean displacement are recorded
        as ``F_right`` and ``u_right``."""
        from ..materials.softening import LinearSofteningDamage
        from .pathfollow import PathFollowingSolver

        mesh = strip(self.length, self.n)
        basis = vector_basis(mesh)
        weak = np.zeros(mesh.nelements, bool)
        weak[self.n // 2] = True
        eps_0 = np.where(weak, self.eps_0, self.strength * self.eps_0)[:, None] * np.ones((1, basis.X.shape[-1]))
        material = LinearSofteningDamage(self.E, 0.0, eps_0, self.eps_f)
        if displacement is None:
            displacement = 2.0 * self.eps_f * self.h + self.peak_displacement
        conditions = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y")]
        if check_option("load", load, ("displacement", "force")) == "displacement":
            conditions.append(Dirichlet.on(basis, "right", "x", displacement, name="right"))
        else:
            f_hat = surface_load(basis, "right", traction=(2.0 * self.f_t, 0.0))
            options.update(external_force=lambda lam: lam * f_hat,
                           monitors={"right": basis.get_dofs("right").nodal["u^1"]})
        if not follow:
            return Solver(basis, material, conditions, **options)
        options.setdefault("opening", element_opening(basis, self.n // 2))    # the weak element's: right − left
        return PathFollowingSolver(basis, material, conditions, **options)
