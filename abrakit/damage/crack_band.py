"""Finite element problems of the anisotropic softening damage (seed 001) with a closed form to test against.

:class:`CrackBandBar` is the crack-band test: a plane-strain strip of ``n`` elements pulled at one end, its middle
element a little weaker (``weakening`` × sigma_c), material
:class:`~abrakit.materials.anisotropic_damage.AnisotropicSofteningDamage` with nu = 0 and the band width of each
point = the extent of its element along the crack normal (``projected_band_width``). The weak element cracks with
normal x; the others unload elastically, so with the traction ``sigma`` carried (unit cross-section)

    v(sigma) = L sigma / E + delta(sigma),       S_I(delta) = sigma,

and the energy dissipated to separation is ``G_Ic × A`` whatever ``n`` (the crack band keeps it mesh
independent). The bar snaps back when ``L/E > max(-d delta/d sigma) = delta_c / sigma_w`` (linear law), which does
not depend on ``n``; a single element wider than ``h_max = 2 E G_Ic / sigma_w^2`` is refused.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import skfem

from ..fem.boundary import Dirichlet
from ..fem.kinematics import vector_basis
from ..fem.pathfollow import PathFollowingSolver
from ..fem.problems import element_opening, strip
from ..fem.solver import Solver
from ..materials.anisotropic_damage import AnisotropicSofteningDamage, projected_band_width
from ..materials.softening_laws import softening_law
from ..validation import check_number_fields, check_option, check_positive, check_range

#: Seed 001's material on the steel specimens of Ch. 7 (E, nu of Table 7.1; MPa, N/mm). Seed 001 gives no numbers
#: for a steel: sigma_c and tau_c are chosen so that the double notch peaks near Model I and II (about 10 kN),
#: G_IIc = 2 G_Ic; the toughness G_Ic (N/mm) is the parameter of a run, as beta and alpha are for Model I and II.
STEEL_SPECIMENS = {"E": 200000.0, "nu": 0.33, "sigma_c": 120.0, "tau_c": 80.0, "mode_II_ratio": 2.0,
                   "surface": "ovoid"}


def specimen_material(basis, toughness: float, mirror_y: bool = False, **changes) -> AnisotropicSofteningDamage:
    """:data:`STEEL_SPECIMENS` (updated by ``changes``, e.g. ``surface=0``) with ``G_Ic = toughness`` on a
    plane-strain basis, band width by projection (doubled on the symmetry line y = 0 with ``mirror_y``)."""
    unknown = set(changes) - set(STEEL_SPECIMENS)
    if unknown:
        raise ValueError(f"material option(s) {sorted(unknown)} unknown; choose from {sorted(STEEL_SPECIMENS)}")
    p = {**STEEL_SPECIMENS, **changes}
    return AnisotropicSofteningDamage(p["E"], p["nu"], p["sigma_c"], p["tau_c"], toughness,
                                      p["mode_II_ratio"] * toughness,
                                      band_width=projected_band_width(basis, mirror_y), plane=True,
                                      surface=p["surface"])


@dataclass(frozen=True)
class CrackBandBar:
    """A strip ``length`` × 1 mm of ``n`` bilinear elements (plane strain, unit thickness; ``dim=3``: a 1 × 1 mm
    bar of ``n`` trilinear hexahedra), nu = 0, pulled at its right end; the middle element's strength is
    ``weakening`` × ``sigma_c`` (MPa)."""

    n: int
    length: float = 100.0
    E: float = 1000.0
    sigma_c: float = 1.0
    tau_c: float = 1.0
    G_Ic: float = 0.1
    G_IIc: float = 0.1
    weakening: float = 0.95
    softening: str = "linear"
    surface: str = "ovoid"
    dim: int = 2

    def __post_init__(self):
        check_number_fields(self)
        check_range("n", self.n, 1, None)
        check_option("dim", self.dim, (2, 3))
        for name in ("length", "E", "sigma_c", "tau_c", "G_Ic", "G_IIc"):
            check_positive(name, getattr(self, name))
        check_range("weakening", self.weakening, 0.0, 1.0, low_open=True, high_open=True)

    @property
    def h(self) -> float:
        return self.length / self.n

    @property
    def strength(self) -> float:
        """sigma_w, the weak element's strength (MPa): the peak force per unit area."""
        return self.weakening * self.sigma_c

    @property
    def fracture_energy(self) -> float:
        """G_Ic · A (N mm) with A = 1 mm²."""
        return self.G_Ic

    def softening_displacement(self, force):
        """v(F) on the softening branch (mm): L F/E + delta(F)."""
        force = np.asarray(force, dtype=float)
        delta = softening_law(self.softening).opening(force, self.strength, self.G_Ic)
        return self.length * force / self.E + delta

    @property
    def snaps_back(self) -> bool:
        """dv/dF > 0 just after the peak: L/E > max|dδ/dS| = k G_Ic/σ_w² (k = 2 linear, 1 exponential)."""
        return self.length / self.E > softening_law(self.softening).band_factor * self.G_Ic / self.strength**2

    def material(self, basis) -> AnisotropicSofteningDamage:
        nqp = basis.X.shape[-1]
        relative = np.ones((basis.mesh.nelements, nqp))
        relative[self.n // 2] = self.weakening
        return AnisotropicSofteningDamage(self.E, 0.0, self.sigma_c, self.tau_c, self.G_Ic, self.G_IIc,
                                          band_width=projected_band_width(basis), softening_I=self.softening,
                                          softening_II=self.softening, surface=self.surface, plane=self.dim == 2,
                                          relative_strength=relative)

    def solver(self, *, displacement: float | None = None, follow: bool = True, **options):
        """A :class:`~abrakit.fem.pathfollow.PathFollowingSolver` (``follow=True``, steered by the weak element's
        opening) or a displacement-controlled :class:`~abrakit.fem.Solver`; the right end moves to
        ``displacement`` (default: past separation) at λ = 1 and its force is recorded as ``F_right``."""
        basis = vector_basis(strip(self.length, self.n, self.dim))
        material = self.material(basis)
        if displacement is None:
            displacement = 1.5 * float(self.softening_displacement(1e-3 * self.strength))
        conditions = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"),
                      Dirichlet.on(basis, "right", "x", displacement, name="right")]
        if self.dim == 3:
            conditions.append(Dirichlet.on(basis, "back", "z"))
        if not follow:
            return Solver(basis, material, conditions, **options)
        options.setdefault("opening", element_opening(basis, self.n // 2))
        return PathFollowingSolver(basis, material, conditions, **options)


@dataclass(frozen=True)
class DoubleCantileverBeam:
    """Upper half of a double cantilever beam (plane strain, unit thickness): ``length`` × ``arm`` (mm), a
    pre-crack of length ``crack`` from the left end along y = 0, the ligament y = 0, x > crack held in y (symmetry),
    the left edge pulled up by the arm deflection ``delta`` (u_y uniform, u_x free) and u_x held at the right end of
    the ligament. Only the row of elements along y = 0 may crack (the others are 10 times stronger and 1000
    times tougher, which widens their band limit tenfold); its crack band is twice its height, because the half
    model holds half of the band. The row runs beside the pre-crack too: a strong element there, with its corner
    on the held ligament, would tie the arm down at the initial crack tip. ``G_IIc`` only matters where the
    ligament shears, which symmetry forbids; it is kept large enough for the band limit of mode II.

    LEFM (linear elastic fracture mechanics) for the half model: with the compliance C(a) = delta/P of a sharp
    crack of length a, the crack grows when P² C'(a)/2 = G_Ic/2, i.e. P = sqrt(G_Ic / C'(a)), at delta = C(a) P.
    Beam theory gives C = 4 (a + chi h)³/(E' h³) (h = ``arm``, E' = E/(1 - nu²), chi = 0 simple, 0.64 with the
    root rotation of Kanninen 1973), so P = sqrt(G_Ic E' h³ / 12) / (a + chi h); :meth:`lefm_curve` instead
    differentiates the compliance of the elastic finite element model with sharp cracks (``compliance``), an
    independent reference.
    """

    length: float = 100.0
    arm: float = 10.0
    crack: float = 30.0
    E: float = 3000.0
    nu: float = 0.3
    sigma_c: float = 30.0
    G_Ic: float = 0.5
    G_IIc: float = 2.0
    element: float = 0.5
    growth: float = 1.25
    softening: str = "linear"

    def __post_init__(self):
        check_number_fields(self)
        for name in ("length", "arm", "E", "sigma_c", "G_Ic", "G_IIc", "element"):
            check_positive(name, getattr(self, name))
        check_range("crack", self.crack, 0.0, self.length, low_open=True, high_open=True)
        check_range("growth", self.growth, 1.0, 3.0)

    @property
    def plane_modulus(self) -> float:
        """E' = E / (1 - nu²) (MPa)."""
        return self.E / (1.0 - self.nu**2)

    def mesh(self) -> skfem.MeshQuad:
        """Columns of width ``element``; rows of height ``element`` at the ligament growing by ``growth``."""
        x = np.linspace(0.0, self.length, int(round(self.length / self.element)) + 1)
        rows, y = [0.0], self.element
        while rows[-1] + y < self.arm - 1e-9:
            rows.append(rows[-1] + y)
            y *= self.growth
        y = np.append(rows, self.arm) if self.arm - rows[-1] > 0.3 * y / self.growth else np.append(rows[:-1],
                                                                                                      self.arm)
        return skfem.MeshQuad.init_tensor(x, y)

    def _conditions(self, basis, crack: float, delta: float):
        mesh = basis.mesh
        ligament = np.isclose(mesh.p[1], 0.0) & (mesh.p[0] >= crack - 1e-9)
        corner = np.isclose(mesh.p[1], 0.0) & np.isclose(mesh.p[0], self.length)
        left = np.isclose(mesh.p[0], 0.0)
        dofs = np.asarray(basis.nodal_dofs)
        return [Dirichlet(dofs[1, ligament], 0.0), Dirichlet(dofs[0, corner], 0.0),
                Dirichlet(dofs[1, left], delta, name="load")]

    def material(self, basis) -> AnisotropicSofteningDamage:
        mesh = basis.mesh
        nqp = basis.X.shape[-1]
        bottom = mesh.p[1, mesh.t].min(axis=0)
        height = mesh.p[1, mesh.t].max(axis=0) - bottom
        ligament = np.isclose(bottom, 0.0)                # the whole first row: beside the pre-crack it is free
        strength = np.where(ligament, 1.0, 10.0)[:, None] * np.ones((1, nqp))
        width = np.where(ligament, 2.0 * height, height)[:, None] * np.ones((1, nqp))
        return AnisotropicSofteningDamage(self.E, self.nu, self.sigma_c, self.sigma_c, self.G_Ic, self.G_IIc,
                                          band_width=width, softening_I=self.softening, softening_II=self.softening,
                                          plane=True, relative_strength=strength, relative_toughness=strength**3,
                                          crack_normal=(0.0, 1.0, 0.0))

    def solver(self, delta: float, *, follow: bool = True, material=None, **options) -> Solver:
        """The damage model under the arm deflection ``delta`` (mm) at λ = 1; force ``F_load``, deflection
        ``u_load``. ``follow``: a :class:`~abrakit.fem.pathfollow.PathFollowingSolver` (dissipation control past
        the peak; each ligament element that fails releases its energy in a small snap-back), else a
        displacement-controlled :class:`~abrakit.fem.Solver`. ``material``: a function of the basis that returns
        the material (default :meth:`material`, whose crack plane is the ligament's)."""
        if material is not None and not callable(material):
            raise TypeError(f"material must be a function of the basis or None, got {type(material).__name__}")
        basis = vector_basis(self.mesh())
        arguments = (basis, (material or self.material)(basis), self._conditions(basis, self.crack, delta))
        return PathFollowingSolver(*arguments, **options) if follow else Solver(*arguments, **options)

    def compliance(self, cracks) -> np.ndarray:
        """delta/P (mm/N) of the elastic half model with sharp cracks of the given lengths (same mesh)."""
        from ..materials import LinearElastic

        basis = vector_basis(self.mesh())
        elastic = LinearElastic(self.E, self.nu)
        out = []
        for a in np.atleast_1d(cracks):
            solver = Solver(basis, elastic, self._conditions(basis, float(a), 1.0))
            result = solver.run(progress=False)
            out.append(1.0 / result.curves["F_load"][-1])
        return np.array(out)

    def beam_theory(self, delta, chi: float = 0.64):
        """P(delta) on the LEFM propagation branch of beam theory with the crack length a + chi h (N per mm)."""
        delta = np.asarray(delta, dtype=float)
        # P = k/(a + chi h), delta = 4 P (a + chi h)^3/(E' h^3)  =>  a_eff = (delta E' h^3 / (4 k))^(1/2)
        k = np.sqrt(self.G_Ic * self.plane_modulus * self.arm**3 / 12.0)
        a_eff = np.sqrt(delta * self.plane_modulus * self.arm**3 / (4.0 * k))
        return k / a_eff

    def lefm_curve(self, cracks) -> tuple[np.ndarray, np.ndarray]:
        """(delta, P) of LEFM propagation at the crack lengths ``cracks`` from the finite element compliance
        (differentiated by a cubic spline through C(a))."""
        from scipy.interpolate import CubicSpline

        cracks = np.asarray(cracks, dtype=float)
        spline = CubicSpline(cracks, self.compliance(cracks))
        force = np.sqrt(self.G_Ic / spline(cracks, 1))
        return spline(cracks) * force, force
