r"""Path following: the load factor becomes an unknown, so a softening structure can be followed through snap-back.

Displacement control prescribes the load factor λ of every step. Past the peak of a softening structure the
force–displacement curve may turn back (snap-back): equilibrium at a larger end displacement then exists only on
a distant branch, and a displacement-controlled solver either fails or jumps there. Path following adds λ to the
unknowns and one scalar equation, the *constraint* g(Δu, Δλ) = 0, to the equilibrium equations (Crisfield 1991,
Ch. 9; de Borst et al. 2012, Ch. 4):

    R_I(u, λ) = f_int,I(u) − λ f̂_I = 0,        g(Δu, Δλ) = 0,

where the load is either an external force λ f̂ or a prescribed displacement u_D = u_D(0) + λ û_D (then f̂ = 0 and
λ enters through the prescribed DOFs). Newton's method on the bordered system solves two systems with the same
tangent per iteration (one factorisation),

    K_II δu_R = −R_I,        K_II δu_q = q,        q = f̂_I − K_ID û_D,

and sets δu_I = δu_R + δλ δu_q with δλ from the linearised constraint (``Constraint.correction``).

Constraints (``g`` of a step from the converged point (u₀, λ₀)):

- :class:`LoadFactorControl`: Δλ = τ (ordinary load or displacement control);
- :class:`ArcLength`: Crisfield's cylindrical arc length ``|Δu|² = Δl²`` over all DOFs (the prescribed ones included,
  Δu_D = Δλ û_D); the quadratic for δλ has two roots, the one whose increment makes the smaller angle with the
  previous one is taken, so the path does not double back;
- :class:`DissipationControl`: the energy released in the step, G = ½ (P₀ Δv − v₀ ΔP) = τ (Gutiérrez 2004;
  Verhoosel, Remmers & Gutiérrez 2009), with (v, P) the work-conjugate load pair: (λ, û_Dᵀ f_int) under
  prescribed displacement, (f̂ᵀ u, λ) under an external force. For a material that unloads along the secant
  (elastic damage) G is exactly the energy dissipated in the step to first order, and it grows monotonically
  through snap-back, which makes it the robust path parameter of localised softening.

:class:`PathFollowingSolver` starts under load-factor control and switches to dissipation control when a step
releases more than ``switch`` times the external work of that step (the structure has begun to soften; a
load-controlled step that did so is redone, since it may have jumped a snap-back, and a limit point where load
control fails is passed with the opening or arc-length constraint); the
dissipation target then follows the iteration count. If the dissipation constraint has no solution (the
structure unloads elastically: G ≤ 0 along the tangent) it switches back to load-factor control. The arc-length
constraint can be chosen instead (``method="arc-length"``). A failed step is retried with the target cut back,
as in :class:`~abrakit.fem.Solver`.

Limits, measured (``tests/test_damage_model_two.py``): G is the dissipated energy only where unloading is secant.
With plasticity, elastic unloading from a plastic state also has G > 0, so dissipation control may follow an
unloading branch instead of damaging (Model II on the double notch does); arc length or opening control follow such
materials (Model II under arc length reaches the displacement-controlled peak to 0.2 %). Arc length cannot pass a
kinked peak (the snap-back bar of 37 elements: the weak element's loading flag alternates, the constraint has no
real root however short the arc); it stops there and its message names dissipation and opening control, which pass
it. The staggered damage update
of Model I (damage after the displacement iterations) is not part of the Newton system; its path follower
(:class:`abrakit.damage.model_one_path.ModelIPathFollowingSolver`) repeats Newton solve and damage update within
each step until they agree.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..io import progress_bar
from ..validation import check_finite, check_number_fields, check_option, check_positive, check_range
from ._path_run import _Walk
from .linsolve import LinearSolveError
from .recorder import RunRecorder
from .solver import NewtonFailure, Solver, SolveResult, StepContext, StepFailed

METHODS = ("dissipation", "arc-length", "opening")


@dataclass
class PathPoint:
    """What a constraint reads: the converged start of the step (``u0``, ``lam0``, load pair ``v0``, ``P0``), the
    current iterate (``u``, ``lam``, ``v``, ``P``), the tangent ``K`` (full), the load directions ``u_hat`` (on
    the prescribed DOFs) and ``f_hat`` (external force), the free DOFs, and the previous step's increment."""

    u0: np.ndarray
    lam0: float
    v0: float
    P0: float
    u: np.ndarray
    lam: float
    v: float
    P: float
    K: object
    u_hat: np.ndarray
    f_hat: np.ndarray
    free: np.ndarray
    previous: tuple[np.ndarray, float] | None = None

    @property
    def du(self) -> np.ndarray:
        return self.u - self.u0

    @property
    def dlam(self) -> float:
        return self.lam - self.lam0


def increment_length(du_free: np.ndarray, dlam: float, u_hat: np.ndarray) -> float:
    """|Δu| over all DOFs of an increment: the free part ``du_free`` and Δλ û on the prescribed DOFs (mm)."""
    return float(np.sqrt(du_free @ du_free + dlam**2 * (u_hat @ u_hat)))


class ConstraintSingular(NewtonFailure):
    """The linearised constraint does not involve the load factor (e.g. no energy is released along the
    tangent of an elastic structure)."""


class LinearConstraint:
    """A constraint ``g`` whose linearisation ``g + a·δu_I + b δλ`` fixes δλ (subclasses give ``residual`` and
    ``gradient``)."""

    tau: float

    def __post_init__(self):
        check_number_fields(self)

    def residual(self, p: PathPoint) -> float:
        raise NotImplementedError

    def gradient(self, p: PathPoint) -> tuple[np.ndarray | None, float]:
        raise NotImplementedError

    def correction(self, p: PathPoint, du_R: np.ndarray, du_q: np.ndarray) -> float:
        a, b = self.gradient(p)
        a_R, a_q = (0.0, 0.0) if a is None else (a @ du_R, a @ du_q)
        denominator = a_q + b
        if not np.isfinite(denominator) or abs(denominator) <= 1e-12 * (abs(a_q) + abs(b)):
            raise ConstraintSingular(f"{self.name}: the constraint does not fix the load factor", [])
        return -(self.residual(p) + a_R) / denominator

    def predictor(self, p: PathPoint, du_q: np.ndarray) -> float:
        """Δλ of the tangent predictor from the converged point (R = 0 there)."""
        return self.correction(p, np.zeros_like(du_q), du_q)

    def satisfied(self, p: PathPoint, scale: float) -> bool:
        return abs(self.residual(p)) <= 1e-8 * scale


@dataclass
class LoadFactorControl(LinearConstraint):
    """Δλ = τ: load (or displacement) control."""

    tau: float
    name = "load factor"

    def residual(self, p):
        return p.dlam - self.tau

    def gradient(self, p):
        return None, 1.0

    def satisfied(self, p, scale):
        return abs(self.residual(p)) <= 1e-12 * max(abs(self.tau), 1e-300)


@dataclass
class DissipationControl(LinearConstraint):
    """G = ½ (P₀ Δv − v₀ ΔP) = τ, the energy released in the step (N mm, or N mm/mm in plane strain)."""

    tau: float
    name = "dissipation"

    def residual(self, p):
        return 0.5 * (p.P0 * (p.v - p.v0) - p.v0 * (p.P - p.P0)) - self.tau

    def gradient(self, p):
        free = p.free
        if np.any(p.u_hat):          # v = λ, P = û_Dᵀ f_int: ∂P/∂u_I = (Kᵀ û)_I, ∂P/∂λ = ûᵀ K û
            KT_u = p.K.T @ p.u_hat
            return -0.5 * p.v0 * KT_u[free], 0.5 * p.P0 - 0.5 * p.v0 * float(p.u_hat @ (p.K @ p.u_hat))
        return 0.5 * p.P0 * p.f_hat[free], -0.5 * p.v0   # v = f̂ᵀ u, P = λ

    def satisfied(self, p, scale):
        return abs(self.residual(p)) <= 1e-6 * self.tau


@dataclass
class OpeningControl(LinearConstraint):
    """c · Δu = τ: indirect displacement control (de Borst 1987) of an opening, e.g. the relative displacement
    across a notch or a weak zone, ``c`` = +1 on one side's DOFs and −1 on the other's (over all DOFs; the
    prescribed ones move with Δλ û). An opening grows monotonically through snap-back."""

    tau: float
    weights: np.ndarray = None
    name = "opening"

    def __post_init__(self):
        super().__post_init__()
        if self.weights is not None:
            self.weights = check_finite("weights", self.weights)

    def residual(self, p):
        return float(self.weights @ p.du) - self.tau

    def gradient(self, p):
        return self.weights[p.free], float(self.weights @ p.u_hat)

    def satisfied(self, p, scale):     # floor: the round-off of c·u, or a cut-back τ could never be met
        return abs(self.residual(p)) <= 1e-10 * abs(self.tau) + 1e-14 * float(np.abs(self.weights) @ np.abs(p.u))


NO_REAL_ROOT = "arc length: no real root"
"""The reason :class:`ArcLength` gives when its constraint has no solution (recognised by :func:`_better_method`)."""


@dataclass
class ArcLength:
    """Crisfield's cylindrical arc length ``|Δu|² = Δl²`` (mm²) over all DOFs; the root of the quadratic that keeps
    the direction of the previous increment is taken."""

    tau: float      # Δl (mm)
    name = "arc length"

    def __post_init__(self):
        check_number_fields(self)

    def residual(self, p):
        return increment_length(p.du[p.free], p.dlam, p.u_hat) - self.tau

    def _cosine(self, du_free, dlam, p):
        if p.previous is None:
            return dlam
        prev_u, prev_lam = p.previous
        return float(du_free @ prev_u[p.free]) + dlam * prev_lam * float(p.u_hat @ p.u_hat)

    def correction(self, p, du_R, du_q):
        base = p.du[p.free] + du_R
        uu = float(p.u_hat @ p.u_hat)
        a1 = float(du_q @ du_q) + uu
        a2 = 2.0 * float(base @ du_q) + 2.0 * p.dlam * uu
        a3 = float(base @ base) + p.dlam**2 * uu - self.tau**2
        disc = a2**2 - 4.0 * a1 * a3
        if disc < 0.0 or a1 == 0.0:
            raise NewtonFailure(f"{NO_REAL_ROOT} (the step is too long for the curvature of the path)", [])
        roots = [(-a2 + sign * np.sqrt(disc)) / (2.0 * a1) for sign in (1.0, -1.0)]
        return max(roots, key=lambda d: self._cosine(base + d * du_q, p.dlam + d, p))

    def predictor(self, p, du_q):
        dlam = self.tau / increment_length(du_q, 1.0, p.u_hat)
        return dlam if self._cosine(dlam * du_q, dlam, p) >= 0.0 else -dlam

    def satisfied(self, p, scale):
        return abs(self.residual(p)) <= 1e-8 * self.tau


#: The constraints by their ``name`` (a resumed run rebuilds its constraint from the name saved in the checkpoint).
CONSTRAINTS = {kind.name: kind for kind in (LoadFactorControl, DissipationControl, ArcLength, OpeningControl)}
#: The ``constraint`` column of a path-followed run's curves (4: the damage dissipation of a monolithic Model I
#: step, :class:`abrakit.damage.model_one_path.DamageControl`).
CONSTRAINT_CODES = {"load factor": 0, "dissipation": 1, "arc length": 2, "opening": 3, "damage": 4}


@dataclass(frozen=True)
class PathControl:
    """Steps of a path-following run.

    ``initial``/``maximum``/``minimum``: load-factor increments under load control; ``switch``: switch to
    dissipation control once a step releases more than this fraction of its external work;
    ``dissipation``: the dissipation target (N mm; ``None``: 1 % of the external work done up to the switch);
    ``arc_length``: first Δl (mm; ``None``: the length of the first load-controlled increment);
    ``target_iterations``: the constraint's target scales by √(target/iterations) after each step (at most ×2);
    ``cutback``: factor on a failed step; ``min_ratio``/``max_ratio``: smallest and largest target of a
    dissipation, opening or arc-length constraint relative to its first one (``max_ratio = 1``: equal energy or
    length per step, points evenly spread over the softening);
    ``max_steps``: a bound on the number of steps.
    """

    initial: float = 0.05
    maximum: float = 0.1
    minimum: float = 1e-6
    switch: float = 1e-3
    dissipation: float | None = None
    arc_length: float | None = None
    target_iterations: int = 5
    cutback: float = 0.25
    min_ratio: float = 1e-6
    max_ratio: float = 1.0
    max_steps: int = 2000

    def __post_init__(self):
        check_number_fields(self)
        check_range("initial", self.initial, 0.0, None, low_open=True)
        check_range("maximum", self.maximum, self.initial, None)
        check_range("minimum", self.minimum, 0.0, self.initial, low_open=True)
        check_positive("switch", self.switch)
        check_range("cutback", self.cutback, 0.0, 1.0, low_open=True, high_open=True)
        check_range("target_iterations", self.target_iterations, 1, None)
        check_range("max_steps", self.max_steps, 1, None)


def _better_method(constraint, reason: str) -> str:
    """The advice a failed arc-length run ends with. At a non-smooth limit point (a softening point's loading flag
    alternates between iterations, the path has a kink) cutting the arc cannot help: the arc-length equation has no
    real root however short the arc (the snap-back bar ``SofteningBar(37)``), or Newton diverges at a residual of
    round-off size (``SofteningBar(500, eps_0=1e-4, eps_f=2e-3)``, f_t/E = 1e-4, stops at F = f_t). Either way the
    constraints that pass such peaks are named."""
    if not isinstance(constraint, ArcLength):
        return ""
    if NO_REAL_ROOT in reason:
        return ("; arc length cannot pass this peak (a kink of the path: cutting the arc does not help): follow "
                "it with method='dissipation' or with method='opening' and opening=(dofs, dofs) across the band")
    return ("; arc length could not continue however short the arc: at the peak of a softening structure (a kink "
            "of the path) follow it with method='dissipation' or with method='opening' and opening=(dofs, dofs) "
            "across the band")


class PathFollowingSolver(Solver):
    """:class:`~abrakit.fem.Solver` with the load factor as an unknown (see the module docstring).

    ``method``: ``"dissipation"`` (default; load control until the structure softens, then dissipation control),
    ``"arc-length"`` (Crisfield's cylindrical arc length from the first step on) or ``"opening"`` (the opening
    ``c · Δu`` from the first step on). ``opening`` = (DOFs on one side, DOFs on the other) of a notch or weak
    zone: their mean relative displacement is the opening control's quantity, and the constraint that passes a
    limit point where load control fails (arc length without it). Other arguments as for
    :class:`~abrakit.fem.Solver`; the load is *either* prescribed displacements linear in λ *or* an external force
    λ f̂ (``external_force`` must then be linear in λ as well).
    """

    def __init__(self, *args, method: str = "dissipation", path: PathControl | None = None, opening=None,
                 **kwargs):
        super().__init__(*args, **kwargs)
        self.method = check_option("method", method, METHODS)
        self.opening = None
        if opening is not None:
            plus, minus = (np.asarray(d, dtype=np.int64) for d in opening)
            if plus.size == 0 or minus.size == 0:
                raise ValueError("opening must be (dofs on one side, dofs on the other), both non-empty")
            self.opening = np.zeros(self.kin.ndof)
            self.opening[plus] += 1.0 / plus.size
            self.opening[minus] -= 1.0 / minus.size
        if method == "opening" and self.opening is None:
            raise ValueError("method='opening' needs opening=(dofs_plus, dofs_minus)")
        self.path = path or PathControl()
        ndof, cons = self.kin.ndof, self.constraints
        zero = np.zeros(ndof)
        self.u_D0 = cons.apply(zero, 0.0)
        self.u_hat = cons.apply(zero, 1.0) - self.u_D0
        if not np.allclose(cons.apply(zero, 0.5), self.u_D0 + 0.5 * self.u_hat, rtol=1e-12, atol=1e-300):
            raise ValueError("path following needs prescribed displacements linear in the load factor")
        f0 = np.zeros(ndof) if self.external_force is None else np.asarray(self.external_force(0.0), float)
        f1 = np.zeros(ndof) if self.external_force is None else np.asarray(self.external_force(1.0), float)
        if np.any(f0):
            raise ValueError("path following needs an external force proportional to the load factor (f(0) = 0)")
        self.f_hat = f1
        if np.any(self.u_hat) == np.any(self.f_hat):
            raise ValueError("path following needs one load: prescribed displacements proportional to the load "
                             "factor or an external force, not both and not neither")

    # ---- the work-conjugate load pair (v, P) ------------------------------------------------------------------
    def load_pair(self, u: np.ndarray, lam: float, f_int: np.ndarray) -> tuple[float, float]:
        """(v, P): (λ, û_Dᵀ f_int) under prescribed displacement, (f̂ᵀ u, λ) under an external force."""
        if np.any(self.u_hat):
            return lam, float(self.u_hat @ f_int)
        return float(self.f_hat @ u), lam

    def _at(self, u_free_part, lam, template):
        u = template.copy()
        u[self.constraints.free] = u_free_part
        prescribed = self.constraints.prescribed
        u[prescribed] = self.u_D0[prescribed] + lam * self.u_hat[prescribed]
        return u

    # ---- one constrained step ---------------------------------------------------------------------------------
    def constrained_newton(self, constraint, u0, lam0, state_old, f_int0, step: int, start, previous=None,
                           guess=None) -> tuple:
        """Newton iterations of the bordered system from the converged (u0, λ0); ``start`` = (response, hook
        tangents) of the converged iterate, whose consistent tangent gives the predictor (the tangent of the new
        state at the same strain would be the secant one of an unloading point). ``guess`` = (u, λ): start the
        iterations there instead of at the predictor (a staggered scheme re-solving the same step). Returns
        ``(u, λ, response, f_int, extra_K, iterations, residuals)`` or raises :class:`NewtonFailure`."""
        opts, free = self.newton_options, self.constraints.free
        v0, P0 = self.load_pair(u0, lam0, f_int0)
        residuals: list[float] = []
        if guess is None:
            K, K_II = self.tangent(*start, u0)
            point = PathPoint(u0, lam0, v0, P0, u0, lam0, v0, P0, K, self.u_hat, self.f_hat, free, previous)
            du, dlam = self._bordered(constraint, point, K_II, None, residuals)
            lam = lam0 + dlam
            u = self._at(u0[free] + du, lam, u0)
        else:
            u, lam = guess[0].copy(), float(guess[1])
        for k in range(1, opts.max_iterations + 1):
            ctx = StepContext(step, lam, lam - lam0, lam * self.duration, (lam - lam0) * self.duration, k, u, u0,
                              state_old, f_int0)
            try:
                response, residual, f_int, scale, extra_K = self.evaluate(u, state_old, ctx)
            except (ArithmeticError, np.linalg.LinAlgError) as exc:
                raise NewtonFailure(f"material update failed: {exc}", residuals) from exc
            norm = float(np.max(np.abs(residual[free]), initial=0.0))
            if not (np.isfinite(norm) and np.all(np.isfinite(response.stress))):
                raise NewtonFailure("non-finite residual or stress", residuals)
            residuals.append(norm)
            v, P = self.load_pair(u, lam, f_int)
            point = PathPoint(u0, lam0, v0, P0, u, lam, v, P, None, self.u_hat, self.f_hat, free, previous)
            tol = opts.residual_tol * scale + opts.absolute_force
            if norm <= tol and constraint.satisfied(point, scale):
                return u, lam, response, f_int, extra_K, k, residuals
            if k >= opts.divergence_check_after and norm > tol and min(residuals[:-2]) < min(residuals[-2:]):
                raise NewtonFailure(f"diverging (residual {norm:.3e} N after {k} iterations)", residuals)
            try:
                point.K, K_II = self.tangent(response, extra_K, u)
            except LinearSolveError as exc:
                raise NewtonFailure(str(exc), residuals) from exc
            du, dlam = self._bordered(constraint, point, K_II, residual[free], residuals)
            lam += dlam
            u = self._at(u[free] + du, lam, u)
        raise NewtonFailure(f"not converged in {opts.max_iterations} iterations", residuals)

    def _bordered(self, constraint, point: PathPoint, K_II, residual, residuals) -> tuple[np.ndarray, float]:
        """(δu_I, δλ) from R and the linearised constraint: by bordering (two solves with K_II, one factorisation),
        or, where K_II is singular (e.g. a vertical tangent of the force–displacement curve), from the augmented
        matrix [[K_II, −q], [a, b]] of a linear constraint, which stays regular there. ``residual=None``: the
        predictor from the converged point (R = 0)."""
        free = self.constraints.free
        q = self.f_hat[free] - (point.K @ self.u_hat)[free]
        R = np.zeros(free.size) if residual is None else residual
        try:
            if residual is None:
                du_R, du_q = np.zeros(free.size), self.solve_linear(K_II, q, new_step=True)
                dlam = constraint.predictor(point, du_q)
            else:
                du_R, du_q = self.solve_linear(K_II, np.column_stack([-R, q]), new_step=False).T
                dlam = constraint.correction(point, du_R, du_q)
            return du_R + dlam * du_q, dlam
        except LinearSolveError as exc:
            if not isinstance(constraint, LinearConstraint):
                raise NewtonFailure(str(exc), residuals) from exc
        a, b = constraint.gradient(point)
        a = np.zeros(free.size) if a is None else a
        augmented = sp.bmat([[K_II, sp.csr_matrix(-q[:, None])], [sp.csr_matrix(a[None, :]), sp.csr_matrix([[b]])]],
                            format="csc")
        rhs = np.append(-R, -constraint.residual(point))
        x = spla.spsolve(augmented, rhs)
        if not (np.all(np.isfinite(x)) and np.linalg.norm(augmented @ x - rhs) <= 1e-8 * np.linalg.norm(rhs)):
            raise NewtonFailure("singular tangent and singular augmented system", residuals)
        return x[:-1], float(x[-1])

    # ---- the run ----------------------------------------------------------------------------------------------
    def run(self, *, end: float = 1.0, stop_force: float = 0.0, output: str | Path | None = None,
            vtu_every: int = 1, progress: bool = True,
            on_step: Callable[[SolveResult], None] | None = None, checkpoint_every: int = 10,
            resume: bool = False) -> SolveResult:
        """Follow the path from λ = 0 until λ reaches ``end`` or, after the peak, the load-pair force |P| falls to
        ``stop_force`` times its peak (e.g. 0.01: until the specimen carries 1 % of its peak load), or
        ``path.max_steps`` steps. Curves gain the columns ``constraint`` (:data:`CONSTRAINT_CODES`: 0 load factor,
        1 dissipation, 2 arc length, 3 opening, 4 damage), ``v``, ``P`` and ``released`` (G of the step).
        ``output``, ``checkpoint_every`` and ``resume`` as in :meth:`Solver.run`: a resumed run continues with the
        constraint, targets and counters of its checkpoint and gives the curve of a run never stopped."""
        check_range("stop_force", stop_force, 0.0, 1.0, high_open=True)
        check_range("checkpoint_every", checkpoint_every, 0, None)
        recorder = RunRecorder(self, output, vtu_every, ("constraint", "v", "P", "released"),
                               checkpoint_every=int(checkpoint_every))
        saved = recorder.resume() if resume else None
        arc = self.method == "arc-length" and self.path.arc_length
        first = ArcLength(self.path.arc_length) if arc else LoadFactorControl(self.path.initial)
        walk, first_step = _Walk.start(self, recorder, saved, first)
        bar = progress_bar(disable=not progress, unit="step", desc="path following")   # the end is not known
        step = first_step - 1
        finished = saved is not None and saved["meta"]["control"].get("finished", False)
        try:
            for step in range(first_step, self.path.max_steps + 1 if not finished else first_step):
                constraint = walk.constraint
                taken = self._path_step(walk, step, end, recorder)
                if taken is None:                         # a new or cut-back constraint: try the step again
                    continue
                iterations, residuals, released, softening = taken
                recorder.record(step, walk.lam, walk.u, walk.f_int, walk.response, walk.state, iterations, residuals,
                                constraint=CONSTRAINT_CODES[constraint.name], v=walk.v, P=walk.P, released=released)
                bar.update(1)
                if on_step is not None:
                    on_step(recorder.result(walk.cutbacks))
                if walk.lam >= end - 1e-12 * max(1.0, abs(end)) or (stop_force > 0.0 and walk.peak > 0.0
                                                                    and abs(walk.P) <= stop_force * walk.peak):
                    break
                walk.constraint = self._next_constraint(constraint, iterations, softening, walk.work, walk.previous,
                                                        walk.firsts.get(type(constraint)))
                walk.firsts.setdefault(type(walk.constraint), walk.constraint.tau)
                if recorder.due(step):
                    walk.checkpoint(recorder, step)
            else:
                if not finished:
                    warnings.warn(f"path following stopped after max_steps = {self.path.max_steps} steps at "
                                  f"λ = {walk.lam:.6g}, |P| = {abs(walk.P):.4g} (peak {walk.peak:.4g}), before "
                                  "reaching end or stop_force", RuntimeWarning, stacklevel=2)
            if recorder.writer is not None and not finished:
                walk.checkpoint(recorder, step, finished=True)            # the end: a rerun returns at once
        finally:
            bar.close()
            recorder.close()
        return recorder.result(walk.cutbacks)

    def _path_step(self, walk: _Walk, step: int, end: float, recorder: RunRecorder):
        """Step ``step`` from the converged point ``walk`` under ``walk.constraint`` (a load factor bounded by
        ``end``): ``(iterations, residuals, released, softening)`` with ``walk`` advanced, or None with the
        constraint changed (a load-controlled step failed or softened: :meth:`_limit_point`; nothing to release:
        load control) or cut back (:meth:`_cut_back`), for the step to be tried again."""
        constraint = walk.constraint
        if isinstance(constraint, LoadFactorControl):
            constraint.tau = min(constraint.tau, end - walk.lam) if constraint.tau > 0 else constraint.tau
        try:
            u, lam, response, f_int, extra_K, iterations, residuals = self.constrained_newton(
                constraint, walk.u, walk.lam, walk.state, walk.f_int, step, (walk.response, walk.extra_K),
                walk.previous)
        except ConstraintSingular:
            if isinstance(constraint, LoadFactorControl):
                raise
            walk.constraint = LoadFactorControl(walk.last_dlam)        # nothing to release: back to load control
            return None
        except NewtonFailure as failure:
            if isinstance(constraint, LoadFactorControl) and walk.previous is not None:
                walk.constraint = self._limit_point(walk.previous)          # load control fails: pass the peak
            else:
                self._cut_back(walk, failure, step, recorder)
            return None
        v, P = self.load_pair(u, lam, f_int)
        released = 0.5 * (walk.P * (v - walk.v) - walk.v * (P - walk.P))
        step_work = 0.5 * (walk.P + P) * (v - walk.v)
        softening = self._softened(released, step_work)
        if isinstance(constraint, LoadFactorControl) and walk.previous is not None and softening:
            walk.constraint = self._limit_point(walk.previous)     # a load-controlled step that softened may have
            return None                                           # jumped a snap-back: redo it path-following
        if isinstance(constraint, LoadFactorControl):
            walk.last_dlam = constraint.tau
        walk.accept(u, lam, response, f_int, extra_K, v, P, step_work)
        return iterations, residuals, released, softening

    def _cut_back(self, walk: _Walk, failure: NewtonFailure, step: int, recorder: RunRecorder) -> None:
        """Cut the failed step's target back by ``path.cutback``; below the smallest target (``path.min_ratio`` of
        the constraint's first one, ``path.minimum`` for a load factor) raise :class:`StepFailed` with the result so
        far and a checkpoint of the last converged step."""
        ctrl, constraint = self.path, walk.constraint
        walk.cutbacks += 1
        constraint.tau *= ctrl.cutback
        reference = walk.firsts.get(type(constraint), ctrl.initial)
        if abs(constraint.tau) < max(ctrl.min_ratio * abs(reference), 1e-300) or (
                isinstance(constraint, LoadFactorControl) and abs(constraint.tau) < ctrl.minimum):
            result = recorder.result(walk.cutbacks)
            raise StepFailed(
                f"path following from λ={walk.lam:.6g} failed under {constraint.name} control: "
                f"{failure.reason}{_better_method(constraint, failure.reason)}", load_factor=walk.lam, u=walk.u,
                state=walk.state, reason=failure.reason, result=result,
                checkpoint=walk.checkpoint(recorder, step - 1)) from failure

    def _softened(self, released: float, step_work: float) -> bool:
        """Whether a step softened the structure: it released more than ``path.switch`` times its work (a
        load-controlled step that did is redone under path following, see :meth:`run`)."""
        return released > self.path.switch * max(abs(step_work), 1e-300)

    def _constraint(self, name: str, tau: float):
        """The constraint called ``name`` with target ``tau`` (for a resumed run)."""
        kind = CONSTRAINTS[name]
        return kind(tau, self.opening) if kind is OpeningControl else kind(tau)

    def _length(self, increment) -> float:
        """:func:`increment_length` of an increment (Δu over all DOFs, Δλ)."""
        du, dlam = increment
        return increment_length(du[self.constraints.free], dlam, self.u_hat)

    def _limit_point(self, previous):
        """The constraint that passes a limit point where load control failed: the opening (if given) or the
        arc length, with a quarter of the last increment."""
        if self.opening is not None:
            return OpeningControl(self.path.cutback * abs(float(self.opening @ previous[0])), self.opening)
        return ArcLength(self.path.cutback * self._length(previous))

    def _next_constraint(self, constraint, iterations: int, softening: bool, work: float, previous, first_target):
        """The constraint of the next step: the target adapted to the iteration count (√(target/iterations), at
        most ×2; at most ``max_ratio`` times the constraint's first target); under ``method="dissipation"``
        a switch to dissipation control once a step released more than ``switch`` times its work (``softening``)."""
        ctrl = self.path
        scale = min(2.0, np.sqrt(ctrl.target_iterations / max(iterations, 1)))
        if self.method == "dissipation" and softening and not isinstance(constraint, DissipationControl):
            return DissipationControl(ctrl.dissipation or 0.01 * work)
        if isinstance(constraint, LoadFactorControl):
            if self.method == "arc-length":
                return ArcLength(ctrl.arc_length or self._length(previous))
            if self.method == "opening":
                return OpeningControl(float(self.opening @ previous[0]), self.opening)
            return LoadFactorControl(float(np.clip(constraint.tau * scale, ctrl.minimum, ctrl.maximum)))
        tau = constraint.tau * scale
        if first_target:
            tau = min(tau, ctrl.max_ratio * first_target)
        return replace(constraint, tau=tau)
