"""Quasi-static Newton–Raphson solver with automatic load stepping, Eq. (4.37)–(4.41).

In every load step lambda_m -> lambda_{m+1} = lambda_m + dlambda the residual

    R(u) = f_int(u) - f_ext(lambda) + R_extra(u)              (Eq. 4.37, plus optional hook terms)

is driven to zero on the free DOFs by Newton iterations u <- u + du, K_II du_I = -R_I (Eq. 4.38–4.41), where the
stresses and the algorithmic tangent come from ``material.update(state_m, eps(u), dt, **loading)`` evaluated from
the *last converged* state, so a rejected step is retried from it unchanged.

A step converges when both ||R_I||_inf <= residual_tol * F_ref and ||du||_inf <= increment_tol * ||u - u_m||_inf
(the increment test is waived once ||R_I||_inf <= exact_tol * F_ref; F_ref is the largest internal, external or
hook force). Where the residual has converged but the last correction was not small, a chord step with the factors
kept from the step's last tangent (``NewtonOptions(chord_check=True)``, the default) tests the increment without
a new tangent and factorisation. A step that diverges (non-finite values, residual growth after
``divergence_check_after`` iterations, too many iterations, singular tangent) is retried with dlambda * cutback; after
``easy_steps`` consecutive steps needing at most ``easy_iterations`` iterations dlambda grows by ``growth``
(the defaults follow Abaqus/Standard's time incrementation). If dlambda falls below ``minimum``, :class:`StepFailed`
is raised with the last converged state (also saved to ``<output>/last_converged.npz``, which a run with
``output`` also writes every ``checkpoint_every`` steps; ``run(..., resume=True)`` continues from it).

The Newton driver takes its pieces as arguments of :class:`Solver`: ``loading(ctx) -> dict`` supplies extra keyword
arguments to ``material.update`` (e.g. the external work of a rate limit); every ``extra_terms`` item
``term(u, ctx) -> (R_extra, K_extra)`` adds a residual vector and a sparse tangent (either may be ``None``), e.g.
penalty contact; ``linear_solver`` solves K_II du_I = −R_I; ``line_search`` (a :class:`LineSearch`) damps the
corrections, u ← u + s du; ``diagnose(reason, iterate) -> str`` names the cause of a failed step from the last
:class:`Iterate`; :meth:`Solver.run` takes ``on_step`` (called after every converged step), ``output`` with
``checkpoint_every``/``resume`` (:mod:`abrakit.fem.recorder`) or a caller's own ``continuation``.

Example::

    solver = Solver(basis, material, bcs, extra_terms=[contact], line_search=LineSearch())
    result = solver.run(end=1.0, on_step=contact.on_step)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import scipy.sparse as sp

from ..io import progress_bar
from ..materials.base import Material
from ..validation import all_finite, check_instance, check_number_fields, check_positive, check_range
from .assembly import Assembler
from .boundary import Constraints, Dirichlet
from .kinematics import FBarKinematics, Kinematics
from .linsolve import DirectSolver, LinearSolveError, make_linear_solver, rigid_body_modes
from .recorder import RunRecorder, SolveResult
from .tangent_reuse import ElementTangentReuse


@dataclass(frozen=True)
class StepControl:
    """Load-factor incrementation. Defaults after Abaqus/Standard: cut back by 1/4 on divergence, grow by 1.5
    after two consecutive increments converging within 4 iterations, minimum 1e-5 of the load path.

    Predictor of a step: ``extrapolate`` the last converged increment where there is one; otherwise (the first
    step, or ``extrapolate=False``) ``lift`` the prescribed increment through the linear system (FElupe's and
    FEniCS' practice) rather than putting it into the start point, where it strains only the boundary elements."""

    initial: float = 0.1
    minimum: float = 1e-5
    maximum: float = 0.1
    cutback: float = 0.25
    growth: float = 1.5
    easy_iterations: int = 4
    easy_steps: int = 2
    extrapolate: bool = True
    lift: bool = True

    def __post_init__(self):
        check_number_fields(self)
        check_range("minimum", self.minimum, 0.0, None, low_open=True)
        check_range("maximum", self.maximum, self.minimum, None)
        check_range("initial", self.initial, self.minimum, self.maximum)
        check_range("cutback", self.cutback, 0.0, 1.0, low_open=True, high_open=True)
        check_range("growth", self.growth, 1.0, None)
        check_range("easy_steps", self.easy_steps, 1, None)


@dataclass(frozen=True)
class NewtonOptions:
    """Convergence test on the residual and on the correction (see module docstring)."""

    residual_tol: float = 1e-6
    increment_tol: float = 1e-4
    exact_tol: float = 1e-10
    absolute_force: float = 1e-12
    max_iterations: int = 12
    divergence_check_after: int = 4
    stabilization: float = 1e-9   # floor of the tangent diagonal, relative to its largest entry
    chord_check: bool = True      # a converged residual's increment test by a chord step (see Solver.newton)
    tangent_reuse: float | None = None   # F-bar: keep element tangents where F moved less (ElementTangentReuse)

    def __post_init__(self):
        check_number_fields(self)
        if self.tangent_reuse is not None:
            check_positive("tangent_reuse", self.tangent_reuse, allow_zero=True)
        for name in ("residual_tol", "increment_tol", "exact_tol", "absolute_force"):
            check_positive(name, getattr(self, name))
        check_range("max_iterations", self.max_iterations, 1, None)
        if not isinstance(self.chord_check, bool):
            raise TypeError(f"chord_check must be True or False, got {self.chord_check!r}")
        check_positive("stabilization", self.stabilization, allow_zero=True)


@dataclass(frozen=True)
class StepContext:
    """What the hooks see: the step being attempted and the current Newton iterate."""

    step: int
    load_factor: float
    delta: float
    time: float
    dt: float
    iteration: int
    u: np.ndarray
    u_old: np.ndarray
    state_old: dict
    f_int_old: np.ndarray


@dataclass
class NewtonResult:
    u: np.ndarray
    response: Any
    f_int: np.ndarray
    iterations: int
    residuals: list[float]


class NewtonFailure(RuntimeError):
    def __init__(self, reason: str, residuals: Sequence[float]):
        super().__init__(reason)
        self.reason = reason
        self.residuals = list(residuals)


class Iterate(NamedTuple):
    """The last evaluated Newton iterate of a step, for a ``diagnose`` callback: ``u``, the residual R(u)
    ``(ndof,)``, the step's :class:`StepContext` and the free DOFs."""

    u: np.ndarray
    residual: np.ndarray
    ctx: StepContext
    free: np.ndarray


@dataclass(frozen=True)
class LineSearch:
    """Backtracking line search on the Euclidean norm of the free residual.

    A Newton correction du is taken as s du with the first s = 1, 1/2, 1/4, ... (at most ``max_backtracks``
    halvings) for which ||R_I(u + s du)||_2 <= (1 − 10⁻⁴ s) ||R_I(u)||_2 (Armijo's sufficient decrease; a full
    step may also keep the residual up to ``growth_allowed`` times); if none does, the s with the smallest
    residual. Penalty contact (open/closed, stick/slip) and plasticity (elastic/plastic) make R only piecewise
    smooth: a full step can jump across a kink, and Newton then cycles between two sets of active points. The
    evaluation at the accepted point is returned, and :meth:`Solver.newton` reuses it as the next iteration's.
    """

    max_backtracks: int = 4
    growth_allowed: float = 1.0

    def __post_init__(self):
        check_number_fields(self)
        check_range("max_backtracks", self.max_backtracks, 0, None)
        check_range("growth_allowed", self.growth_allowed, 1.0, None)

    def __call__(self, evaluate: Callable, u: np.ndarray, du: np.ndarray, free: np.ndarray,
                 residual: np.ndarray) -> tuple[float, np.ndarray, tuple | None]:
        """``(s, u + s du, evaluation there or None)`` for the correction ``du`` on the ``free`` DOFs of ``u``;
        ``evaluate(trial)`` returns a :meth:`Solver.evaluate` tuple, whose second entry is the residual."""
        norm0 = float(np.linalg.norm(residual[free]))
        best = None
        s = 1.0
        for _ in range(self.max_backtracks + 1):
            trial = u.copy()
            trial[free] += s * du
            try:
                with np.errstate(all="ignore"):
                    evaluation = evaluate(trial)
                norm = float(np.linalg.norm(evaluation[1][free]))
            except (ArithmeticError, ValueError, np.linalg.LinAlgError):
                norm, evaluation = np.inf, None
            if not np.isfinite(norm):
                norm = np.inf
            if best is None or norm < best[0]:
                best = (norm, s, trial, evaluation)
            if norm <= (self.growth_allowed if s == 1.0 else 1.0 - 1e-4 * s) * norm0:
                break
            s *= 0.5
        _, s, trial, evaluation = best
        return s, trial, evaluation


class StepFailed(RuntimeError):
    """The load step could not be completed with dlambda >= minimum. Holds the last converged state."""

    def __init__(self, message: str, *, load_factor: float, u, state, reason: str, result: SolveResult,
                 checkpoint: Path | None):
        super().__init__(message)
        self.load_factor = load_factor
        self.u = u
        self.state = state
        self.reason = reason
        self.result = result
        self.checkpoint = checkpoint


class Solver:
    """Quasi-static nonlinear FE problem: kinematics + material + boundary conditions + hooks.

    Parameters
    ----------
    basis : scikit-fem vector ``CellBasis`` or :class:`Kinematics`.
    material : object with ``initial_state(shape)`` and ``update(state, eps, dt, **loading)`` (Mandel).
    dirichlet : prescribed displacements as functions of the load factor (:class:`Dirichlet`).
    external_force : ``f_ext(load_factor) -> (ndof,)`` (N), e.g. ``lambda lam: lam * surface_load(...)``.
    loading : ``loading(ctx: StepContext) -> dict`` of extra keyword arguments to ``material.update``.
    extra_terms : callables ``term(u, ctx) -> (R_extra | None, K_extra | None)`` added to residual and tangent.
    monitors : ``{name: dofs}`` whose summed reaction/internal force and mean displacement are recorded
        (every named :class:`Dirichlet` is monitored automatically).
    linear_solver : ``"auto"``, ``"direct"``, ``"amg"``, an object with ``solve(K, rhs, new_step)`` or
        a callable ``f(K, rhs)``.
    duration : time (s) of the whole load path (load factor 0 -> 1); ``dt = dlambda * duration``.
    bbar : use the B-bar operator (against volumetric locking) when ``basis`` is a scikit-fem basis.
    finite_strain : total-Lagrangian kinematics (:class:`~abrakit.fem.kinematics.TotalLagrangianKinematics`):
        the material then maps the deformation gradient F to P and ∂P/∂F (e.g.
        :class:`~abrakit.materials.LogStrainPlasticity`).
    line_search : a :class:`LineSearch` damping the Newton corrections, or ``None`` (full corrections).
    diagnose : ``diagnose(reason, iterate: Iterate | None) -> str``, appended in brackets to the reason of a
        failed Newton step (``iterate``: the step's last evaluated iterate, ``None`` before the first).
    """

    def __init__(self, basis, material: Material, dirichlet: Sequence[Dirichlet] = (), *,
                 external_force: Callable[[float], np.ndarray] | None = None,
                 loading: Callable[[StepContext], dict] | None = None,
                 extra_terms: Sequence[Callable] = (),
                 monitors: dict[str, np.ndarray] | None = None,
                 control: StepControl | None = None, newton: NewtonOptions | None = None,
                 linear_solver="auto", duration: float = 1.0, bbar: bool = False, finite_strain: bool = False,
                 line_search: LineSearch | None = None, diagnose: Callable[[str, Iterate | None], str] | None = None):
        self.kin = (basis if isinstance(basis, Kinematics)
                    else Kinematics.from_basis(basis, bbar=bbar, finite_strain=finite_strain))
        self.assembler = Assembler(self.kin)
        self.material = check_instance("material", material, Material)
        self.constraints = Constraints(dirichlet, self.kin.ndof)
        self.constraints.condense_pattern(self.assembler.indptr, self.assembler.indices)
        for name, hook in (("external_force", external_force), ("loading", loading)):
            if hook is not None and not callable(hook):
                raise TypeError(f"{name} must be a function of the load factor (or context) or None, got {hook!r}")
        if diagnose is not None and not callable(diagnose):
            raise TypeError(f"diagnose must be a function diagnose(reason, iterate) -> str or None, got {diagnose!r}")
        if line_search is not None and not isinstance(line_search, LineSearch):
            raise TypeError(f"line_search must be a LineSearch or None, got {line_search!r}")
        self.line_search = line_search
        self.diagnose = diagnose
        self.external_force = external_force
        self.loading = loading
        self.extra_terms = list(extra_terms)
        self.control = check_instance("control", control, StepControl, optional=True) or StepControl()
        self.newton_options = check_instance("newton", newton, NewtonOptions, optional=True) or NewtonOptions()
        self.duration = check_positive("duration", duration)
        self.monitors = {c.name: c.dofs for c in self.constraints.conditions if c.name}
        self.monitors.update({k: np.asarray(v, dtype=np.int64) for k, v in (monitors or {}).items()})
        basis_ = self.kin.basis
        free = self.constraints.free
        null_space = None
        if hasattr(basis_, "doflocs"):
            component = np.zeros(self.kin.ndof, dtype=int)
            component[self.kin.element_dofs] = np.arange(self.kin.nbf) % self.kin.dim
            null_space = rigid_body_modes(basis_.doflocs[:, free], component[free])
        self.linear_solver = make_linear_solver(linear_solver, self.kin.dim, free.size, null_space)

    # ---- one evaluation of Eq. (4.37) -------------------------------------------------------------------------
    def evaluate(self, u, state_old, ctx: StepContext):
        """Material update at all quadrature points and the residual of Eq. (4.37) with the hook terms.

        Returns ``(response, R, f_int, F_ref, K_extra_list)``; ``F_ref`` is the largest nodal force (N).
        """
        kwargs = self.loading(ctx) if self.loading is not None else {}
        eps = self.assembler.strain(u)
        with np.errstate(all="ignore"):
            response = self.material.update(state_old, eps, ctx.dt, **kwargs)
            f_int = self.assembler.internal_force(response.stress, u)
        residual = f_int.copy()
        scale = np.max(np.abs(f_int), initial=0.0)
        if self.external_force is not None:
            f_ext = np.asarray(self.external_force(ctx.load_factor), dtype=float)
            residual -= f_ext
            scale = max(scale, np.max(np.abs(f_ext), initial=0.0))
        extra_K = []
        for term in self.extra_terms:
            r_extra, K_extra = term(u, ctx)
            if r_extra is not None:
                residual += r_extra
                scale = max(scale, np.max(np.abs(r_extra), initial=0.0))
            if K_extra is not None:
                extra_K.append(K_extra)
        return response, residual, f_int, scale, extra_K

    def _correction(self, response, extra_K, residual, new_step: bool, lift: np.ndarray | None = None,
                    u: np.ndarray | None = None) -> np.ndarray:
        """du_I from K_II du_I = −R_I, or with ``lift`` (the prescribed increment Δu_D, zero on free DOFs) from
        K_II du_I = −R_I − K_ID Δu_D: the Dirichlet increment entering through the linear system."""
        K, K_II = self.tangent(response, extra_K, u, full=lift is not None)
        if lift is not None:
            residual = residual + K @ lift
        return self.solve_linear(K_II, -residual[self.constraints.free], new_step)

    def tangent(self, response, extra_K, u: np.ndarray | None = None,
                full: bool = True) -> tuple[sp.csr_matrix | None, sp.csr_matrix]:
        """The global tangent K of Eq. (4.40) with the hook terms, and its free block K_II (diagonal floored).

        ``full=False``: K itself is not built (None) where K_II can be taken from the values directly, as a
        Newton correction without a prescribed increment needs only K_II."""
        cons = self.constraints
        data = self._tangent_values(response, u)
        # extra terms inside the mesh's pattern (contact blocks on its nodes) keep the pattern, and with it the
        # linear solver's symbolic analysis; others fall back to a general sparse sum
        outside = [K for K in extra_K if not self.assembler.add_into(data, K)]
        if outside:
            K = sp.csr_matrix(self.assembler.matrix(data) + sum(outside))
            K_II = cons.condense(K, same_pattern=False)
            diag_pos = None
        else:
            K = self.assembler.matrix(data) if full else None
            K_II = cons.condense_values(data)
            diag_pos = cons.diagonal_positions
        if not all_finite(K_II.data):
            raise LinearSolveError("non-finite tangent")
        # a region without stiffness (e.g. fully damaged) must not make K_II singular: floor its diagonal
        diagonal = K_II.diagonal() if diag_pos is None else K_II.data[diag_pos]
        floor = self.newton_options.stabilization * np.max(np.abs(diagonal), initial=0.0)
        if floor > 0:
            if diag_pos is None:
                K_II = K_II + sp.diags(np.where(np.abs(diagonal) < floor, floor, 0.0))
            else:                                  # K_II's values are its own (condense_values gathers them)
                K_II.data[diag_pos] = np.where(np.abs(diagonal) < floor, floor, diagonal)
        return K, K_II

    def _tangent_values(self, response, u) -> np.ndarray:
        """The global tangent's values in the assembler's pattern; with ``NewtonOptions(tangent_reuse=tol)``
        on F-bar kinematics, element tangents are kept where F moved less than tol and nothing yields
        (:class:`~abrakit.fem.tangent_reuse.ElementTangentReuse`)."""
        tol = self.newton_options.tangent_reuse
        if tol is not None and isinstance(self.kin, FBarKinematics) and ElementTangentReuse.applies(response):
            reuse = getattr(self, "_reuse", None)
            if reuse is None or reuse.tolerance != tol:
                reuse = self._reuse = ElementTangentReuse(self.assembler, tol)
            return reuse.data(response, u)
        return self.assembler.tangent_data(response.tangent, u, response.stress)

    def solve_linear(self, K_II, rhs: np.ndarray, new_step: bool) -> np.ndarray:
        """x with K_II x = rhs for ``rhs`` ``(n,)`` or ``(n, k)`` (several right-hand sides, one factorisation
        with a direct solver)."""
        solver = self.linear_solver
        if rhs.ndim == 2 and not isinstance(solver, DirectSolver):
            return np.column_stack([self.solve_linear(K_II, column, new_step and j == 0)
                                    for j, column in enumerate(rhs.T)])
        if hasattr(solver, "solve"):
            return solver.solve(K_II, rhs, new_step=new_step)
        return np.asarray(solver(K_II, rhs))

    # ---- Newton iterations, Eq. (4.38)–(4.41) ----------------------------------------------------------------
    def newton(self, u_trial, state_old, ctx: StepContext, lift: np.ndarray | None = None) -> NewtonResult:
        """Iterate from ``u_trial`` (prescribed DOFs already at their new values) until converged.

        With ``lift`` (Δu_D: the prescribed increment, zero on free DOFs) ``u_trial`` is the start of the step
        (prescribed DOFs at their old values) and the first iteration solves K_II du_I = −R_I − K_ID Δu_D there:
        a purely elastic step is then exact after one iteration, and no boundary layer of elements takes the
        whole increment alone.

        With ``NewtonOptions(chord_check=True)`` an iterate whose residual has converged but whose last correction
        was not yet small takes a *chord* step, du_I = −K_old⁻¹ R_I with the factors of the step's last tangent
        (a linear solver with ``resolve``, e.g. :class:`~abrakit.fem.DirectSolver`), instead of assembling and
        factorising a new tangent only to confirm convergence. The chord step still moves u and its size is tested
        like a Newton correction's; if it is not small, the step goes on with full Newton corrections only.

        With a ``line_search`` every Newton correction (not the lifted predictor, not a chord step) is damped,
        u ← u + s du, and the search's evaluation at the accepted point is that of the next iteration. A failure
        (:class:`NewtonFailure`) carries ``diagnose``'s reading of the last iterate in its reason."""
        last: list[Iterate] = []
        try:
            return self._newton_iterations(np.array(u_trial, dtype=float), state_old, ctx, lift, last)
        except NewtonFailure as failure:
            if self.diagnose is not None:
                failure.reason = f"{failure.reason} [{self.diagnose(failure.reason, last[-1] if last else None)}]"
                failure.args = (failure.reason,)
            raise

    def _lifted_predictor(self, u, state_old, ctx: StepContext, lift: np.ndarray, last: list) -> np.ndarray:
        """du_I of K_II du_I = −R_I − K_ID Δu_D at the start of the step (see :meth:`newton`)."""
        try:
            response, residual, _, _, extra_K = self.evaluate(u, state_old, replace(ctx, iteration=0, u=u))
            last.append(Iterate(u.copy(), residual, ctx, self.constraints.free))
            return self._correction(response, extra_K, residual, new_step=True, lift=lift, u=u)
        except (ArithmeticError, np.linalg.LinAlgError, LinearSolveError) as exc:
            raise NewtonFailure(f"lifted predictor failed: {exc}", []) from exc

    def _newton_iterations(self, u, state_old, ctx: StepContext, lift, last: list) -> NewtonResult:
        opts = self.newton_options
        free = self.constraints.free
        residuals: list[float] = []
        increment = np.inf
        first = 0
        chord = False                                 # a chord step was taken (one per step at most)
        resolve = getattr(self.linear_solver, "resolve", None) if opts.chord_check else None
        searched = None                               # (u, evaluation) of the line search's accepted point
        if lift is not None:
            du = self._lifted_predictor(u, state_old, ctx, lift, last)
            # the residual at the old state (≈ 0 for a Dirichlet-driven step) is not part of the convergence history
            u[free] += du
            u += lift
            increment, first = np.max(np.abs(du), initial=0.0), 1
        for k in range(first, opts.max_iterations + 1):
            ctx_k = replace(ctx, iteration=k, u=u)
            try:
                if searched is not None and np.array_equal(searched[0], u):
                    evaluation = searched[1]
                else:
                    evaluation = self.evaluate(u, state_old, ctx_k)
            except (ArithmeticError, np.linalg.LinAlgError) as exc:  # e.g. a local iteration that broke down
                raise NewtonFailure(f"material update failed: {exc}", residuals) from exc
            response, residual, f_int, scale, extra_K = evaluation
            last.append(Iterate(u.copy(), residual, ctx_k, free))
            r_free = residual[free]
            norm = np.max(np.abs(r_free), initial=0.0)
            if not (np.isfinite(norm) and np.all(np.isfinite(response.stress))):
                raise NewtonFailure("non-finite residual or stress", residuals)
            residuals.append(float(norm))
            tol = opts.residual_tol * scale + opts.absolute_force
            step_size = np.max(np.abs((u - ctx.u_old)[free]), initial=0.0)
            small_correction = increment <= opts.increment_tol * step_size + 1e-300
            if norm <= tol and (k == first == 0 or small_correction
                                or norm <= opts.exact_tol * scale + opts.absolute_force):
                return NewtonResult(u, response, f_int, k, residuals)
            if k == opts.max_iterations:
                raise NewtonFailure(f"not converged in {k} iterations (residual {norm:.3e} N, tolerance "
                                    f"{tol:.3e} N)", residuals)
            if k >= opts.divergence_check_after and min(residuals[:-2]) < min(residuals[-2:]):
                raise NewtonFailure(f"diverging (residual {norm:.3e} N after {k} iterations)", residuals)
            take_chord = resolve is not None and norm <= tol and k > 0 and not chord
            chord = chord or take_chord
            try:
                du = resolve(-r_free) if take_chord else self._correction(response, extra_K, residual,
                                                                          new_step=(k == first), u=u)
            except LinearSolveError as exc:
                raise NewtonFailure(str(exc), residuals) from exc
            if self.line_search is not None and not take_chord:
                s, trial, at_trial = self.line_search(
                    lambda x, ctx_k=ctx_k: self.evaluate(x, state_old, replace(ctx_k, u=x)), u, du, free, residual)
                du = s * du
                searched = (trial, at_trial) if at_trial is not None else searched
            u[free] += du
            increment = np.max(np.abs(du), initial=0.0)
        raise AssertionError("unreachable")

    # ---- load stepping --------------------------------------------------------------------------------------
    def _start(self, start: float, u0, state0, continuation: dict | None) -> tuple[float, np.ndarray, dict]:
        """(load factor, u, state) a run starts from: a ``continuation``'s, else ``u0`` (default 0) with the
        prescribed values at ``start`` and ``state0`` (default the material's initial state)."""
        if continuation is not None:
            return continuation["load_factor"], continuation["u"], continuation["state"]
        kin = self.kin
        state = state0 if state0 is not None else self.material.initial_state((kin.nel, kin.nqp))
        return start, self.constraints.apply(np.zeros(kin.ndof) if u0 is None else u0, start), state

    def _predictor(self, u, u_prev, lam_new: float, delta: float, delta_prev) -> tuple[np.ndarray, np.ndarray | None]:
        """(u_trial, lift) of the step to ``lam_new`` (:class:`StepControl`): the last converged increment
        extrapolated, or the prescribed increment Δu_D lifted through the linear system from u_m, or neither."""
        ctrl, cons = self.control, self.constraints
        u_trial = cons.apply(u, lam_new)
        lift = None
        if ctrl.extrapolate and u_prev is not None:
            u_trial[cons.free] += (delta / delta_prev) * (u - u_prev)[cons.free]
        elif ctrl.lift and np.any(u_trial != u):          # prescribed values change in this step
            lift, u_trial = u_trial - u, u.copy()            # Δu_D (zero on free DOFs), start at u_m
        return u_trial, lift

    def run(self, *, end: float = 1.0, start: float = 0.0, u0: np.ndarray | None = None,
            state0: dict | None = None, output: str | Path | None = None, vtu_every: int = 1,
            progress: bool = True, on_step: Callable[[SolveResult], None] | None = None,
            checkpoint_every: int = 10, resume: bool = False, continuation: dict | None = None) -> SolveResult:
        """Follow the load path from ``start`` to ``end`` (load factors); returns the converged history.

        ``output``: directory for ``curves.csv``, ``fields/step.pvd`` (+ ``.vtu``) and ``last_converged.npz``,
        the checkpoint, saved every ``checkpoint_every`` converged steps (0: only on failure), at the end, and on
        failure; ``vtu_every=0`` disables field output. ``resume=True`` takes a run up again from the checkpoint in
        ``output`` (if there is one): the steps after it are recomputed, their rows and VTU files replaced, and the
        result is that of an uninterrupted run. ``on_step`` is called after every converged step with the
        (partial) result. ``continuation`` (a :attr:`SolveResult.continuation`, e.g. kept by a caller's own
        checkpoint) starts the run where that one stood, at its load factor with its step control, instead of at
        ``start``.
        """
        check_range("end", end, start, None, low_open=True)
        check_range("checkpoint_every", checkpoint_every, 0, None)
        ctrl, kin = self.control, self.kin
        recorder = RunRecorder(self, output, vtu_every, checkpoint_every=int(checkpoint_every))
        saved = recorder.resume() if resume else None
        if saved is not None:
            continuation = saved["continuation"]
        start, u, state = self._start(start, u0, state0, continuation)
        ctx0 = StepContext(0, start, 0.0, start * self.duration, 0.0, 0, u, u, state, np.zeros(kin.ndof))
        response, _, f_int, _, _ = self.evaluate(u, state, ctx0)  # the start state, for the record only
        cutbacks = 0

        def record(step, lam, iterations, residuals):
            recorder.record(step, lam, u, f_int, response, state, iterations, residuals)

        def control():
            return {"step": step, "delta": delta, "easy": easy, "cutbacks": cutbacks, "delta_prev": delta_prev}

        def result():
            res = recorder.result(cutbacks)
            res.continuation = {"u": u, "state": state, "load_factor": lam, "f_int": f_int, "u_prev": u_prev,
                                "control": control()}
            return res

        def checkpoint():
            return recorder.checkpoint(u, state, lam, control(), f_int=f_int, u_prev=u_prev)

        lam, delta, easy, step = start, min(ctrl.initial, end - start), 0, 0
        u_prev, delta_prev = None, None
        if continuation is not None:                   # continue exactly where the checkpoint left the run
            if continuation.get("f_int") is not None:
                f_int = continuation["f_int"]
            saved_control = continuation["control"]
            step, delta, easy, cutbacks = (saved_control[k] for k in ("step", "delta", "easy", "cutbacks"))
            u_prev, delta_prev = continuation.get("u_prev"), saved_control["delta_prev"]
        if saved is None:
            record(step, start, 0, [])
        else:
            recorder.last = (u, state, response, f_int)
        bar = progress_bar(total=end - start, disable=not progress, unit="λ",
                           bar_format="{l_bar}{bar}| λ={n:.4f}/{total}")
        try:
            while lam < end - 1e-12 * max(1.0, abs(end)):
                delta = min(delta, end - lam)
                lam_new = lam + delta
                u_trial, lift = self._predictor(u, u_prev, lam_new, delta, delta_prev)
                ctx = StepContext(step + 1, lam_new, delta, lam_new * self.duration, delta * self.duration, 0,
                                  u_trial, u, state, f_int)
                try:
                    res = self.newton(u_trial, state, ctx, lift=lift)
                except NewtonFailure as failure:
                    cutbacks += 1
                    easy = 0
                    delta *= ctrl.cutback
                    if delta < ctrl.minimum * (1 - 1e-12):
                        saved_to = checkpoint()
                        where = f"; saved to {saved_to}" if saved_to else ""
                        raise StepFailed(
                            f"load step from λ={lam:.6g} failed: {failure.reason}; the step size was cut back to "
                            f"{delta:.3g} < minimum {ctrl.minimum:.3g}. Last converged state: λ={lam:.6g}"
                            f"{where}. (Is the load beyond the limit load, or has the structure lost stiffness?)",
                            load_factor=lam, u=u, state=state, reason=failure.reason, result=result(),
                            checkpoint=saved_to) from failure
                    continue
                u_prev, delta_prev = u, delta
                u, response, f_int, state = res.u, res.response, res.f_int, res.response.state
                lam, step = lam_new, step + 1
                record(step, lam, res.iterations, res.residuals)
                bar.update(delta)
                easy = easy + 1 if res.iterations <= ctrl.easy_iterations else 0
                if easy >= ctrl.easy_steps:
                    delta, easy = min(delta * ctrl.growth, ctrl.maximum), 0
                if on_step is not None:
                    on_step(result())
                if recorder.due(step):
                    checkpoint()
            if recorder.writer is not None and not recorder.due(step):
                checkpoint()                                     # the end: a rerun returns at once
        finally:
            bar.close()
            recorder.close()
        return result()


def solve(basis, material: Material, dirichlet: Sequence[Dirichlet] = (), *, end: float = 1.0,
          output=None, progress: bool = True, vtu_every: int = 1, **options) -> SolveResult:
    """One-call form: ``Solver(basis, material, dirichlet, **options).run(end=..., output=...)``."""
    return Solver(basis, material, dirichlet, **options).run(end=end, output=output, progress=progress,
                                                             vtu_every=vtu_every)
