"""Running a scratch scene: the Newton driver's pieces, the increments, the record and the result.

:func:`run_scratch` follows the path of a :class:`~abrakit.scratch.scene.ScratchScene` (indent, slide, unload)
with :class:`abrakit.fem.Solver`, configured by :func:`scene_solver`:

* increments (:func:`segments`): the indentation in ``indent_steps`` equal increments; the slide in increments of
  ``slide_step`` (default h_z/4), the first one :data:`SLIDE_RAMP` of it, growing by 1.5 after two increments of
  at most 7 Newton iterations and cut back by 1/4 down to 10⁻³ of the nominal one; the unloading in
  ``unload_steps``. Every increment starts from the last converged state (``StepControl(extrapolate=False)``):
  extrapolating the last increment pushes the nodes ahead of a moving tip into it or away from it;
* Newton: :data:`SCRATCH_NEWTON`, the corrections damped by a backtracking :class:`~abrakit.fem.solver.LineSearch`
  (contact and plasticity make the residual only piecewise smooth), a converged residual's increment test by a
  chord step with the kept factors; a failed step is named by :class:`ScratchDiagnosis`;
* linear solver: :func:`scene_linear_solver` (PARDISO or SuperLU keeping their analysis, inexact corrections
  :data:`SCENE_FORCING` within an increment);
* Model II (``damage=True``): the rate limit of Eq. (6.97) takes α times the work of the tip on the half model in
  the increment, with the tip force of the last converged increment (explicit); elements whose damage reaches
  Model II's cap are removed material (the volume audit, :attr:`ScratchResult.removed`) and their surface nodes
  leave the contact.

It writes ``forces.csv`` (one row per increment, :mod:`abrakit.scratch.record`), ``fields/step.pvd``,
``summary.json`` and the checkpoint ``last_converged.npz`` (:mod:`abrakit.scratch.checkpoint`) as it goes, and
reads the groove's mid-length cross-section with the tip in contact (τ = 1.5) and after unloading
(:func:`~abrakit.scratch.readouts.groove_section`: A_g, A_s, w, f_ab of Eq. 8.5, D_p of Eq. 8.6, regime).
:func:`~abrakit.scratch.run_hertz.hertz_indentation` is the elastic check of the indentation against Hertz.
Units: N, mm, MPa.

Example::

    result = run_scratch(DEMO_SCENE, vtu_every=0)
    result.mean_normal_force, result.groove_unloaded.degree_of_wear
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from abrakit.fem.linsolve import DirectSolver, pardiso_available, rigid_body_modes
from abrakit.fem.preconditioners import ReusedPreconditioner, nested_dissection
from abrakit.fem.solver import Iterate, LineSearch, NewtonOptions, Solver, StepControl, StepFailed
from abrakit.io import write_json
from abrakit.materials import LogStrainPlasticity
from abrakit.scratch.budget import VolumeBudget
from abrakit.scratch.checkpoint import CHECKPOINT, load_scratch_checkpoint, save_scratch_checkpoint
from abrakit.scratch.contact import penalty_from_stiffness
from abrakit.scratch.contact_term import IndenterContact
from abrakit.scratch.erosion import ErodingMaterial, ErosionStep, erosion_summary
from abrakit.scratch.groove import GrooveMetrics, Profile, RemovedMaterial, removed_material
from abrakit.scratch.indenters import ScratchPath
from abrakit.scratch.readouts import element_damage, groove_section, removed_elements, surface_nodes_of
from abrakit.scratch.record import PHASES, ScratchRecorder, slide_mean
from abrakit.scratch.scene import (
    ST52,
    ScratchScene,
    ScratchSpecimen,
    SpecimenMesh,
    build_specimen,
    st52_material,
)
from abrakit.validation import check_integer, check_option

SCRATCH_NEWTON = NewtonOptions(residual_tol=1e-3, increment_tol=1e-2, max_iterations=20, divergence_check_after=10,
                               tangent_reuse=1e-4)
"""Newton's options of :func:`run_scratch`: converged when the residual is below 10⁻³ of the largest nodal force
and the last correction below 10⁻² of the increment's displacement (Abaqus/Standard's correction criterion); the
element tangents of elements whose F moved by less than 10⁻⁴ and that do not yield are kept
(:class:`~abrakit.fem.tangent_reuse.ElementTangentReuse`: the residual stays exact, only the Newton matrix differs,
by about 10⁻⁴ relative in those elements)."""

AMG_ABOVE = 120_000
"""Free DOFs above which a scene without PARDISO takes the AMG-preconditioned GMRES instead of SuperLU
(:func:`scene_linear_solver`); with PARDISO the direct solver serves every size."""

SCENE_FORCING = {"forcing": 0.03, "krylov_iterations": 8}
"""Inexact Newton corrections of a scene's direct solvers (:class:`~abrakit.fem.DirectSolver` ``forcing``): within
an increment, GMRES preconditioned with the factors kept from the increment's last factorisation, to 3 % of the
residual (the forcing term η = 0.03 of Eisenstat and Walker) in at most eight iterations, before a new
factorisation; the first iteration of an increment always factorises (nodes newly in contact).
``benchmarks/bench_kept_factors.py`` measures what it saves."""

SLIDE_RAMP = 0.25
"""The slide starts with this fraction of its increment and grows to it (×1.5 after two easy increments): the
tip's first move turns the whole contact from stick to slip at once."""

SOLVER_COUNTS = ("analyses", "factorisations", "solves", "krylov_solves", "krylov_fallbacks", "gmres_iterations",
                 "precision_fallbacks")
"""The linear solver's counters a :class:`ScratchResult` keeps (``solver_counts``, with the seconds of its
analyses, factorisations and solves)."""


# ---- the solver's pieces ----------------------------------------------------------------------------------------


def scene_linear_solver(solver: Solver, kind: str = "auto", inexact: bool = True):
    """The linear solver of a 3D contact scene for ``solver``'s free DOFs, all keeping their analysis across
    Newton iterations: ``"pardiso"`` (:class:`~abrakit.fem.DirectSolver` on MKL PARDISO, METIS order, factors in
    single precision refined to the double answer), ``"lu"`` (the same on SuperLU in the
    :func:`~abrakit.fem.preconditioners.nested_dissection` order), ``"amg"`` (GMRES with a reused AMG hierarchy,
    the rigid-body modes as near-null space, :class:`~abrakit.fem.preconditioners.ReusedPreconditioner`) or
    ``"auto"`` (PARDISO if installed, at every size; else LU, or AMG above :data:`AMG_ABOVE` free DOFs, where
    SuperLU's factors grow too large). ``inexact``: the direct solvers' corrections within an increment by GMRES
    with kept factors (:data:`SCENE_FORCING`; False: every correction exact)."""
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


class ScratchDiagnosis:
    """``diagnose(reason, iterate)`` of :class:`abrakit.fem.Solver` for a scratch: the cause of a failed Newton
    step, from its last iterate. ``element inversion`` (det F ≤ 0 under the tip), ``contact`` (the largest free
    residual sits at a surface node of ``contact``: its status and gap are named, the signature of a node
    chattering between states) or ``bulk`` (inside the block, where plasticity switches; position named).
    Positions in µm, gaps in nm."""

    def __init__(self, basis, contact: IndenterContact):
        self.doflocs = basis.doflocs
        self.contact = contact

    def __call__(self, reason: str = "", iterate: Iterate | None = None) -> str:
        if "inverted" in reason:
            return ("element inversion: det F <= 0 under the tip; the slide step is too large for the mesh, or "
                    "the top layer too thin for the depth")
        if iterate is None:
            return "no residual was evaluated"
        u, residual, ctx, free = iterate
        dof = int(free[np.argmax(np.abs(residual[free]))])
        where = np.round(self.doflocs[:, dof] * 1e3, 2)
        c = self.contact
        nodes = np.nonzero(np.any(c.dofs == dof, axis=1))[0]
        if nodes.size:
            n = nodes[0]
            status = c.trial_status
            status = "?" if status is None else ("open", "stick", "slip")[int(status[n])]
            gap = c.indenter.gap((c.reference[n] + u[c.dofs[n]])[None],
                                 np.asarray(c.position(ctx.load_factor), dtype=float)).gap[0]
            return (f"contact: the largest residual, {abs(residual[dof]):.2e} N, sits at surface node "
                    f"{int(c.nodes[n])} at (x, z) = ({where[0]:g}, {where[2]:g}) um, {status}, gap "
                    f"{gap * 1e6:.3g} nm: a contact node switching between states (chatter)")
        return (f"bulk: the largest residual, {abs(residual[dof]):.2e} N, sits inside the block at "
                f"(x, y, z) = ({where[0]:g}, {where[1]:g}, {where[2]:g}) um")


def scene_solver(basis, material, conditions, contact: IndenterContact, *, newton: NewtonOptions,
                 linear_solver: str = "auto", inexact: bool = True, **options) -> Solver:
    """:class:`abrakit.fem.Solver` of a contact scene: ``contact`` as its extra term, a backtracking
    :class:`~abrakit.fem.solver.LineSearch`, :class:`ScratchDiagnosis` and :func:`scene_linear_solver`;
    ``options`` (``loading``, ``control``, ``bbar``, ``finite_strain``) go to the solver."""
    solver = Solver(basis, material, conditions, extra_terms=[contact], newton=newton, linear_solver="direct",
                    line_search=LineSearch(), diagnose=ScratchDiagnosis(basis, contact), **options)
    solver.linear_solver = scene_linear_solver(solver, linear_solver, inexact)
    return solver


def segments(scene: ScratchScene, spec: SpecimenMesh) -> list[tuple[float, float, float, float]]:
    """Pseudo-time segments (start, end, increment, first increment): indentation, the slide's two halves,
    unloading."""
    slide_step = scene.slide_step if scene.slide_step is not None else 0.25 * spec.size_z
    dtau = 1.0 / scene.indent_steps
    parts = [(0.0, 1.0, dtau, dtau)]
    if scene.slide > 0.0:
        dtau = min(0.5, slide_step / scene.slide)
        parts += [(1.0, 1.5, dtau, SLIDE_RAMP * dtau), (1.5, 2.0, dtau, dtau)]
    if scene.unload:
        if scene.slide == 0.0:
            parts.append((1.0, 2.0, 1.0, 1.0))             # nothing moves: one idle increment
        dtau = 1.0 / scene.unload_steps
        parts.append((2.0, 3.0, dtau, dtau))
    return parts


# ---- the result -------------------------------------------------------------------------------------------------


@dataclass
class ScratchResult:
    """What a scratch run gives (forces for the whole grain; lengths mm, areas mm², forces N, times s).

    curves: the force curves, one entry per converged increment (also in ``forces.csv``): ``tau`` (pseudo-time
    of :class:`~abrakit.scratch.ScratchPath`), ``tip_y``, ``tip_z``, ``slide`` (apex travel along z),
    ``normal_force``, ``tangential_force``, ``contact_area``, ``max_penetration``, ``iterations``;
    groove_loaded / groove_unloaded: :class:`~abrakit.scratch.groove.GrooveMetrics` of the mid-length section
    with the apex there / after unloading (None when not computed; ``notes`` say why), with their profiles;
    removed: :class:`~abrakit.scratch.groove.RemovedMaterial` near mid-length (damage runs), None otherwise;
    erosion: eroded elements, released energy (N mm) and the largest element damage (erosion runs, else None);
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
    specimen: ScratchSpecimen
    contact: IndenterContact
    budget: VolumeBudget | None = None
    output: Path | None = None
    notes: list = field(default_factory=list)
    solver_counts: dict = field(default_factory=dict)
    erosion: dict | None = None

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
        if self.erosion is not None:
            out["erosion"] = self.erosion
        return out


def _solver_notes(ls, contact: IndenterContact, path: ScratchPath) -> tuple[dict, list[str]]:
    """The linear solver's counters (:data:`SOLVER_COUNTS` and seconds) and the notes on the contact's
    stick/slip holds and on the linear solver."""
    notes = []
    if contact.holds:
        sliding = [h for h in contact.holds if path.phase(h[0]) == "scratching"]
        during = (f", at most {100 * max(h[2] for h in sliding):.2g} % while sliding ({len(sliding)} increments)"
                  if sliding else ", none while sliding")
        notes.append(
            f"stick/slip chatter: {len(contact.holds)} increments held {max(h[1] for h in contact.holds)} or fewer "
            f"surface nodes in slip along a frozen direction; they carried at most "
            f"{100 * max(h[2] for h in contact.holds):.2g} % of the contact's Coulomb force sum(A mu p){during}")
    counts = {key: getattr(ls, key) for key in SOLVER_COUNTS if hasattr(ls, key)}
    if hasattr(ls, "times"):
        counts.update({f"{key}_s": seconds for key, seconds in ls.times.items()})
    if hasattr(ls, "factorisations"):
        notes.append(f"linear solver {ls.name}: {ls.analyses} analyses, {ls.factorisations} numerical "
                     f"factorisations ({ls.times['factorise']:.1f} s), {ls.solves} solves"
                     + (f", {ls.precision_fallbacks} fallback from single to double factors"
                        if getattr(ls, "precision_fallbacks", 0) else "")
                     + (f"; {ls.krylov_solves} inexact corrections with kept factors ({ls.gmres_iterations} "
                        f"GMRES iterations, {ls.krylov_fallbacks} refactorised)"
                        if getattr(ls, "forcing", 0) else ""))
    if hasattr(ls, "builds"):
        notes.append(f"linear solver {ls.name}: {ls.builds} factorisations, "
                     f"{int(np.sum(ls.iterations))} Krylov iterations for {len(ls.iterations)} solves")
    return counts, notes


# ---- running a scene --------------------------------------------------------------------------------------------


class _ScratchRun:
    """One run of a scene: its specimen, material, contact, solver, record and checkpoint, and where it stands
    (u, state, the counters of the finished phases, the displacement with the tip in contact)."""

    def __init__(self, scene: ScratchScene, output, *, vtu_every: int, linear_solver: str, newton: NewtonOptions,
                 inexact: bool, checkpoint_every: int):
        self.scene, self.path = scene, scene.path
        self.specimen = specimen = build_specimen(scene)
        material = st52_material(scene.material, scene.damage, scene.damage_energy, scene.hardening)
        finite = scene.kinematics == "finite"
        material = LogStrainPlasticity(material) if finite else material
        if scene.erosion is not None:
            material = ErodingMaterial(material, scene.erosion.residual)
        self.material = material
        c_N = penalty_from_stiffness(ST52["E"], specimen.top_layer, scene.penalty)
        self.contact = contact = IndenterContact(specimen.basis, scene.indenter, self.path.position, c_N=c_N,
                                                 mu=scene.mu)
        # the indenter must start outside the block (ScratchPath refuses clearance < 0; this also covers a tip
        # whose surface reaches below y = 0 away from its apex)
        if np.any(scene.indenter.gap(contact.reference, self.path.position(0.0)).gap < -1e-12):
            raise ValueError("the indenter starts inside the block: some surface nodes lie inside the tip at tau = 0")
        self.converged_force = np.zeros(3)   # the tip force of the last converged increment (explicit rate limit)
        removing = scene.damage or scene.erosion is not None
        self.removed_nodes = surface_nodes_of(specimen.mesh, contact.nodes) if removing else None
        self.solver = scene_solver(specimen.basis, material, specimen.conditions, contact, newton=newton,
                                   linear_solver=linear_solver, inexact=inexact, loading=self.loading,
                                   bbar=scene.bbar, finite_strain=finite)
        self.out = Path(output) if output is not None else None
        self.erosion = erosion = ErosionStep(scene.erosion, self.solver.kin, material, contact.symmetry_factor) \
            if scene.erosion is not None else None
        extra, removed = None, None
        if scene.damage:
            extra = lambda st: {"effective_damage": material.effective_damage(st).mean(axis=1)}   # noqa: E731
            removed = removed_elements(material)
        elif erosion is not None:
            extra = lambda st: {"ductile_damage": erosion.element_damage(st),                      # noqa: E731
                                "eroded": ErosionStep.removed(st).astype(float)}
            removed = ErosionStep.removed
        self.recorder = ScratchRecorder(self.path, contact, self.solver.kin, output=self.out, vtu_every=vtu_every,
                                        extra_fields=extra, removed=removed)
        self.checkpoint = self.out / CHECKPOINT if self.out is not None else None
        self.checkpoint_every = checkpoint_every
        self.u = np.zeros(specimen.basis.N)
        self.state = material.initial_state((self.solver.kin.nel, self.solver.kin.nqp))
        self.converged_state = self.state             # the state the erosion's damage update starts from
        self.iterations = self.cutbacks = 0
        self.tau_done, self.u_loaded, self.continuation, self.earlier = 0.0, None, None, 0.0

    def loading(self, ctx) -> dict:
        """Model II's rate limit (``external_work``): α Δt of Table 8.2 (``damage_rate="step"``) or the work of
        the last converged tip force over the tip's move in this increment, half model, N mm (``"work"``)."""
        if not self.scene.damage:
            return {}
        if self.scene.damage_rate == "step":
            return {"external_work": 1.0}     # alpha [1/s] * dt [1 s]: the increment alpha*dt of Table 8.2
        path = self.path
        tip_move = np.asarray(path.position(ctx.load_factor)) - path.position(ctx.load_factor - ctx.delta)
        work = -self.converged_force @ tip_move / self.contact.symmetry_factor
        return {"external_work": max(work, 0.0)}

    def plain_gradient(self, state) -> None:
        """Eroded elements leave F-bar for the plain gradient (they may invert: they carry only the residual
        spring, :class:`~abrakit.fem.kinematics.FBarKinematics`)."""
        if hasattr(self.solver.kin, "use_plain_gradient"):
            self.solver.kin.use_plain_gradient(ErosionStep.removed(state))

    def save(self, u, state, tau: float, iterations: int, continuation=None) -> None:
        save_scratch_checkpoint(self.checkpoint, self.scene, u=u, state=state, tau=tau, recorder=self.recorder,
                                contact=self.contact, iterations=iterations, cutbacks=self.cutbacks,
                                u_loaded=self.u_loaded, continuation=continuation)

    def on_step(self, res) -> None:
        """After every converged increment: record it (and commit the contact), take removed material out of the
        contact, save a checkpoint every ``checkpoint_every`` increments. Erosion (staggered, first) erodes the
        elements this increment failed, so that the record and the contact see them."""
        if self.erosion is not None:
            if self.erosion(self.converged_state, res.state).size:
                self.plain_gradient(res.state)
            self.converged_state = res.state
        self.recorder(res)
        self.converged_force = np.array(self.contact.forces.force, dtype=float)
        if self.removed_nodes is not None:                   # removed material (the audit's mask) leaves the contact
            self.contact.remove(self.removed_nodes(self.recorder.removed_mask))
        if self.checkpoint is not None and self.checkpoint_every and \
                len(self.recorder.rows) % self.checkpoint_every == 0:
            self.save(res.u, res.state, float(res.load_factors[-1]), self.iterations + int(res.iterations.sum()),
                      res.continuation)

    def start(self, saved: dict | None) -> None:
        """From the start (a virgin contact) or from the checkpoint ``saved``."""
        if saved is None:
            self.contact.reset(0.0, self.u)
            return
        self.u, self.state, self.tau_done, self.u_loaded = (saved[k] for k in ("u", "state", "load_factor",
                                                                               "u_loaded"))
        self.iterations, self.cutbacks = saved["meta"]["iterations"], saved["meta"]["cutbacks"]
        self.continuation = saved["continuation"]
        self.converged_state = self.state
        if self.erosion is not None:
            self.plain_gradient(self.state)
        self.recorder.restart(saved["meta"]["record"])
        self.earlier = self.recorder.rows[-1]["wall_time"] if self.recorder.rows else 0.0   # the calls before
        self.contact.restore(saved["arrays"], saved["meta"]["contact"])
        if self.contact.forces is not None:
            self.converged_force = np.array(self.contact.forces.force, dtype=float)

    def phase(self, start: float, end: float, dtau: float, first: float, progress: bool) -> None:
        """One segment of the path, from the state reached (or the checkpoint's continuation inside it)."""
        solver = self.solver
        solver.control = StepControl(initial=first, maximum=dtau, minimum=dtau * 1e-3, easy_iterations=7,
                                     extrapolate=False)
        try:
            result = solver.run(start=start, end=end, u0=self.u, state0=self.state, progress=progress,
                                on_step=self.on_step,
                                continuation=self.continuation if start < self.tau_done else None)
        except StepFailed as failure:          # keep the last converged increment, then say where the run stopped
            raise self.stopped(failure) from failure
        self.u, self.state = result.u, result.state
        self.iterations += int(result.iterations.sum())
        self.cutbacks += result.cutbacks
        self.recorder.write_fields(end, self.u, result.response.stress, self.state)      # the end of every phase
        if self.scene.slide > 0.0 and end == 1.5:
            self.u_loaded = self.u.copy()
        if self.checkpoint is not None:
            self.save(self.u, self.state, end, self.iterations)

    def stopped(self, failure: StepFailed) -> StepFailed:
        """The run's :class:`~abrakit.fem.StepFailed`: where it stopped, why, and the checkpoint it left."""
        res, checkpoint, scene = failure.result, self.checkpoint, self.scene
        if checkpoint is not None:
            self.save(res.u, res.state, float(res.load_factors[-1]), self.iterations + int(res.iterations.sum()),
                      res.continuation)
        where = f"; its last converged increment is saved in {checkpoint} (resume=True goes on from it)" \
            if checkpoint is not None else ""
        slid = min(max(failure.load_factor - 1.0, 0.0), 1.0) * scene.slide * 1e3
        return StepFailed(f"scratch stopped at tau = {failure.load_factor:.6g} "
                          f"({self.path.phase(failure.load_factor)}, slide {slid:.4g} um of {scene.slide * 1e3:g}):"
                          f" {failure.reason}{where}",
                          load_factor=failure.load_factor, u=failure.u, state=failure.state,
                          reason=failure.reason, result=res, checkpoint=checkpoint)

    def grooves(self) -> tuple[dict, list[str]]:
        """The mid-length sections with the tip in contact and at the end, ``{key: (metrics, profile)}``, and the
        notes on sections without a groove."""
        grooves, notes = {}, []
        for key, u, label in (("loaded", self.u_loaded, "tip in contact"),
                              ("unloaded", self.u if self.scene.slide > 0.0 else None,
                               "after unloading" if self.scene.unload else "end of slide")):
            if u is not None:
                metrics, profile, why = groove_section(self.specimen, u, self.scene)
                if why:
                    notes.append(f"{label}: {why}")
                grooves[key] = metrics, profile
        return grooves, notes

    def result(self, grooves: dict, notes: list[str], seconds: float) -> ScratchResult:
        scene, state, mesh, curves = self.scene, self.state, self.specimen.mesh, self.recorder.curves()
        removed = None
        if scene.damage:
            centres = mesh.p[:, mesh.t].mean(axis=1).T
            window = (scene.z_section - 0.25 * scene.slide, scene.z_section + 0.25 * scene.slide) \
                if scene.slide else None
            removed = removed_material(self.solver.kin.dx.sum(axis=1), element_damage(state), self.material.d_max,
                                       half=True, centres=centres if window else None, z_range=window)
        steady = (curves["phase"] == PHASES["scratching"]) & (curves["slide"] >= 2.0 * scene.footprint)
        if scene.slide > 0.0 and not np.any(steady):
            steady = curves["phase"] == PHASES["scratching"]
        (groove_loaded, profile_loaded), (groove_unloaded, profile_unloaded) = (
            grooves.get(k, (None, None)) for k in ("loaded", "unloaded"))
        counts, solver_notes = _solver_notes(self.solver.linear_solver, self.contact, self.path)
        return ScratchResult(
            scene=scene, curves=curves, groove_loaded=groove_loaded, groove_unloaded=groove_unloaded,
            profile_loaded=profile_loaded, profile_unloaded=profile_unloaded, removed=removed,
            mean_normal_force=slide_mean(curves["slide"][steady], curves["normal_force"][steady]),   # NaN: no slide
            mean_tangential_force=slide_mean(curves["slide"][steady], curves["tangential_force"][steady]),
            n_elements=int(mesh.t.shape[1]), n_dofs=int(self.specimen.basis.N), wall_time=self.earlier + seconds,
            increments=len(self.recorder.rows), newton_iterations=self.iterations, cutbacks=self.cutbacks,
            budget=self.recorder.budget, linear_solver=getattr(self.solver.linear_solver, "name", "custom"),
            u=self.u, state=state, specimen=self.specimen, contact=self.contact, output=self.out,
            notes=notes + solver_notes, solver_counts=counts,
            erosion=None if self.erosion is None else erosion_summary(self.erosion, state))


SEED_SCENE = ScratchScene()
"""The seed's default scene (sphere R = 50 µm, d = 2 µm, 100 µm slide, "default" mesh): :func:`run_scratch`'s."""


def run_scratch(scene: ScratchScene = SEED_SCENE, *, output=None, progress: bool = False, vtu_every: int = 10,
                linear_solver: str = "auto", newton: NewtonOptions | None = None, checkpoint_every: int = 10,
                resume: bool = False, inexact: bool = True) -> ScratchResult:
    """Run the single scratch ``scene``; write ``forces.csv``, ``fields/step.pvd`` and ``summary.json`` to
    ``output`` (if given) as it goes; return a :class:`ScratchResult`.

    ``linear_solver``: "pardiso", "lu", "amg" or "auto", and ``inexact`` (corrections within an increment by GMRES
    with kept factors, :data:`SCENE_FORCING`), see :func:`scene_linear_solver`; ``newton``: default
    :data:`SCRATCH_NEWTON`. ``vtu_every``: field output every that many increments (and at the end of every
    phase); 0 disables it. ``checkpoint_every``: with ``output``, save ``last_converged.npz`` every that many
    increments and at the end of every phase (0: at phase ends only; :mod:`abrakit.scratch.checkpoint`).
    ``resume=True`` continues from that checkpoint, if there is one: ``forces.csv`` and the VTU series go back to
    it and the increments after it are recomputed with the phase's nominal increment (the same increments as an
    uninterrupted run unless a cutback was being recovered from when it stopped).
    """
    check_integer("vtu_every", vtu_every, 0)
    check_integer("checkpoint_every", checkpoint_every, 0)
    t_start = time.perf_counter()
    run = _ScratchRun(scene, output, vtu_every=vtu_every, linear_solver=linear_solver,
                      newton=newton or SCRATCH_NEWTON, inexact=inexact, checkpoint_every=checkpoint_every)
    saved = (load_scratch_checkpoint(run.checkpoint, scene, run.specimen.basis.N)
             if resume and run.checkpoint is not None else None)
    try:
        run.start(saved)
        for start, end, dtau, first in segments(scene, scene.mesh_spec):
            if end > run.tau_done:                                        # not done before the checkpoint
                run.phase(start, end, dtau, first, progress)
        grooves, notes = run.grooves()
    finally:
        run.recorder.close()
    result = run.result(grooves, notes, time.perf_counter() - t_start)
    if run.out is not None:
        write_json(run.out / "summary.json", result.summary())
    return result
