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
from ..fem.solver import Solver
from ..materials.anisotropic_damage import AnisotropicSofteningDamage, projected_band_width
from ..materials.softening_laws import softening_law
from ..validation import check_option, check_positive, check_range


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
        law = softening_law(self.softening)
        delta_c = law.failure_opening(self.strength, self.G_Ic)
        if self.softening == "linear":
            delta = delta_c * (1.0 - force / self.strength)
        else:
            delta = -self.G_Ic / self.strength * np.log(force / self.strength)
        return self.length * force / self.E + delta

    @property
    def snaps_back(self) -> bool:
        return self.length / self.E > 2.0 * self.G_Ic / self.strength ** 2 * (self.softening == "linear") + (
            self.G_Ic / self.strength ** 2 * (self.softening == "exponential"))

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
        x, unit = np.linspace(0.0, self.length, self.n + 1), np.array([0.0, 1.0])
        mesh = (skfem.MeshQuad.init_tensor(x, unit) if self.dim == 2 else skfem.MeshHex.init_tensor(x, unit, unit))
        faces = {"left": lambda p: np.isclose(p[0], 0.0), "right": lambda p: np.isclose(p[0], self.length),
                 "bottom": lambda p: np.isclose(p[1], 0.0), "back": lambda p: np.isclose(p[-1], 0.0)}
        mesh = mesh.with_boundaries(faces if self.dim == 3 else {k: v for k, v in faces.items() if k != "back"})
        basis = vector_basis(mesh)
        material = self.material(basis)
        if displacement is None:
            displacement = 1.5 * float(self.softening_displacement(1e-3 * self.strength))
        conditions = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"),
                      Dirichlet.on(basis, "right", "x", displacement, name="right")]
        if self.dim == 3:
            conditions.append(Dirichlet.on(basis, "back", "z"))
        if not follow:
            return Solver(basis, material, conditions, **options)
        nodes = mesh.t[:, self.n // 2]
        at = mesh.p[0, nodes]
        dofs = basis.nodal_dofs[0, nodes]
        options.setdefault("opening", (dofs[np.isclose(at, at.max())], dofs[np.isclose(at, at.min())]))
        return PathFollowingSolver(basis, material, conditions, **options)
