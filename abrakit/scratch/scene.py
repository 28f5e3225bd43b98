"""The single scratch test of Sec. 8.2.1 as a 3D finite element scene: specimen, material, mesh and path.

The seed's set-up (Fig. 8.1–8.3, Table 8.1/8.2), in the axes of :mod:`abrakit.scratch.indenters`:

* specimen: a 200 × 100 × 15 µm block of St-52 (length 200 µm along the scratch z, width 100 µm across it along
  x, thickness 15 µm along y), top face y = 0; the half model x ≥ 0 with the symmetry plane x = 0 (u_x = 0
  there, "the displacement along the x-axis is zero on the symmetry plane"); "the other surfaces of the specimen
  are fixed": u = 0 on x = 50 µm, on the bottom y = −15 µm and on both ends z = 0, 200 µm. The top face is free
  except for the contact;
* mesh: trilinear hexahedra (the seed's C3D8) on a tensor grid with the three zones of Fig. 8.3 — an
  *effective* zone of uniform fine elements under the whole scratch (its footprint plus a margin), an
  *intermediate* zone whose element sizes grow geometrically, and the *coarse* far field they grow into
  (:func:`zoned_axis`, :class:`SpecimenMesh`, :data:`MESH_LEVELS`);
* material: St-52 with linear hardening (:data:`ST52`, Fig. 8.4 approximated linearly as the seed does), or
  Model II (ERVE damage, Table 8.2) on top of it with ``damage=True`` (in small strain, and at finite strain on
  logarithmic strains, :class:`~abrakit.materials.LogStrainPlasticity`); elastic for the verifications;
* contact: the rigid analytic tip with penalty contact and Coulomb friction, μ = 0.1
  (:class:`~abrakit.scratch.contact_term.IndenterContact`), penalty c_N = factor · E / h_y with h_y the top
  element layer (the seed: "the minimum of the master and slave surface stiffness", scaling factor 1);
* path: "a displacement-control loading ... in two steps": indent to d, slide along +z at constant depth, and
  here optionally lift the tip again so the groove is read both with the tip in contact and after unloading.

:func:`~abrakit.scratch.run.run_scratch` runs a scene. Units: N, mm, MPa (µm values written as mm).

Example::

    scene = ScratchScene(depth=0.002, slide=0.03, mesh="demo", size=(0.1, 0.015, 0.1))
    specimen = build_specimen(scene)          # graded half block, its basis and boundary conditions
    specimen.mesh.t.shape[1]                  # number of hexahedra
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import NamedTuple

import numpy as np
import skfem

from abrakit.fem.boundary import Dirichlet
from abrakit.fem.kinematics import vector_basis
from abrakit.materials import LinearElastic, ModelIIDamage, VonMisesPlasticity
from abrakit.scratch.erosion import Erosion
from abrakit.scratch.indenters import ConicalIndenter, FineZone, ScratchPath, SphericalIndenter, check_path
from abrakit.validation import (
    check_instance,
    check_number_fields,
    check_option,
    check_positive,
    check_range,
    number_arguments,
)

SPECIMEN = (0.1, 0.015, 0.2)
"""The seed's block, mm: full width (x), thickness (y), length along the scratch (z) = 100 × 15 × 200 µm."""

ST52 = {"E": 210000.0, "nu": 0.33, "yield_stress": 355.0, "hardening": 1000.0}
"""St-52 (Table 8.1; Fig. 8.4 approximated linearly): E, ν, uniaxial yield stress σ_0 and linear hardening slope
H = dσ/dε_p, MPa.

Fig. 8.4 (Ribeiro et al. 2016) is missing from the text, so the numbers are ours: σ_0 = 355 MPa is St-52's
(S355's) nominal yield strength, and H = 1000 MPa is the straight line from it to ≈ 855 MPa true stress at 0.5
true strain, the range of a true stress–strain curve of this steel. In the model of Ch. 6 (yield function
|dev σ| − (r_p + K_H α_p)) this is r_p = σ_0/√1.5 = 289.9 MPa and K_H = H/1.5 = 666.7 MPa."""

TABLE_8_2 = {"E": 210000.0, "nu": 0.33, "r_d": 0.1, "n": 20, "dt": 1.0, "alpha": 0.05}
"""Model II parameters of the scratch, Table 8.2 (MPa, s; α printed in 1/s)."""

END_CLEARANCE = 0.01
"""Least distance (mm) between the fine zone and the fixed end faces z = 0, L: room for the intermediate zone."""


def st52_material(kind: str = "plastic", damage: bool = False, damage_energy: str = "full",
                  hardening: float | None = None):
    """The specimen's material: ``"plastic"`` (St-52 with linear hardening, :data:`ST52`) or ``"elastic"``;
    ``damage=True`` wraps it in Model II with Table 8.2 (``damage_energy`` "full" or "tension", Eq. 6.56);
    ``hardening``: the uniaxial slope H (MPa) instead of St-52's (0: perfect plasticity)."""
    check_option("kind", kind, ("plastic", "elastic"))
    E, nu = ST52["E"], ST52["nu"]
    H = ST52["hardening"] if hardening is None else check_positive("hardening", hardening, allow_zero=True)
    r_p = ST52["yield_stress"] / math.sqrt(1.5) if kind == "plastic" else None
    K_H = H / 1.5 if kind == "plastic" else 0.0
    if damage:
        p = TABLE_8_2
        return ModelIIDamage(p["E"], p["nu"], p["r_d"], n=p["n"], alpha=p["alpha"], dt=p["dt"], r_p=r_p, K_H=K_H,
                             integration="implicit", damage_energy=damage_energy)
    if kind == "elastic":
        return LinearElastic(E, nu)
    return VonMisesPlasticity(E, nu, r_p, K_H, integration="implicit")


# ---- mesh: the zones of Fig. 8.3 --------------------------------------------------------------------------------


def _growing(length: float, h: float, growth: float) -> np.ndarray:
    """Element sizes that start at about ``h`` (times ``growth``) and grow by ``growth`` to fill ``length``."""
    if length <= 1e-12:
        return np.zeros(0)
    if growth == 1.0:
        n = max(1, round(length / h))
        return np.full(n, length / n)
    sizes = [h * growth]
    while sum(sizes) < length:
        sizes.append(sizes[-1] * growth)
    sizes = np.array(sizes)
    if len(sizes) > 1 and sizes.sum() - length > 0.5 * sizes[-1]:
        sizes = sizes[:-1]                                   # drop the overshoot, stretch the rest
    return sizes * (length / sizes.sum())


@number_arguments
def zoned_axis(lo: float, hi: float, fine_lo: float, fine_hi: float, h: float, growth: float) -> np.ndarray:
    """Node coordinates on [lo, hi]: uniform elements of about ``h`` on [fine_lo, fine_hi] (the effective zone),
    sizes growing geometrically by ``growth`` towards both ends (intermediate and coarse zones of Fig. 8.3)."""
    check_range("fine_lo", fine_lo, lo, fine_hi)
    check_range("fine_hi", fine_hi, fine_lo, hi)
    check_positive("h", h)
    check_range("growth", growth, 1.0, None)
    n_fine = max(1, math.ceil((fine_hi - fine_lo) / h - 1e-9))
    fine = np.linspace(fine_lo, fine_hi, n_fine + 1)
    step = (fine_hi - fine_lo) / n_fine
    left = fine_lo - np.cumsum(_growing(fine_lo - lo, step, growth))
    right = fine_hi + np.cumsum(_growing(hi - fine_hi, step, growth))
    axis = np.concatenate([left[::-1], fine, right])
    axis[0], axis[-1] = lo, hi
    return np.unique(np.round(axis, 12))


@dataclass(frozen=True)
class SpecimenMesh:
    """Element sizes and zones of the graded specimen mesh (mm; the zones of Fig. 8.3).

    h: fine element size across the groove (x); h_z: along the scratch (default 2 h); h_y: thickness of the top
    element layers (default h/2); growth: size ratio of neighbouring elements outside the fine zone;
    width: half-width of the fine zone in footprint radii a of the tip at the scratch depth (shoulders included);
    fine_depth: depth of the uniform top layers in units of the scratch depth (at least two layers);
    margin: extra fine elements (in h_z) before and after the footprint's path; fine_z: an explicit
    (z_min, z_max) of the fine zone instead of the one that fits the path (a scratch leaving it is refused).
    """

    h: float = 0.0015
    h_z: float | None = None
    h_y: float | None = None
    growth: float = 1.35
    width: float = 2.0
    fine_depth: float = 1.5
    margin: float = 2.0
    fine_z: tuple[float, float] | None = None

    def __post_init__(self):
        check_number_fields(self)
        check_positive("h", self.h)
        for name in ("h_z", "h_y"):
            if getattr(self, name) is not None:
                check_positive(name, getattr(self, name))
        check_range("growth", self.growth, 1.0, 3.0)
        check_positive("width", self.width)
        check_positive("fine_depth", self.fine_depth)
        check_positive("margin", self.margin, allow_zero=True)

    @property
    def size_z(self) -> float:
        return 2.0 * self.h if self.h_z is None else self.h_z

    @property
    def size_y(self) -> float:
        return 0.5 * self.h if self.h_y is None else self.h_y


MESH_LEVELS = {
    "demo": SpecimenMesh(h=0.004, h_z=0.006, h_y=0.001, growth=1.6, width=1.6),
    "coarse": SpecimenMesh(h=0.003, h_z=0.005, h_y=0.001, growth=1.5),
    "default": SpecimenMesh(h=0.002, h_z=0.004, h_y=0.00075, growth=1.45),
    "fine": SpecimenMesh(h=0.0015, h_z=0.004, h_y=0.0006, growth=1.4),
    "finer": SpecimenMesh(h=0.001, h_z=0.003, h_y=0.0004, growth=1.35),
}
"""Mesh levels used by the demo, the tests, the benchmark and the book (``"default"`` for the seed's scene)."""


# ---- the scene --------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ScratchScene:
    """One single scratch (Sec. 8.2.1): tip, path, friction, penalty, material, mesh and specimen.

    indenter: the rigid tip (default the seed's sphere R = 50 µm); depth d and slide length (mm), the seed's
    default 2 µm and 100 µm; unload: lift the tip at the end (groove after unloading); z_start: apex position
    at the start of the slide (default: the slide centred on the block); clearance: height of the apex above
    the surface at the start (≥ 0: a tip starting inside the block is refused); mu: Coulomb coefficient (0.1);
    penalty: factor of c_N = factor · E / h_y (1, the seed's default scaling); material: "plastic" (St-52) or
    "elastic"; damage: Model II (Table 8.2) on top; damage_rate: how Model II's rate limit is fed, "work" (the
    default: Eq. 6.97, α times the work of the tip on the half model in the increment, α in 1/(N mm) as Eq. 6.98
    requires and Table 7.2 prints; Table 8.2's "1/s" is taken as a misprint) or "step" (the literal reading of
    Table 8.2, α in 1/s with Δt = 1 s: every increment may add α Δt = 0.05 to a sub-domain);
    mesh: a :class:`SpecimenMesh` or a level name of :data:`MESH_LEVELS`; size: the block (full width, thickness,
    length), mm; indent_steps, unload_steps: load increments of the two vertical phases; slide_step: apex
    advance per sliding increment (default h_z/4), mm; bbar: B-bar hexahedra against volumetric locking (F-bar
    with finite strain; Abaqus' C3D8 of the seed is selectively reduced); kinematics: "finite" (total
    Lagrangian, :class:`~abrakit.materials.LogStrainPlasticity`) or "small" (Eq. 4.26, the seed's). The defaults,
    finite strain with F-bar, are the scene's physics: :data:`SEED_FORMULATION` (small strain, full
    integration) loses about a third of the groove's volume to its kinematics and locks into a growing prow
    (book chapter "Where the groove goes"); end_faces: "fixed" (the seed: "the
    other surfaces of the specimen are fixed") or "free" (traction-free ends z = 0, L); hardening: the uniaxial
    hardening slope H of the plastic material, MPa (St-52's 1000 MPa; 0 for perfect plasticity); erosion: an
    :class:`~abrakit.scratch.erosion.Erosion` removes the elements whose ductile damage reaches 1 (finite strain,
    plastic material, no Model II), None (the default) removes nothing.
    """

    indenter: SphericalIndenter | ConicalIndenter = SphericalIndenter(0.05)
    depth: float = 0.002
    slide: float = 0.1
    unload: bool = True
    z_start: float | None = None
    clearance: float = 0.0
    mu: float = 0.1
    penalty: float = 1.0
    material: str = "plastic"
    damage: bool = False
    damage_rate: str = "work"
    damage_energy: str = "full"
    mesh: SpecimenMesh | str = "default"
    size: tuple[float, float, float] = SPECIMEN
    indent_steps: int = 5
    unload_steps: int = 5
    slide_step: float | None = None
    bbar: bool = True
    kinematics: str = "finite"
    end_faces: str = "fixed"
    hardening: float = ST52["hardening"]
    erosion: Erosion | None = None

    def __post_init__(self):
        check_number_fields(self)
        check_positive("depth", self.depth)
        check_positive("slide", self.slide, allow_zero=True)
        check_positive("mu", self.mu, allow_zero=True)
        check_positive("penalty", self.penalty)
        check_option("material", self.material, ("plastic", "elastic"))
        check_option("damage_rate", self.damage_rate, ("step", "work"))
        check_option("damage_energy", self.damage_energy, ("full", "tension"))
        check_option("kinematics", self.kinematics, ("small", "finite"))
        check_option("end_faces", self.end_faces, ("fixed", "free"))
        check_positive("hardening", self.hardening, allow_zero=True)
        check_instance("erosion", self.erosion, Erosion, optional=True)
        if self.erosion is not None and (self.kinematics != "finite" or self.material != "plastic" or self.damage):
            raise ValueError("erosion needs kinematics='finite', material='plastic' and damage=False (the ductile "
                             f"damage integrates the finite-strain plastic flow), got kinematics="
                             f"{self.kinematics!r}, material={self.material!r}, damage={self.damage!r}")
        if isinstance(self.mesh, str):
            check_option("mesh", self.mesh, tuple(MESH_LEVELS))
        check_positive("size", self.size)
        check_range("indent_steps", self.indent_steps, 1, None)
        check_range("unload_steps", self.unload_steps, 1, None)
        if self.slide_step is not None:
            check_positive("slide_step", self.slide_step)
        _ = self.path                               # a path the indenter cannot follow is refused here
        if self.depth >= self.size[1]:
            raise ValueError(f"depth {self.depth:g} mm must be smaller than the block's thickness {self.size[1]:g} mm")

    def __repr__(self) -> str:
        """The dataclass's repr without ``erosion=None``: the stored runs' fingerprints (``repr(scene)``) of the
        scenes that remove nothing stay what they were before erosion existed."""
        shown = [f for f in fields(self) if f.repr and not (f.name == "erosion" and self.erosion is None)]
        return f"ScratchScene({', '.join(f'{f.name}={getattr(self, f.name)!r}' for f in shown)})"

    @property
    def mesh_spec(self) -> SpecimenMesh:
        return MESH_LEVELS[self.mesh] if isinstance(self.mesh, str) else self.mesh

    @property
    def footprint(self) -> float:
        """Geometric footprint radius a of the tip at the scratch depth, mm."""
        return float(self.indenter.footprint_radius(self.depth))

    @property
    def path(self) -> ScratchPath:
        z0 = 0.5 * (self.size[2] - self.slide) if self.z_start is None else self.z_start
        return ScratchPath(depth=self.depth, slide=self.slide, z_start=z0, clearance=self.clearance,
                           unload=self.unload)

    @property
    def z_section(self) -> float:
        """Mid-length of the scratch, where the groove's cross-section is read, mm."""
        return self.path.z_start + 0.5 * self.slide

    def with_(self, **changes) -> ScratchScene:
        return replace(self, **changes)


class ScratchSpecimen(NamedTuple):
    """The meshed half block: mesh, displacement basis, fine zone, boundary conditions, top layer thickness."""

    mesh: skfem.MeshHex
    basis: skfem.CellBasis
    fine_zone: FineZone
    conditions: list
    top_layer: float


def build_specimen(scene: ScratchScene) -> ScratchSpecimen:
    """Graded half block of ``scene`` with its boundary conditions; refuses a scratch that leaves the fine zone.

    The fine zone covers the contact footprint along the whole path plus ``margin`` elements; it must keep
    :data:`END_CLEARANCE` from the fixed ends, else (or if an explicit ``fine_z`` is too short) the scratch is
    refused with the message of :func:`~abrakit.scratch.check_path`.
    """
    spec, path = scene.mesh_spec, scene.path
    width, thickness, length = scene.size
    half = 0.5 * width
    a = scene.footprint
    if spec.fine_z is not None:
        z_lo, z_hi = spec.fine_z
    else:
        z_lo = max(path.z_start - a - spec.margin * spec.size_z, min(END_CLEARANCE, 0.25 * length))
        z_hi = min(path.z_end + a + spec.margin * spec.size_z, length - min(END_CLEARANCE, 0.25 * length))
    x_fine = min(max(spec.width * a, 3 * spec.h), 0.9 * half)
    y_fine = min(max(spec.fine_depth * scene.depth, 2 * spec.size_y), 0.5 * thickness)
    zone = FineZone(z_lo, z_hi, x_max=x_fine, depth=y_fine)
    if not 0.0 <= z_lo < z_hi <= length:
        raise ValueError(f"the fine zone ({z_lo:g}, {z_hi:g}) mm must lie inside the block's length {length:g} mm")
    check_path(path, zone, scene.indenter)                               # refuses leaving the fine zone

    xs = zoned_axis(0.0, half, 0.0, x_fine, spec.h, spec.growth)
    ys = zoned_axis(-thickness, 0.0, -y_fine, 0.0, spec.size_y, spec.growth)
    zs = zoned_axis(0.0, length, z_lo, z_hi, spec.size_z, spec.growth)
    mesh = skfem.MeshHex.init_tensor(xs, ys, zs)
    tol = 1e-9 * length
    mesh = mesh.with_boundaries({
        "symmetry": lambda x: x[0] < tol,
        "side": lambda x: x[0] > half - tol,
        "bottom": lambda x: x[1] < -thickness + tol,
        "top": lambda x: x[1] > -tol,
        "front": lambda x: x[2] < tol,
        "back": lambda x: x[2] > length - tol,
    })
    basis = vector_basis(mesh)
    fixed = ("side", "bottom") + (("front", "back") if scene.end_faces == "fixed" else ())
    conditions = [Dirichlet.on(basis, "symmetry", "x")] + [Dirichlet.on(basis, face, "xyz") for face in fixed]
    return ScratchSpecimen(mesh, basis, zone, conditions, float(ys[-1] - ys[-2]))


SEED_FORMULATION = {"kinematics": "small", "bbar": False}
"""The seed's formulation of the scratch (Ch. 4.2: small strain, fully integrated hexahedra):
``ScratchScene(**SEED_FORMULATION)``."""

DEMO_SCENE = ScratchScene(slide=0.03, mesh="demo", size=(0.1, 0.015, 0.1))
"""The coarse live scene of ``abrakit demo`` and the book: the seed's tip and depth, 100 µm long block, 30 µm slide,
in the scene's physics (finite strain, F-bar); ``DEMO_SCENE.with_(**SEED_FORMULATION)`` is the seed's small-strain,
fully integrated formulation of the same scene, for comparison."""
