"""The single scratch test of Sec. 8.2.1 as a 3D finite element scene: specimen, mesh, path, run, groove.

The seed's set-up (Fig. 8.1–8.3, Table 8.1/8.2), in the axes of :mod:`abrakit.scratch.indenters`:

* specimen: a 200 × 100 × 15 µm block of St-52 (length 200 µm along the scratch z, width 100 µm across it along
  x, thickness 15 µm along y), top face y = 0; the half model x ≥ 0 with the symmetry plane x = 0 (u_x = 0
  there, "the displacement along the x-axis is zero on the symmetry plane"); "the other surfaces of the specimen
  are fixed": u = 0 on x = 50 µm, on the bottom y = −15 µm and on both ends z = 0, 200 µm. The top face is free
  except for the contact;
* mesh: trilinear hexahedra (the seed's C3D8) on a tensor grid with the three zones of Fig. 8.3 — an
  *effective* zone of uniform fine elements under the whole scratch (its footprint plus a margin), an
  *intermediate* zone whose element sizes grow geometrically, and the *coarse* far field they grow into;
* material: St-52 with linear hardening (:data:`ST52`, Fig. 8.4 approximated linearly as the seed does), or
  Model II (ERVE damage, Table 8.2) on top of it with ``damage=True`` (in small strain, and at finite strain on
  logarithmic strains, :class:`~abrakit.materials.LogStrainPlasticity`); elastic for the verifications;
  elements whose damage reaches Model II's cap are counted as removed (``removed`` in the volume audit and
  :attr:`ScratchResult.removed`);
* contact: the rigid analytic tip with penalty contact and Coulomb friction, μ = 0.1
  (:class:`~abrakit.scratch.contact_term.IndenterContact`), penalty c_N = factor · E / h_y with h_y the top
  element layer (the seed: "the minimum of the master and slave surface stiffness", scaling factor 1);
* path: "a displacement-control loading ... in two steps": indent to d, slide along +z at constant depth, and
  here optionally lift the tip again so the groove is read both with the tip in contact and after unloading.

:func:`run_scratch` writes the force curves (``forces.csv``) and fields (``fields/step.pvd``) as it goes and
extracts the groove cross-section at mid-length — with the tip in contact (the apex at mid-length, the section
through it) and after unloading — with :func:`~abrakit.scratch.groove.groove_metrics`: A_g, A_s, w, f_ab
(Eq. 8.5), D_p (Eq. 8.6), regime, and the removed (fully damaged) material.

Speed (profiled with pyinstrument): the half model, grading, nodal contact (no new matrix couplings), a sparse
LU in a geometric nested-dissection order (5–9× faster than SuperLU's own orderings on these tensor grids; a
stale factorisation as GMRES preconditioner did not pay for exact solves, since plastic points switching between
elastic and plastic change the tangent too much between iterations, but it does for inexact Newton corrections,
:data:`SCENE_FORCING`, below; an AMG-preconditioned GMRES with a reused hierarchy is the option for large
meshes), a backtracking line search that keeps Newton from cycling across the kinks of
contact and plasticity (fewer cut-backs), and Model II's damage sweep skips every point whose driving force is
below the threshold (Φ_d < 0). Every increment starts from the last converged state (``StepControl(extrapolate=
False)``): extrapolating the last increment pushes the nodes ahead of a moving tip into it or away from it, and
on the seed's default scene it cost 791 instead of 646 Newton iterations and two cutbacks for the same grooves (f_ab
equal to 10⁻⁷); on the finite-strain scene the extrapolating run stalled in cutbacks. A converged residual's
increment test takes a chord step with the kept factors (:class:`~abrakit.fem.NewtonOptions` ``chord_check``).

Increments (issue 39, measured on the mesh levels by ``benchmarks/bench_scratch_speed.py``): the 2 µm indentation
in 5 increments (20 before: about 150 of the default scene's 818 Newton iterations, for a monotonic indentation
that converges in 5 without a cutback), the slide starting at a quarter of its increment (:data:`SLIDE_RAMP`: the
full first increment turned the whole contact from stick to slip at once and was cut back twice on every mesh),
and Newton converged when the residual is below 10⁻⁴ of the largest nodal force (10⁻³ since the second round,
below) and the last correction below 10⁻² of the increment's displacement (Abaqus/Standard's default correction
criterion; 10⁻³ before). The grooves agree with the earlier control within 2 %
(``test_the_faster_increment_control_changes_no_groove_beyond_its_tolerances``). Tried and rejected: a slide
increment of h_z/2 (13 cutbacks on the coarse mesh, more iterations than h_z/4), chord steps while Newton contracts
tenfold (more factorisations, not fewer: the contact's active set changes between them).

Second round (issue 39): the residual test at 10⁻³ of the largest nodal force instead of 10⁻⁴, and PARDISO's
factors in single precision. Both had been tried once and rejected: the tolerance under the controls of the
time (it saved no iteration then), the mixed precision with a result (within ±7 % of the double factorisation)
that iparm settings PARDISO never reads give: MKL ignores every ``iparm`` entry unless ``iparm(1) = 1``, which
pypardiso leaves 0, and a first probe of this round that set ``iparm(28)`` alone measured the same. Measured on the
coarse scene's 100 µm slide, one run each: 88 s and 553 Newton iterations with both off, 76 s (519) with the
tolerance, 76 s (544) with the single factors, 68 s (525) with both; F_N, F_T, A_g, A_s within 0.2 % and f_ab
within 0.002 of each other, as close as two runs that differ only in round-off (the threads' summation order
changes a cutback). The single factors (87 against 121 ms per factorisation in a short run on the default level,
whose fine zone, as long as the slide, makes the mesh smaller than the 100 µm slide's) are refined in double
precision to the double answer (:class:`~abrakit.fem.DirectSolver`, ``precision="single"``; a tangent too
ill-conditioned for them falls back to double factors).

Where a Newton iteration's time goes on the default scene (24 510 DOF, cProfile): PARDISO's factorisation and solve
about 0.27 s, the F-bar element tangents 0.13 s, the finite-strain material tangent 0.05 s and their scatter into
the sparse matrix 0.03 s, one or two residual evaluations about 0.1 s each. Most of the block moves by less than
10⁻⁴ in F per iteration and stays elastic, so :data:`SCRATCH_NEWTON` keeps the element tangents of those elements
(:class:`~abrakit.fem.tangent_reuse.ElementTangentReuse`; about 36 % of the elements are recomputed per iteration,
most of them because a point yields): the tangent's part of an iteration falls from 0.21 to 0.10 s. Measured on
the default scene back to back: 0.66 → 0.56 s per iteration; run side by side on the two cores: 888 → 792 s, with
grooves equal to 2·10⁻⁶ in A_g and 2·10⁻⁴ in f_ab (``tests/test_scratch_scene.py`` pins the tiny scene within
1 %). The F-bar internal forces are compiled too (:func:`abrakit.fem._fbar_kernels.element_forces`, 2.3 against
26 ms). What is left is PARDISO (about half of an iteration in double precision, a third in single precision:
117 of the default scene's 332 s) times the five to six iterations an increment needs while the plastic zone settles
(the residual falls about tenfold per iteration, with and without friction): fewer iterations, not cheaper ones,
are the next lever. Counted per Newton iterate on sliding increments of the coarse mesh, it is the plastic set that
moves, not the contact's: at most four contact nodes change state, while the flowing Gauss points change by about
1300, 400, 80 and 10 in the second to fifth iterations. Tried and rejected there: the elastic-plastic tangent at
points on the yield surface at an increment's start (226 instead of 174 iterations and five cutbacks on a 20 µm
slide), the first correction of an increment with the last increment's factors (the indentation diverges: nodes
newly in contact have no stiffness in them). Also rejected (coarse mesh, 30 µm slide, baseline 230–238
iterations and 1–2 cutbacks in 57–67 s): a convected predictor, each slide increment starting from u shifted along
z by the tip's advance (a steady translation of the field), whose first residual is ten times smaller but whose
plastic set then toggles for 8–13 iterations per increment, with three cutbacks in the first 6 µm; and a line
search that keeps a full Newton step up to twice the residual (``growth_allowed = 2``): 384 iterations, 9
cutbacks, 108 s.

Third round (issue 39): inexact Newton corrections (:data:`SCENE_FORCING`). Within an increment the correction is
first sought by GMRES on the current tangent, preconditioned with the factors kept from the increment's last
factorisation, to 3 % of the residual (Eisenstat and Walker's forcing term η = 0.03) in at most eight iterations
(:func:`~abrakit.fem.linsolve.kept_factor_gmres`); only if that fails is the tangent factorised. An exact solve
with stale factors needs 25–30 GMRES iterations (above), a 3 % one three to eight: most corrections of an
increment's later iterations, where the plastic set moves by tens to hundreds of points, come from the kept
factors, and Newton, whose residual falls only about tenfold per iteration anyway, needs as many iterations. The
first iteration of an increment always factorises (nodes newly in contact). What it saves, measured on a quiet
machine, is in :data:`SCENE_FORCING`'s docstring. With η = 0.1 and five iterations the corrections are too coarse
(607 against 510 Newton iterations on the coarse mesh's 100 µm slide, one thread, the machine shared);
with η = 0.01 and eight, too many GMRES runs fail (a 30 µm slide: 248 against 213 iterations, no time saved).
``benchmarks/bench_scratch_speed.py`` compares every level with and without (``against_exact_corrections``).

Fourth round (issue 39): threads. On meshes above about 10 000 unknowns OpenBLAS splits numpy's vector products
(the GMRES and the residual norms) over its own threads, which spin after each call and hold the cores that the
OpenMP pools of the compiled kernels and PARDISO wait for: on the coarse mesh's 200 µm slide a PARDISO call took
21 ms in the run against 5–7 ms alone, and two threads were slower than one. :mod:`abrakit.threads` now gives
OpenBLAS one thread: the default scene 276 → 181 s, the coarse 200 µm slide 255 → 151 s.
Units: N, mm, MPa (µm values written as mm).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import skfem

from abrakit.fem import Dirichlet, LinearSolveError, NewtonOptions, Solver, StepControl, StepFailed, vector_basis
from abrakit.fem.linsolve import DirectSolver, pardiso_available, rigid_body_modes
from abrakit.fem.solver import NewtonFailure
from abrakit.io import write_json
from abrakit.materials import LinearElastic, LogStrainPlasticity, ModelIIDamage, VonMisesPlasticity
from abrakit.scratch.budget import VolumeBudget
from abrakit.scratch.checkpoint import CHECKPOINT, load_scratch_checkpoint, save_scratch_checkpoint
from abrakit.scratch.contact import penalty_from_stiffness
from abrakit.scratch.contact_term import IndenterContact
from abrakit.scratch.groove import (
    GrooveMetrics,
    Profile,
    RemovedMaterial,
    at_cap,
    groove_metrics,
    profile_from_surface_nodes,
    removed_material,
)
from abrakit.scratch.hertz import hertz_sphere
from abrakit.scratch.indenters import ConicalIndenter, FineZone, ScratchPath, SphericalIndenter, check_path
from abrakit.scratch.record import PHASES, ScratchRecorder, slide_mean
from abrakit.validation import check_number_fields, check_option, check_positive, check_range, number_arguments

__all__ = ["GrooveBalance", "HertzCheck", "LineSearchSolver", "MESH_LEVELS", "SEED_FORMULATION", "SPECIMEN",
           "DEMO_SCENE", "SCRATCH_NEWTON", "ST52", "TABLE_8_2", "ScratchResult", "ScratchScene", "Specimen",
           "SpecimenMesh", "build_specimen", "demo", "groove_along", "groove_balance", "groove_section",
           "hertz_indentation", "run_scratch", "scene_linear_solver", "st52_material"]

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

SCRATCH_NEWTON = NewtonOptions(residual_tol=1e-3, increment_tol=1e-2, max_iterations=20, divergence_check_after=10,
                               tangent_reuse=1e-4)
"""Newton's options of :func:`run_scratch`: converged when the residual is below 10⁻³ of the largest nodal force
(10⁻⁴ before issue 39's second round: the coarse scene's 100 µm slide then took 553 iterations against 519, and the
forces, groove areas and f_ab moved by no more than two runs differing in round-off do, 0.2 % and 0.002; see the
module docstring) and the last correction below 10⁻² of the increment's displacement (Abaqus/Standard's correction
criterion); the
element tangents of elements whose F moved by less than 10⁻⁴ and that do not yield are kept
(:class:`~abrakit.fem.tangent_reuse.ElementTangentReuse`: the residual stays exact, only the Newton matrix differs,
by about 10⁻⁴ relative in those elements)."""

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
    hardening slope H of the plastic material, MPa (St-52's 1000 MPa; 0 for perfect plasticity).
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


class Specimen(NamedTuple):
    """The meshed half block: mesh, displacement basis, fine zone, boundary conditions, top layer thickness."""

    mesh: skfem.MeshHex
    basis: skfem.CellBasis
    fine_zone: FineZone
    conditions: list
    top_layer: float


def build_specimen(scene: ScratchScene) -> Specimen:
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
    return Specimen(mesh, basis, zone, conditions, float(ys[-1] - ys[-2]))


# ---- linear solver with a reused preconditioner ----------------------------------------------------------------


def nested_dissection(points: np.ndarray, leaf: int = 192) -> np.ndarray:
    """Fill-reducing order of the DOFs at ``points`` (dim, n) of a tensor-product mesh: geometric nested dissection.

    The DOF set is split recursively at the middle grid plane of its longest index extent; both halves are
    ordered first (recursively), the plane (the separator) last. On the tensor grids of the scratch this gives
    far less fill than SuperLU's minimum-degree orderings (about 5× faster factorisations on the scene's tangent).
    """
    index = np.stack([np.unique(np.round(c, 12), return_inverse=True)[1] for c in points], axis=1)
    order: list[np.ndarray] = []

    def dissect(items, depth=0):
        if items.size <= leaf or depth > 60:
            order.append(items)
            return
        g = index[items]
        lo, extent = g.min(axis=0), np.ptp(g, axis=0)
        axis = int(np.argmax(extent))
        if extent[axis] < 2:
            order.append(items)
            return
        mid = lo[axis] + extent[axis] // 2
        dissect(items[g[:, axis] < mid], depth + 1)
        dissect(items[g[:, axis] > mid], depth + 1)
        order.append(items[g[:, axis] == mid])

    dissect(np.arange(index.shape[0]))
    return np.concatenate(order)


class ReusedPreconditioner:
    """GMRES on the current tangent K, preconditioned by a smoothed-aggregation AMG hierarchy (pyamg, on the
    symmetric part of an *earlier* K, the rigid-body modes as near-null space) kept across Newton iterations and
    load steps: the tangent of a scratch changes only near the tip, so the hierarchy stays a good preconditioner
    for the largest scenes. It is rebuilt when GMRES needs more than ``rebuild_after`` iterations, or fails.
    GMRES always sees K itself (the contact tangent is non-symmetric in slip).

    Measured on the scratch ("default" mesh, 24 000 DOFs): a stale *LU* as preconditioner needs 25–30 GMRES
    iterations to this ``rtol``, as costly as a fresh factorisation, because plastic points switching between
    elastic and plastic change the tangent too much (to the 3 % of an inexact Newton correction it needs three to
    eight: :data:`SCENE_FORCING`); reuse pays for the AMG hierarchy only, and the direct solver with a kept
    analysis (:class:`~abrakit.fem.DirectSolver`) is faster where PARDISO is installed. On the "finer" level's
    300 µm block (131 805 free DOFs) PARDISO's single factors take 4.5 s and a solve with them 71 ms, while GMRES
    with a fresh hierarchy did not reach this ``rtol`` on the first tangent at all and the run's first increment
    took 251 s for 14 Newton iterations: ``"auto"`` takes it only without PARDISO, above 120 000 free DOFs, where
    SuperLU's factors grow too large.
    """

    name = "gmres+reused-amg"

    def __init__(self, *, near_null_space=None, rtol: float = 1e-9, rebuild_after: int = 12, maxiter: int = 300):
        self.near_null_space = near_null_space
        self.rtol = rtol
        self.rebuild_after = rebuild_after
        self.maxiter = maxiter
        self._M = None
        self.builds = 0
        self.build_time = 0.0
        self.iterations: list[int] = []

    def _build(self, K):
        import pyamg

        t0 = time.perf_counter()
        sym = sp.csr_matrix(0.5 * (K + K.T))
        ml = pyamg.smoothed_aggregation_solver(sym, B=self.near_null_space, symmetry="symmetric", max_coarse=500)
        self._M = ml.aspreconditioner(cycle="V")
        self.builds += 1
        self.build_time += time.perf_counter() - t0

    def solve(self, K: sp.csr_matrix, rhs: np.ndarray, new_step: bool = True) -> np.ndarray:
        for attempt in range(2):
            fresh = self._M is None or attempt == 1
            if fresh:
                self._build(K)
            count = [0]

            def callback(_, count=count):
                count[0] += 1

            x, info = spla.gmres(K, rhs, rtol=self.rtol, atol=0.0, restart=50, maxiter=self.maxiter // 50 + 1,
                                 M=self._M, callback=callback, callback_type="pr_norm")
            self.iterations.append(count[0])
            if info == 0 and np.all(np.isfinite(x)):
                if count[0] > self.rebuild_after:
                    self._M = None                                     # rebuild before the next solve
                return x
            if fresh and attempt == 1:
                break
        raise LinearSolveError("GMRES with a fresh AMG preconditioner did not converge")


AMG_ABOVE = 120_000
"""Free DOFs above which a scene without PARDISO takes the AMG-preconditioned GMRES instead of SuperLU
(:func:`scene_linear_solver`); with PARDISO the direct solver serves every size."""

SCENE_FORCING = {"forcing": 0.03, "krylov_iterations": 8}
"""Inexact Newton corrections of a scene's direct solvers (:class:`~abrakit.fem.DirectSolver` ``forcing``): within
an increment, GMRES preconditioned with the factors kept from the increment's last factorisation, to 3 % of the
residual in at most eight iterations, before a new factorisation. They pay where a factorisation is dear against a
GMRES iteration. ``benchmarks/bench_kept_factors.py`` measures it on the coarse mesh's 100 µm slide, one thread
per process (two side by side) and two threads alone, in one sitting: 91 → 75 s and 54 → 44 s, as many Newton
iterations (508/510, 515/529), 191 and 194 factorisations instead of 489 and 530; F_N, A_g within 3·10⁻⁴ and f_ab
within 0.001 of the exact corrections (in a later sitting, OpenBLAS on one thread: 86 → 69 s and 59 → 52 s). On
the default scene and the coarse mesh's 200 µm slide, two threads, separate sittings of the same hour, the exact
and inexact runs took 276.1 and 276.3 s, 258.8 and 255.0 s: the gain shrank where a GMRES iteration's solve grows
with the factors, and on two threads the solves waited for OpenBLAS's spinning threads; with OpenBLAS on one
thread (:mod:`abrakit.threads`) the inexact runs take 181 and 151 s. The machine's hour changes such timings by
±15 %; ``benchmarks/bench_scratch_speed.py`` compares every level with the exact corrections stored before."""


def scene_linear_solver(solver: Solver, kind: str = "auto", inexact: bool = True):
    """The linear solver of a 3D contact scene for ``solver``'s free DOFs, all keeping their analysis across
    Newton iterations: ``"pardiso"`` (:class:`~abrakit.fem.DirectSolver` on MKL PARDISO, METIS order, factors in
    single precision refined to the double answer, see the module docstring), ``"lu"``
    (the same on SuperLU in the :func:`nested_dissection` order), ``"amg"`` (GMRES with a reused AMG hierarchy,
    the rigid-body modes as near-null space) or ``"auto"`` (PARDISO if installed, at every size; else LU, or AMG
    above :data:`AMG_ABOVE` free DOFs: :class:`ReusedPreconditioner` says why). ``inexact``: the direct solvers'
    corrections within an increment by GMRES with kept factors (:data:`SCENE_FORCING`; False: every correction
    exact)."""
    check_option("linear_solver", kind, ("auto", "pardiso", "lu", "amg"))
    if not isinstance(inexact, bool):
        raise TypeError(f"inexact must be True or False, got {inexact!r}")
    forcing = SCENE_FORCING if inexact else {}
    free = solver.constraints.free
    if kind == "auto":
        kind = "pardiso" if pardiso_available() else ("amg" if free.size > AMG_ABOVE else "lu")
    points = solver.kin.basis.doflocs[:, free]
    if kind == "pardiso":
        return DirectSolver("pardiso", precision="single", **forcing)
    if kind == "lu":
        return DirectSolver("superlu", order=nested_dissection(points), **forcing)
    component = np.zeros(solver.kin.ndof, dtype=int)
    component[solver.kin.element_dofs] = np.arange(solver.kin.nbf) % 3
    return ReusedPreconditioner(near_null_space=rigid_body_modes(points, component[free]))


# ---- Newton with a backtracking line search ---------------------------------------------------------------------


class LineSearchSolver(Solver):
    """:class:`abrakit.fem.Solver` whose Newton corrections are damped by a backtracking line search.

    Penalty contact (open/closed, stick/slip) and plasticity (elastic/plastic) make the residual only piecewise
    smooth; a full Newton step can jump across a kink and the iteration then cycles between two sets of active
    points. The correction du is therefore accepted only if it lowers the Euclidean norm of the free residual,
    ||R(u + s du)|| ≤ (1 − 10⁻⁴ s) ||R(u)||; otherwise s is halved (at most ``max_backtracks`` times) and the
    step with the smallest residual is taken. The trial evaluation of an accepted step is cached and reused as
    the next iteration's evaluation, so an undamped Newton iteration costs nothing extra.

    Composition only: the solver's own Newton loop and convergence test are unchanged; this class overrides its
    ``evaluate`` (to cache) and ``_correction`` (to scale du). The trials start from the iterate ``u`` that
    Newton passes to ``_correction`` (before this was made explicit, an iteration whose evaluation came from the
    cache searched from the last *uncached* point: wrong trial points, about twice the evaluations and more
    cut-backs; ``test_line_search_trials_start_from_the_current_iterate``).
    """

    max_backtracks = 4
    growth_allowed = 1.0

    def evaluate(self, u, state_old, ctx):
        cache = getattr(self, "_cache", None)
        key = (ctx.load_factor, ctx.delta, id(state_old))
        self._last = (state_old, ctx, key)
        if cache is not None and cache[0] == key and np.array_equal(cache[1], u):
            evaluation = cache[2]
        else:
            evaluation = super().evaluate(u, state_old, ctx)
        self._last_residual = (u, evaluation[1])
        return evaluation

    def newton(self, u_trial, state_old, ctx, lift=None):
        """:meth:`abrakit.fem.Solver.newton`; a failure's reason names where it happened (:meth:`diagnose`)."""
        self._last_residual = None
        try:
            return super().newton(u_trial, state_old, ctx, lift=lift)
        except NewtonFailure as failure:
            failure.reason = f"{failure.reason} [{self.diagnose(failure.reason)}]"
            failure.args = (failure.reason,)
            raise

    def diagnose(self, reason: str = "") -> str:
        """The cause of a failed Newton step in a scratch, from the last residual: ``element inversion`` (det F ≤ 0
        under the tip), ``contact`` (the largest free residual sits at a surface node of the contact term: its
        status and gap are named, the signature of a node chattering between states), or ``bulk`` (inside the
        block, where plasticity switches; position named). Positions in µm."""
        if "inverted" in reason:
            return ("element inversion: det F <= 0 under the tip; the slide step is too large for the mesh, or "
                    "the top layer too thin for the depth")
        if getattr(self, "_last_residual", None) is None:
            return "no residual was evaluated"
        u, residual = self._last_residual
        free = self.constraints.free
        dof = int(free[np.argmax(np.abs(residual[free]))])
        where = np.round(self.kin.basis.doflocs[:, dof] * 1e3, 2)
        for term in self.extra_terms:
            nodes = np.nonzero(np.any(getattr(term, "dofs", np.empty((0, 3))) == dof, axis=1))[0]
            if nodes.size:
                pending = getattr(term, "_pending", None)
                status = ("open", "stick", "slip")[int(pending["state"]["status"][nodes[0]])] if pending else "?"
                gap = term.indenter.gap((term.reference[nodes[0]] + u[term.dofs[nodes[0]]])[None],
                                        np.asarray(term.position(self._last[1].load_factor), dtype=float)).gap[0]
                return (f"contact: the largest residual, {abs(residual[dof]):.2e} N, sits at surface node "
                        f"{int(term.nodes[nodes[0]])} at (x, z) = ({where[0]:g}, {where[2]:g}) um, {status}, gap "
                        f"{gap * 1e6:.3g} nm: a contact node switching between states (chatter)")
        return (f"bulk: the largest residual, {abs(residual[dof]):.2e} N, sits inside the block at "
                f"(x, y, z) = ({where[0]:g}, {where[1]:g}, {where[2]:g}) um")

    def _free_norm(self, residual):
        return float(np.linalg.norm(residual[self.constraints.free]))

    def _correction(self, response, extra_K, residual, new_step: bool, lift=None, u=None) -> np.ndarray:
        du = super()._correction(response, extra_K, residual, new_step, lift=lift, u=u)
        if u is None:
            raise ValueError("the line search needs the current iterate u")
        state_old, ctx, key = self._last          # of the evaluation at u (the iterate Newton passes)
        free = self.constraints.free
        norm0 = self._free_norm(residual)
        best = None
        s = 1.0
        for _ in range(self.max_backtracks + 1):
            trial = u.copy()
            trial[free] += s * du
            try:
                with np.errstate(all="ignore"):
                    evaluation = Solver.evaluate(self, trial, state_old, replace(ctx, u=trial))
                norm = self._free_norm(evaluation[1])
            except (ArithmeticError, ValueError, np.linalg.LinAlgError):
                norm, evaluation = np.inf, None
            if not np.isfinite(norm):
                norm = np.inf
            if best is None or norm < best[0]:
                best = (norm, s, trial, evaluation)
            if norm <= (self.growth_allowed if s == 1.0 else 1.0 - 1e-4 * s) * norm0:
                break
            s *= 0.5
        norm, s, trial, evaluation = best
        if evaluation is not None:
            self._cache = (key, trial, evaluation)
        return s * du


# ---- running a scene --------------------------------------------------------------------------------------------


@dataclass
class ScratchResult:
    """What a scratch run gives (forces for the whole grain; lengths mm, areas mm², forces N, times s).

    curves: the force curves, one entry per converged increment (also in ``forces.csv``): ``tau`` (pseudo-time
    of :class:`~abrakit.scratch.ScratchPath`), ``tip_y``, ``tip_z``, ``slide`` (apex travel along z),
    ``normal_force``, ``tangential_force``, ``contact_area``, ``max_penetration``, ``iterations``;
    groove_loaded / groove_unloaded: :class:`~abrakit.scratch.groove.GrooveMetrics` of the mid-length section
    with the apex there / after unloading (None when not computed; ``notes`` say why), with their profiles;
    removed: :class:`~abrakit.scratch.groove.RemovedMaterial` near mid-length (damage runs), None otherwise;
    mean_normal_force / mean_tangential_force: means over the slide distance of its steady part (after one
    footprint diameter of travel; :func:`~abrakit.scratch.record.slide_mean`, robust to cutbacks); u, state: the
    final displacement and material state; solver_counts: the linear solver's counters (:data:`SOLVER_COUNTS`)
    and the seconds of its analyses, factorisations and solves.
    """

    scene: ScratchScene
    curves: dict
    groove_loaded: GrooveMetrics | None
    groove_unloaded: GrooveMetrics | None
    profile_loaded: Profile | None
    profile_unloaded: Profile | None
    removed: RemovedMaterial | None
    mean_normal_force: float
    mean_tangential_force: float
    n_elements: int
    n_dofs: int
    wall_time: float                  # [s] over every call that computed it (a resumed run adds the earlier ones)
    increments: int
    newton_iterations: int
    cutbacks: int
    linear_solver: str
    u: np.ndarray
    state: dict
    specimen: Specimen
    contact: IndenterContact
    budget: VolumeBudget | None = None
    output: Path | None = None
    notes: list = field(default_factory=list)
    solver_counts: dict = field(default_factory=dict)

    def summary(self) -> dict:
        """JSON-ready numbers of the run (µm and µm² for lengths and areas, N for forces)."""
        def metrics(g):
            if g is None:
                return None
            return {"A_g_um2": g.groove_area * 1e6, "A_s_um2": g.shoulder_area * 1e6, "w_um": g.width * 1e3,
                    "depth_um": g.depth * 1e3, "f_ab": g.degree_of_wear, "D_p": g.degree_of_penetration,
                    "regime": g.regime, "shoulder_height_um": g.shoulder_height * 1e3}

        s = self.scene
        out = {
            "indenter": type(s.indenter).__name__, "R_um": s.indenter.radius * 1e3, "d_um": s.depth * 1e3,
            "slide_um": s.slide * 1e3, "mu": s.mu, "penalty": s.penalty, "material": s.material,
            "damage": s.damage, "elements": self.n_elements, "dofs": self.n_dofs, "increments": self.increments,
            "newton_iterations": self.newton_iterations, "cutbacks": self.cutbacks, "wall_time_s": self.wall_time,
            "linear_solver": self.linear_solver, "solver_counts": dict(self.solver_counts),
            "mean_normal_force_N": self.mean_normal_force,
            "mean_tangential_force_N": self.mean_tangential_force,
            "max_normal_force_N": float(np.max(self.curves["normal_force"], initial=0.0)),
            "groove_loaded": metrics(self.groove_loaded), "groove_unloaded": metrics(self.groove_unloaded),
            "notes": list(self.notes),
        }
        if self.budget is not None:
            out["volume_budget_um3"] = self.budget.as_dict(scale=1e9)
        if self.removed is not None:
            out["removed_volume_um3"] = self.removed.volume * 1e9
            out["removed_area_um2"] = None if self.removed.area is None else self.removed.area * 1e6
            out["removed_elements"] = self.removed.count
        return out


SLIDE_RAMP = 0.25
"""The slide starts with this fraction of its increment and grows to it (x1.5 after two easy increments): the
tip's first move turns the whole contact from stick to slip, and a full first increment failed there on every mesh
(two cutbacks, 20–30 Newton iterations lost)."""


def _segments(scene: ScratchScene, spec: SpecimenMesh):
    """Pseudo-time segments (start, end, increment, first increment): indentation, the slide's two halves,
    unloading."""
    slide_step = scene.slide_step if scene.slide_step is not None else 0.25 * spec.size_z
    dtau = 1.0 / scene.indent_steps
    segments = [(0.0, 1.0, dtau, dtau)]
    if scene.slide > 0.0:
        dtau = min(0.5, slide_step / scene.slide)
        segments += [(1.0, 1.5, dtau, SLIDE_RAMP * dtau), (1.5, 2.0, dtau, dtau)]
    if scene.unload:
        if scene.slide == 0.0:
            segments.append((1.0, 2.0, 1.0, 1.0))             # nothing moves: one idle increment
        dtau = 1.0 / scene.unload_steps
        segments.append((2.0, 3.0, dtau, dtau))
    return segments


def _noted(section, label, notes):
    metrics, profile, why = section
    if why:
        notes.append(f"{label}: {why}")
    return metrics, profile


def groove_section(specimen: Specimen, u: np.ndarray, scene: ScratchScene, z: float | None = None):
    """(:class:`~abrakit.scratch.groove.GrooveMetrics` or None, half :class:`~abrakit.scratch.groove.Profile`,
    reason) of the spatial cross-section at ``z`` (default: mid-length of the scratch); the metrics are None
    (and ``reason`` says why) where the profile has no groove."""
    disp = u[np.asarray(specimen.basis.nodal_dofs)].T
    profile = profile_from_surface_nodes(specimen.mesh.p.T, disp, scene.z_section if z is None else z)
    try:
        return groove_metrics(profile.x, profile.y, half=True, depth=scene.depth, tol=2e-3 * scene.depth), \
            profile, None
    except ValueError as exc:
        return None, profile, str(exc)


class GrooveAlong(NamedTuple):
    """Groove sections along the wake (µm², whole grain): positions z (mm), A_g, A_s, f_ab (NaN where the
    section has no groove)."""

    z: np.ndarray
    groove_area: np.ndarray
    shoulder_area: np.ndarray
    degree_of_wear: np.ndarray


def groove_along(specimen: Specimen, u: np.ndarray, scene: ScratchScene, z: np.ndarray) -> GrooveAlong:
    """:func:`groove_section` at every position of ``z``: where along the scratch the section reaches a plateau."""
    rows = []
    for zi in np.asarray(z, dtype=float):
        g = groove_section(specimen, u, scene, zi)[0]
        rows.append((np.nan, np.nan, np.nan) if g is None
                    else (g.groove_area * 1e6, g.shoulder_area * 1e6, g.degree_of_wear))
    values = np.array(rows).reshape(-1, 3).T
    return GrooveAlong(np.asarray(z, dtype=float), *values)


def element_damage(state) -> np.ndarray:
    """One damage value per element: the largest sub-domain damage of Model II's ERVE, averaged over the
    element's quadrature points, ``(nel,)``."""
    return state["d"].max(axis=-1).mean(axis=1)


def removed_elements(material):
    """``f(state) -> (nel,) bool``: the elements whose :func:`element_damage` reached the material's cap
    (:func:`~abrakit.scratch.groove.at_cap`, the criterion of :func:`~abrakit.scratch.groove.removed_material`),
    for the volume audit."""
    return lambda state: at_cap(element_damage(state), material.d_max)


def surface_nodes_of(mesh, nodes):
    """``f(removed) -> (len(nodes),) bool``: the surface ``nodes`` all of whose elements the element mask
    ``removed`` (nel,) flags (a node with one intact element keeps touching the tip)."""
    import scipy.sparse as sp

    incidence = sp.csr_matrix((np.ones(mesh.t.size), (mesh.t.ravel(), np.tile(np.arange(mesh.t.shape[1]),
                                                                                 mesh.t.shape[0]))),
                              shape=(mesh.p.shape[1], mesh.t.shape[1]))[nodes]
    count = np.asarray(incidence.sum(axis=1)).ravel()
    return lambda removed: incidence @ removed.astype(float) >= count


SOLVER_COUNTS = ("analyses", "factorisations", "solves", "krylov_solves", "krylov_fallbacks", "gmres_iterations",
                 "precision_fallbacks")
"""The linear solver's counters a :class:`ScratchResult` keeps (``solver_counts``, with the seconds of its
analyses, factorisations and solves)."""


def run_scratch(scene: ScratchScene = ScratchScene(), *, output=None, progress: bool = False, vtu_every: int = 10,
                linear_solver: str = "auto", newton: NewtonOptions | None = None, checkpoint_every: int = 10,
                resume: bool = False, inexact: bool = True) -> ScratchResult:
    """Run the single scratch ``scene``; write ``forces.csv``, ``fields/step.pvd`` and ``summary.json`` to
    ``output`` (if given) as it goes; return a :class:`ScratchResult`.

    ``linear_solver``: "pardiso", "lu", "amg" or "auto", and ``inexact`` (corrections within an increment by GMRES
    with kept factors, :data:`SCENE_FORCING`), see :func:`scene_linear_solver`.
    ``vtu_every``: field output every that many increments (and at the end of every phase); 0 disables it.
    ``checkpoint_every``: with ``output``, save ``last_converged.npz`` every that many increments and at the end of
    every phase (0: at phase ends only; :mod:`abrakit.scratch.checkpoint`). ``resume=True`` continues from that
    checkpoint, if there is one: ``forces.csv`` and the VTU series go back to it and the increments after it are
    recomputed with the phase's nominal increment (the same increments as an uninterrupted run unless a cutback was
    being recovered from when it stopped).
    """
    check_range("checkpoint_every", checkpoint_every, 0, None)
    t_start, earlier = time.perf_counter(), 0.0
    spec = scene.mesh_spec
    path = scene.path
    specimen = build_specimen(scene)
    mesh, basis = specimen.mesh, specimen.basis
    material = st52_material(scene.material, scene.damage, scene.damage_energy, scene.hardening)
    finite = scene.kinematics == "finite"
    if finite:
        material = LogStrainPlasticity(material)
    c_N = penalty_from_stiffness(ST52["E"], specimen.top_layer, scene.penalty)
    contact = IndenterContact(basis, scene.indenter, path.position, c_N=c_N, mu=scene.mu)

    # the indenter must start outside the block (ScratchPath refuses clearance < 0; this also covers a tip
    # whose surface reaches below y = 0 away from its apex)
    if np.any(scene.indenter.gap(contact.reference, path.position(0.0)).gap < -1e-12):
        raise ValueError("the indenter starts inside the block: some surface nodes lie inside the tip at tau = 0")

    converged_force = [np.zeros(3)]          # the tip force of the last converged increment (explicit rate limit)
    removed_nodes = surface_nodes_of(mesh, contact.nodes) if scene.damage else None

    def loading(ctx):
        if not scene.damage:
            return {}
        if scene.damage_rate == "step":
            return {"external_work": 1.0}     # alpha [1/s] * dt [1 s]: the increment alpha*dt of Table 8.2
        tip_move = np.asarray(path.position(ctx.load_factor)) - path.position(ctx.load_factor - ctx.delta)
        work = -converged_force[0] @ tip_move / contact.symmetry_factor        # on the half model, N mm
        return {"external_work": max(work, 0.0)}

    newton = newton or SCRATCH_NEWTON
    solver = LineSearchSolver(basis, material, specimen.conditions, loading=loading, extra_terms=[contact],
                              newton=newton, linear_solver="direct", bbar=scene.bbar,
                              finite_strain=finite)
    solver.linear_solver = scene_linear_solver(solver, linear_solver, inexact)

    out = Path(output) if output is not None else None
    extra = (lambda st: {"effective_damage": material.effective_damage(st).mean(axis=1)}) if scene.damage else None
    recorder = ScratchRecorder(path, contact, solver.kin, output=out, vtu_every=vtu_every, extra_fields=extra,
                               removed=removed_elements(material) if scene.damage else None)
    u = np.zeros(basis.N)
    state = material.initial_state((solver.kin.nel, solver.kin.nqp))
    iterations = cutbacks = 0
    tau_done, u_loaded = 0.0, None
    checkpoint = out / CHECKPOINT if out is not None else None
    saved = load_scratch_checkpoint(checkpoint, scene, basis.N) if resume and checkpoint is not None else None
    grooves, notes = {}, []

    def save(u_, state_, tau, iterations_, continuation=None):
        save_scratch_checkpoint(checkpoint, scene, u=u_, state=state_, tau=tau, recorder=recorder, contact=contact,
                                iterations=iterations_, cutbacks=cutbacks, u_loaded=u_loaded,
                                continuation=continuation)

    def on_step(res):            # ``iterations``/``cutbacks``: the counts before the phase that is running
        recorder(res)
        converged_force[0] = np.array(contact.forces.force, dtype=float)
        if removed_nodes is not None:                   # removed material (the audit's mask) leaves the contact
            contact.remove(removed_nodes(recorder.removed_mask))
        if checkpoint is not None and checkpoint_every and len(recorder.rows) % checkpoint_every == 0:
            save(res.u, res.state, float(res.load_factors[-1]), iterations + int(res.iterations.sum()),
                 res.continuation)

    continuation = None
    try:
        if saved is None:
            contact.reset(0.0, u)
        else:
            u, state, tau_done, u_loaded = saved["u"], saved["state"], saved["load_factor"], saved["u_loaded"]
            iterations, cutbacks = saved["meta"]["iterations"], saved["meta"]["cutbacks"]
            continuation = saved["continuation"]
            recorder.restart(saved["meta"]["record"])
            earlier = recorder.rows[-1]["wall_time"] if recorder.rows else 0.0     # the calls before this one
            contact.restore(saved["arrays"], saved["meta"]["contact"])
            if contact.forces is not None:
                converged_force[0] = np.array(contact.forces.force, dtype=float)
        for start, end, dtau, first in _segments(scene, spec):
            if end <= tau_done:                                              # done before the checkpoint
                continue
            solver.control = StepControl(initial=first, maximum=dtau, minimum=dtau * 1e-3, easy_iterations=7,
                                         extrapolate=False)                   # see the module docstring
            try:
                result = solver.run(start=start, end=end, u0=u, state0=state, progress=progress, on_step=on_step,
                                    continuation=continuation if start < tau_done else None)
            except StepFailed as failure:       # keep the last converged increment, then say where the run stopped
                res = failure.result
                if checkpoint is not None:
                    save(res.u, res.state, float(res.load_factors[-1]), iterations + int(res.iterations.sum()),
                         res.continuation)
                where = f"; its last converged increment is saved in {checkpoint} (resume=True goes on from it)" \
                    if checkpoint is not None else ""
                slid = min(max(failure.load_factor - 1.0, 0.0), 1.0) * scene.slide * 1e3
                raise StepFailed(f"scratch stopped at tau = {failure.load_factor:.6g} "
                                 f"({path.phase(failure.load_factor)}, slide {slid:.4g} um of {scene.slide * 1e3:g}):"
                                 f" {failure.reason}{where}",
                                 load_factor=failure.load_factor, u=failure.u, state=failure.state,
                                 reason=failure.reason, result=res, checkpoint=checkpoint) from failure
            u, state = result.u, result.state
            iterations += int(result.iterations.sum())
            cutbacks += result.cutbacks
            recorder.write_fields(end, u, result.response.stress, state)      # the end of every phase
            if scene.slide > 0.0 and end == 1.5:
                u_loaded = u.copy()
            if checkpoint is not None:
                save(u, state, end, iterations)
        if u_loaded is not None:
            grooves["loaded"] = _noted(groove_section(specimen, u_loaded, scene), "tip in contact", notes)
        if scene.slide > 0.0:
            label = "after unloading" if scene.unload else "end of slide"
            grooves["unloaded"] = _noted(groove_section(specimen, u, scene), label, notes)
    finally:
        recorder.close()

    curves = recorder.curves()
    removed = None
    if scene.damage:
        kin = solver.kin
        centres = mesh.p[:, mesh.t].mean(axis=1).T
        window = (scene.z_section - 0.25 * scene.slide, scene.z_section + 0.25 * scene.slide) if scene.slide else None
        removed = removed_material(kin.dx.sum(axis=1), element_damage(state), material.d_max,
                                   half=True, centres=centres if window else None, z_range=window)
    steady = (curves["phase"] == PHASES["scratching"]) & (curves["slide"] >= 2.0 * scene.footprint)
    if scene.slide > 0.0 and not np.any(steady):
        steady = curves["phase"] == PHASES["scratching"]
    mean_fn = slide_mean(curves["slide"][steady], curves["normal_force"][steady])       # NaN without a slide
    mean_ft = slide_mean(curves["slide"][steady], curves["tangential_force"][steady])
    (groove_loaded, profile_loaded), (groove_unloaded, profile_unloaded) = (
        grooves.get(k, (None, None)) for k in ("loaded", "unloaded"))
    result = ScratchResult(
        scene=scene, curves=curves, groove_loaded=groove_loaded, groove_unloaded=groove_unloaded,
        profile_loaded=profile_loaded, profile_unloaded=profile_unloaded, removed=removed,
        mean_normal_force=mean_fn, mean_tangential_force=mean_ft, n_elements=int(mesh.t.shape[1]),
        n_dofs=int(basis.N), wall_time=earlier + time.perf_counter() - t_start, increments=len(recorder.rows),
        newton_iterations=iterations, cutbacks=cutbacks, budget=recorder.budget,
        linear_solver=getattr(solver.linear_solver, "name", "custom"), u=u, state=state, specimen=specimen,
        contact=contact, output=out, notes=notes)
    if contact.holds:
        sliding = [h for h in contact.holds if path.phase(h[0]) == "scratching"]
        during = (f", at most {100 * max(h[2] for h in sliding):.2g} % while sliding ({len(sliding)} increments)"
                  if sliding else ", none while sliding")
        result.notes.append(
            f"stick/slip chatter: {len(contact.holds)} increments held {max(h[1] for h in contact.holds)} or fewer "
            f"surface nodes in slip along a frozen direction; they carried at most "
            f"{100 * max(h[2] for h in contact.holds):.2g} % of the contact's Coulomb force sum(A mu p){during}")
    ls = solver.linear_solver
    result.solver_counts = {key: getattr(ls, key) for key in SOLVER_COUNTS if hasattr(ls, key)}
    if hasattr(ls, "times"):
        result.solver_counts.update({f"{key}_s": seconds for key, seconds in ls.times.items()})
    if hasattr(ls, "factorisations"):
        result.notes.append(f"linear solver {ls.name}: {ls.analyses} analyses, {ls.factorisations} numerical "
                            f"factorisations ({ls.times['factorise']:.1f} s), {ls.solves} solves"
                            + (f", {ls.precision_fallbacks} fallback from single to double factors"
                               if getattr(ls, "precision_fallbacks", 0) else "")
                            + (f"; {ls.krylov_solves} inexact corrections with kept factors ({ls.gmres_iterations} "
                               f"GMRES iterations, {ls.krylov_fallbacks} refactorised)"
                               if getattr(ls, "forcing", 0) else ""))
    if hasattr(ls, "builds"):
        result.notes.append(f"linear solver {ls.name}: {ls.builds} factorisations, "
                            f"{int(np.sum(ls.iterations))} Krylov iterations for {len(ls.iterations)} solves")
    if out is not None:
        write_json(out / "summary.json", result.summary())
    return result


class GrooveBalance(NamedTuple):
    """Where the groove's material went, per unit length of scratch at a cross-section (whole model, mm²).

    With u_x = 0 on the symmetry plane and the far side and u_y = 0 on the bottom, integrating
    tr ε = ∂u_x/∂x + ∂u_y/∂y + ∂u_z/∂z over the section gives ∫u_y dx over the top = A_s − A_g (material
    section) = ∫tr ε dA − ∫∂u_z/∂z dA. So A_g − A_s = carried_forward − volume_change: material pushed along
    the scratch (the bow ahead of the tip, ∫∂u_z/∂z dA > 0 where sections nearer the end were pushed further)
    minus the elastic volume change ∫tr ε dA. ``finite_volume_change`` = ∫(det(I + ∇u) − 1) dA is the volume
    change a finite-strain model would see for the same displacements: its difference from ∫tr ε dA is the
    second-order error of the small-strain kinematics in the areas A_g and A_s.
    """

    surface_change: float
    volume_change: float
    carried_forward: float
    finite_volume_change: float


def groove_balance(result: ScratchResult, z: float | None = None) -> GrooveBalance:
    """:class:`GrooveBalance` of the final state of ``result`` in the element layer that contains ``z`` (default:
    the mid-length section), whole model (twice the half model's integrals)."""
    from abrakit.fem import Kinematics

    kin = Kinematics.from_basis(result.specimen.basis)
    z = result.scene.z_section if z is None else z
    zs = np.unique(np.round(result.specimen.mesh.p[2], 12))
    k = int(np.clip(np.searchsorted(zs, z, side="right") - 1, 0, zs.size - 2))
    z0, z1 = zs[k], zs[k + 1]
    qz = kin.quadrature_points[2]
    weight = 2.0 * kin.dx * ((qz >= z0) & (qz <= z1)) / (z1 - z0)
    grad = kin.displacement_gradient(result.u)
    return GrooveBalance(
        surface_change=float(np.sum((grad[..., 0, 0] + grad[..., 1, 1]) * weight)),
        volume_change=float(np.sum(np.trace(grad, axis1=-2, axis2=-1) * weight)),
        carried_forward=float(np.sum(grad[..., 2, 2] * weight)),
        finite_volume_change=float(np.sum((np.linalg.det(np.eye(3) + grad) - 1.0) * weight)),
    )


class HertzCheck(NamedTuple):
    """FE indentation of an elastic quarter block against Hertz (lengths mm, forces N for the whole sphere).

    depth, force: the FE force–depth curve; hertz_force: (4/3) E* √R d^{3/2} at the same depths; error: relative
    force error at the final depth; contact_radius: √(A_c/π) from the closed nodes' surface share A_c;
    radius_bracket: (last closed, first open) node along the x axis; hertz_radius √(R d); max_penetration and
    the penetration the penalty allows at Hertz's peak pressure, p_0/c_N; elements, dofs, wall_time.
    """

    depth: np.ndarray
    force: np.ndarray
    hertz_force: np.ndarray
    error: float
    contact_radius: float
    radius_bracket: tuple[float, float]
    hertz_radius: float
    max_penetration: float
    allowed_penetration: float
    elements: int
    dofs: int
    wall_time: float


@number_arguments
def hertz_indentation(h: float, penalty: float = 1.0, *, R: float = 0.05, d: float = 5e-4, steps: int = 4,
                      extent: float = 30.0, growth: float = 1.4, linear_solver: str = "auto",
                      kinematics: str = "small") -> HertzCheck:
    """Frictionless sphere pressed into an elastic St-52 quarter block, the elastic check of the indentation step.

    The quarter x ≥ 0, z ≥ 0 (symmetry planes x = 0 and z = 0 through the tip's axis) of a block reaching
    ``extent`` contact radii a = √(R d) in every direction, the bottom fixed and the far sides free (the
    half-space of Hertz, truncated); elements of about ``h`` (mm) over (2.25 a)³ under the tip, growing by
    ``growth`` outside; penalty c_N = ``penalty`` · E / h. The depth is reached in ``steps`` increments. The
    truncation stiffens the block by about 0.4 a/L in depth (< 2 % for ``extent`` = 30), the nodal contact
    and the trilinear elements by O((h/a)²), the penalty softens it by the penetration p/c_N. ``kinematics``:
    "small" or "finite" (Hencky material, total Lagrangian; at d/R = 1 % the two agree to O(d/R)).
    """
    t0 = time.perf_counter()
    check_positive("h", h)
    a = math.sqrt(R * d)
    L = extent * a
    # fine zone 2.25 a: nodes then never fall on the contact edge r = a for h = a, a/2, a/4, ...
    axis = zoned_axis(0.0, L, 0.0, 2.25 * a, h, growth)
    ys = zoned_axis(-L, 0.0, -2.25 * a, 0.0, h, growth)
    mesh = skfem.MeshHex.init_tensor(axis, ys, axis)
    tol = 1e-9 * L
    mesh = mesh.with_boundaries({"x0": lambda x: x[0] < tol, "z0": lambda x: x[2] < tol,
                                 "bottom": lambda x: x[1] < -L + tol})
    basis = vector_basis(mesh)
    conditions = [Dirichlet.on(basis, "x0", "x"), Dirichlet.on(basis, "z0", "z"), Dirichlet.on(basis, "bottom")]
    indenter = SphericalIndenter(R)
    path = ScratchPath(depth=d, slide=0.0, z_start=0.0, unload=False)
    c_N = penalty_from_stiffness(ST52["E"], h, penalty)
    contact = IndenterContact(basis, indenter, path.position, c_N=c_N, mu=0.0, symmetry_factor=4.0)
    check_option("kinematics", kinematics, ("small", "finite"))
    finite = kinematics == "finite"
    material = LogStrainPlasticity(st52_material("elastic")) if finite else st52_material("elastic")
    solver = LineSearchSolver(basis, material, conditions, extra_terms=[contact], finite_strain=finite,
                              control=StepControl(initial=1.0 / steps, maximum=1.0 / steps, minimum=1e-4),
                              newton=NewtonOptions(residual_tol=1e-8, max_iterations=30, divergence_check_after=30),
                              linear_solver="direct")
    solver.linear_solver = scene_linear_solver(solver, linear_solver, inexact=False)   # the Hertz check: exact
    depths, forces = [0.0], [0.0]

    def on_step(result):
        contact.on_step(result)
        depths.append(-float(path.position(result.load_factors[-1])[1]))
        forces.append(contact.forces.normal)

    contact.reset(0.0, np.zeros(basis.N))
    solver.run(end=1.0, progress=False, on_step=on_step)
    depths, forces = np.array(depths), np.array(forces)
    hertz = hertz_sphere(ST52["E"], ST52["nu"], R, depths)
    closed = contact.pressure > 0.0
    on_axis = np.abs(contact.reference[:, 2]) < tol
    r_closed = contact.reference[closed & on_axis, 0]
    r_open = contact.reference[~closed & on_axis, 0]
    bracket = (float(r_closed.max(initial=0.0)), float(r_open.min(initial=np.inf)))
    p0 = hertz_sphere(ST52["E"], ST52["nu"], R, d).max_pressure
    return HertzCheck(
        depth=depths, force=forces, hertz_force=np.asarray(hertz.force), error=float(forces[-1] / hertz.force[-1] - 1),
        contact_radius=math.sqrt(contact.forces.area / math.pi), radius_bracket=bracket, hertz_radius=a,
        max_penetration=contact.forces.max_penetration, allowed_penetration=p0 / c_N,
        elements=int(mesh.t.shape[1]), dofs=int(basis.N), wall_time=time.perf_counter() - t0)


SEED_FORMULATION = {"kinematics": "small", "bbar": False}
"""The seed's formulation of the scratch (Ch. 4.2: small strain; full integration as the scene had it before):
``ScratchScene(**SEED_FORMULATION)``."""

DEMO_SCENE = ScratchScene(slide=0.03, mesh="demo", size=(0.1, 0.015, 0.1))
"""The coarse live scene of ``abrakit demo`` and the book: the seed's tip and depth, 100 µm long block, 30 µm slide,
in the scene's physics (finite strain, F-bar); ``DEMO_SCENE.with_(**SEED_FORMULATION)`` is the seed's small-strain,
fully integrated formulation of the same scene, for comparison."""


def demo() -> str:
    """A coarse scratch (sphere R = 50 µm, d = 2 µm, 30 µm slide, St-52, demo mesh) in well under a minute."""
    scene = DEMO_SCENE
    r = run_scratch(scene, vtu_every=0)
    lines = [
        f"Single scratch, half model: sphere R = {scene.indenter.radius * 1e3:g} um, d = {scene.depth * 1e3:g} um, "
        f"slide {scene.slide * 1e3:g} um, St-52 (sigma_0 = {ST52['yield_stress']:g} MPa, H = "
        f"{ST52['hardening']:g} MPa), mu = {scene.mu}; finite strain with F-bar (the scene's physics; "
        f"DEMO_SCENE.with_(**SEED_FORMULATION) is the seed's small-strain formulation, for comparison); "
        f"{r.n_elements} hexes / {r.n_dofs} DOF, {r.increments} increments, {r.newton_iterations} Newton "
        f"iterations, {r.cutbacks} cutbacks, {r.wall_time:.1f} s",
        f"forces while sliding (whole grain): F_N = {r.mean_normal_force:.3f} N, F_T = {r.mean_tangential_force:.3f}"
        f" N (F_T/F_N = {r.mean_tangential_force / r.mean_normal_force:.3f}); peak F_N "
        f"{np.max(r.curves['normal_force']):.3f} N at the end of the indentation",
    ]
    for label, g in (("tip in contact", r.groove_loaded), ("after unloading", r.groove_unloaded)):
        if g is None:
            lines.append(f"groove {label}: not defined ({'; '.join(r.notes)})")
        else:
            lines.append(f"groove {label}: A_g = {g.groove_area * 1e6:.1f} um2, A_s = {g.shoulder_area * 1e6:.1f} "
                         f"um2, w = {g.width * 1e3:.1f} um, f_ab = {g.degree_of_wear:.2f} ({g.regime}), "
                         f"D_p = {g.degree_of_penetration:.3f}")
    b = r.budget.as_dict(scale=1e9)
    lines.append(f"volume audit (um3): groove {b['groove']:.0f} + sink {b['sink']:.0f} = shoulders {b['shoulders']:.0f}"
                 f" + prow {b['prow']:.0f} - int(J-1)dV {b['volume_change']:+.0f} (closure {b['residual']:.1e}); "
                 "finite strain keeps only the elastic volume change, small strain loses volume at second order "
                 "(chapter 'Where the groove goes')")
    return "\n".join(lines)
