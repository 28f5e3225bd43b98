r"""Model I with the load factor as an unknown: path following through the snap-back of a damaging structure.

:class:`~abrakit.damage.model_one_fe.ModelISolver` runs Algorithm 1 of the seed under displacement control: a
Newton solve for the displacements with the damage function frozen at ``f^m``, then one damage update. Where the
force-displacement curve of the specimen turns back, no displacement increment reaches the next equilibrium, the
damage update jumps, and the solver accepts the jump (``result.jumps``). What happens in between is not computed.

Here the same two stages run inside a :class:`~abrakit.fem.PathFollowingSolver` step and are *repeated until they
agree* (a converged staggered scheme, "alternate minimisation" in the phase-field literature):

1. the constrained Newton solve of the step, ``R_u(u, λ) = 0`` and ``g(Δu, Δλ) = 0`` (bordered system), with the
   damage function frozen at the current damage iterate ``f^(k)``, plastic flow from the start of the step;
2. the coupled damage update (:func:`~abrakit.damage.model_one_fe.coupled_damage_function`, Eq. 6.64/6.76) with the
   new driving energy; irreversibility is measured from the start of the step, ``f^(k+1) <= f^m``.

The sweeps stop when no element's damage function changes by more than ``damage_tol`` between two sweeps; the
Newton solve of sweep k+1 starts from the solution of sweep k. The converged step is then an equilibrium point of
the coupled problem (to ``damage_tol``) *on the constraint*, so a constraint that grows monotonically through the
snap-back -- an opening across the damage zone (``method="opening"``, indirect displacement control) or the arc
length -- follows it. The damage does not jump: each step's change is whatever equilibrium on the constraint
requires, and the step length adapts to the number of sweeps and the first sweep's Newton iterations. A step
whose sweeps do not settle in ``max_sweeps`` is retried with a shorter constraint (the path follower's cutback).

The released energy G of :class:`~abrakit.fem.DissipationControl` suits Model I no better than Model II: the
material is plastic too, and elastic unloading from a plastic state releases energy by G without damaging. The
monolithic step below has the damage as an unknown and prescribes the damage dissipation itself
(:class:`DamageControl`, ``method="dissipation"``), which grows in every damaging step.

Cost: each sweep is a Newton solve; sweeps are few where damage grows slowly and many near a snap-back. The
staggered scheme is the seed's own splitting (Eq. 6.62/6.63), only converged. Where an element at the damage front
toggles between loading and unloading from one sweep to the next, the sweeps do not settle at all (measured on the
double notch with 500 elements: a change of 2.5e-4 after 400 sweeps).

``coupling="monolithic"`` solves the same equations in one Newton system instead: displacements, the element
damage functions of the damage zone and the load factor together, the complementarity of Eq. (6.64) written with
the Fischer-Burmeister function (semismooth Newton; the coupling blocks from
:mod:`~abrakit.damage.model_one_monolithic`). It converges where the sweeps cycle, because the unloading of an
element and the strain redistribution it causes are solved together rather than in turn. A converged monolithic
step solves the staggered step's equations (to the tolerances and the smoothing of H; tested on the bars).
"""

from __future__ import annotations

import time as _time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..fem.linsolve import DirectSolver, LinearSolveError
from ..fem.pathfollow import ConstraintSingular, LinearConstraint, LoadFactorControl, PathFollowingSolver, PathPoint
from ..fem.solver import NewtonFailure, StepContext
from ..materials.model_one import damage_indicator
from ..validation import check_finite, check_option, check_range
from .laplacian import ElementLaplacian
from .metrics import path_work
from .model_one_fe import (
    FrozenDamage,
    _fischer_burmeister,
    _jacobian_pattern,
    check_model_one_material,
    damage_update,
    element_damage_function,
    element_mean,
    indicator_jacobian_values,
    mesh_laplacian,
    model_one_energies,
)
from .model_one_monolithic import _point_sensitivities, coupling_blocks

#: A step whose sweeps have not improved for this many sweeps is accepted if its change is within
#: ``STALL_FACTOR * damage_tol`` (measured on the double notch: a 2e-6 cycle at tolerance 1e-6 after 400 sweeps).
STALL_SWEEPS, STALL_FACTOR = 30, 10.0
COUPLINGS = ("staggered", "monolithic")
#: Halvings of a monolithic Newton correction before the best of the tried points is taken.
MAX_BACKTRACKS = 6
#: An element whose f has not moved in the step and whose indicator lies within this many ``damage_tol`` (times r_d)
#: below its surface counts as on it under damage control (see :meth:`ModelIPathFollowingSolver._onset`).
NEAR_SURFACE = 10.0
#: Smoothing of the monolithic step's Fischer-Burmeister function, relative to ``damage_tol``: an element of the
#: damage front that sits on its surface without damaging (a = b = 0, the function's kink) made the semismooth
#: iterations toggle it between loading and unloading (double notch, 500 elements, beta = 1: stalled at
#: max |H| = 1.3 damage_tol); smoothed, it damages by at most ``(SMOOTHING damage_tol)^2 / b`` where it is b below
#: its surface.
SMOOTHING = 0.1
#: Elements whose smoothed complementarity reacts to their indicator by less than this (``c_b``) and whose H is
#: below 1e-3 ``damage_tol`` keep their f in a monolithic correction.
ACTIVE_DERIVATIVE = 1e-8


class _Iterate(NamedTuple):
    """What a monolithic Newton iteration reads at an iterate (u, f, λ) (:meth:`ModelIPathFollowingSolver._at_iterate`):
    the material response and the residual of the trial state, the element driving energies ``psi0_bar``, ``L f``,
    the indicator ``phi`` of Eq. (6.76) and the complementarity ``H`` with its derivatives ``c_a``, ``c_b``."""

    response: object
    residual: np.ndarray
    f_int: np.ndarray
    scale: float
    extra_K: list
    psi0_bar: np.ndarray
    lap_f: np.ndarray
    phi: np.ndarray
    H: np.ndarray
    c_a: np.ndarray
    c_b: np.ndarray
    trial: dict


@dataclass
class DamageControl:
    """``D(f) = sum_e V_e r_d (f^m_e - f_e) / f^m_e = τ``: the damage dissipation of the step, ``sum V_e r_d Δd_e``
    (Eq. 6.25, N mm, or N mm/mm in plane strain), to first order in the step (``Δd = -Δf / f^m + O(Δf^2)``), as the
    path constraint of a monolithic Model I step. Linear in f, so a Newton correction keeps it exactly. It grows in
    every step in which any element damages (no healing), through any snap-back of force or displacement, and,
    unlike the released energy of :class:`~abrakit.fem.DissipationControl`, it does not count the elastic
    unloading of plastically deformed material. Where no element damages it cannot be met; the step then loads the
    structure to the next element's damage onset (:meth:`ModelIPathFollowingSolver._onset`). ``weights``:
    ``V_e r_d`` per element."""

    tau: float
    weights: np.ndarray = None
    name = "damage"

    def __post_init__(self):
        check_range("tau", check_finite("tau", self.tau), 0.0, None, low_open=True)
        if self.weights is not None:
            self.weights = check_range("weights", check_finite("weights", self.weights), 0.0, None)

    def value(self, f: np.ndarray, f_old: np.ndarray) -> float:
        return float(self.weights @ (1.0 - f / f_old))

    def residual(self, f: np.ndarray, f_old: np.ndarray) -> float:
        return self.value(f, f_old) - self.tau

    def gradient(self, f_old: np.ndarray) -> np.ndarray:
        """``dD/df_e = -V_e r_d / f^m_e``."""
        return -self.weights / f_old

    def tolerance(self) -> float:
        """``1e-8 τ``, floored at the round-off of the sum."""
        return 1e-8 * abs(self.tau) + 1e-13 * float(np.sum(self.weights))


@dataclass
class ModelIPathResult:
    """A path-followed Model I run: the path follower's :class:`~abrakit.fem.SolveResult` (``solve``: curves with
    ``u_<name>``, ``F_<name>``, ``constraint``, ``released``, ...), the element fields at the end (``f``,
    ``alpha_p``), the energies at the end (N mm, or N mm/mm in plane strain), the sweeps per step, the steps
    accepted after their sweeps stalled (``stalled``) and the cost."""

    solve: object
    f: np.ndarray
    alpha_p: np.ndarray
    external_work: float
    stored_energy: float
    dissipated_energy: float
    damage_dissipation: float
    sweeps: np.ndarray
    seconds: float
    stalled: int = 0
    solver: object = None

    @property
    def curves(self) -> dict:
        return self.solve.curves

    @property
    def energy_error(self) -> float:
        """External work minus stored and dissipated energy (N mm): closes to the step error of the trapezoidal
        work sum; a converged staggered path has no jumps that release energy."""
        return self.external_work - self.stored_energy - self.dissipated_energy


class ModelIPathFollowingSolver(PathFollowingSolver):
    """Model I (a :class:`~abrakit.materials.ModelIDamage`) under path following, see the module docstring.

    ``damage_tol``: largest change of an element's damage function between two sweeps of a converged step
    (default 1e-6; on the notched bar 1e-4 left 15 % of the work unaccounted for); ``max_sweeps``: sweeps before
    the step is cut back; ``target_sweeps``: the step length adapts so that a step takes about this many sweeps
    (and the first sweep ``path.target_iterations`` Newton iterations, whichever asks for the shorter step);
    Anderson mixing needs 3-5 sweeps to reach 1e-6 however short the step, so a target below that would shrink
    every step (default 8); ``anderson``: depth of the Anderson mixing of the sweeps (0: plain sweeps);
    ``laplacian``: the mesh's :class:`~abrakit.damage.ElementLaplacian` (built here when ``beta > 0``);
    ``coupling``: ``"staggered"`` (sweeps, above) or ``"monolithic"`` (one Newton system for u, f and λ; then
    ``damage_tol`` bounds the complementarity residual ``max |H|`` and the sweep options are unused; linear
    constraints only, i.e. ``method="opening"`` or ``"dissipation"``). Other arguments as for
    :class:`~abrakit.fem.PathFollowingSolver` (``method``, ``path``, ``opening``, ``monitors``, ``newton``, ...).
    """

    def __init__(self, basis, material, dirichlet: Sequence = (), *, damage_tol: float = 1e-6,
                 max_sweeps: int = 100, target_sweeps: int = 8, anderson: int = 5,
                 laplacian: ElementLaplacian | None = None, coupling: str = "staggered", **options):
        check_model_one_material(material)
        super().__init__(basis, FrozenDamage(material), dirichlet, **options)
        self.model = material
        self.damage_tol = check_range("damage_tol", damage_tol, 0.0, 1.0, low_open=True, high_open=True)
        self.max_sweeps = int(check_range("max_sweeps", max_sweeps, 1, None))
        self.anderson = int(check_range("anderson", anderson, 0, None))
        self.target_sweeps = int(check_range("target_sweeps", target_sweeps, 1, self.max_sweeps))
        self.laplacian = mesh_laplacian(self.kin, material, laplacian)
        self.coupling = check_option("coupling", coupling, COUPLINGS)
        if self.coupling == "monolithic" and self.method == "arc-length":
            raise ValueError("coupling='monolithic' needs a linear constraint: method='opening' or 'dissipation', "
                             "got method='arc-length'")
        self._coupled_solver = DirectSolver("auto")     # the bordered (u, f, λ) system of a monolithic step
        self._reset()

    def constrained_newton(self, constraint, u0, lam0, state_old, f_int0, step, start, previous=None, guess=None):
        """Constrained Newton solve and coupled damage update, repeated until the damage settles.

        The sweeps are a fixed-point iteration ``f -> G(f)`` on the element damage functions (G: solve the
        displacements with f frozen, then update the damage). Near a snap-back its contraction factor
        approaches 1 (plain sweeps change f by 1e-3 after 100 sweeps on the double notch), so the iterates are
        mixed by Anderson acceleration of depth ``anderson`` (Walker & Ni 2011; for staggered phase-field
        fracture, Storvik et al. 2021), projected onto ``[f_min, f^m]``; where the projection stalls the mixing (the
        change does not fall below its best so far) the history is dropped and the next sweep is a plain one.
        Where the change has not improved for ``STALL_SWEEPS`` sweeps and lies within ``STALL_FACTOR`` times
        ``damage_tol`` (an element at the damage front toggling between loading and unloading), the step is
        accepted and counted in ``stalled``.
        """
        if self.coupling == "monolithic":
            return self._monolithic_newton(constraint, u0, lam0, state_old, f_int0, step, start, previous)
        iterations, residuals, best, best_sweep = 0, [], np.inf, 1
        f_old = element_damage_function(state_old)
        x, xs, gs = f_old, [], []
        for sweep in range(1, self.max_sweeps + 1):
            trial = state_old if sweep == 1 else {**state_old, "d": np.repeat(-np.log(x)[:, None], self.kin.nqp, 1)}
            u, lam, response, f_int, extra, its, res = super().constrained_newton(
                constraint, u0, lam0, trial, f_int0, step, start, previous, guess)
            if sweep == 1:
                first = its
            iterations, residuals = iterations + its, residuals + res
            try:   # irreversibility from the start of the step: f <= f^m, not f <= f^(k)
                new = damage_update(self.model, {**response.state, "d": state_old["d"]}, self.kin.dx,
                                    self.laplacian, "coupled")
            except RuntimeError as exc:
                raise NewtonFailure(str(exc), residuals) from exc
            g = element_damage_function(new)
            change = float(np.max(np.abs(g - x), initial=0.0))
            stalled = sweep - best_sweep >= STALL_SWEEPS and change <= STALL_FACTOR * self.damage_tol
            if change <= self.damage_tol or stalled:
                self.stalled += int(change > self.damage_tol)
                self.sweeps.append(sweep)
                self._effort = max(first, self.path.target_iterations * sweep / self.target_sweeps)
                return u, lam, replace(response, state=new), f_int, extra, iterations, residuals
            if change >= best:                     # the mixing stalls (e.g. on the bound f^m): restart plain
                xs.clear()
                gs.clear()
            else:
                best, best_sweep = change, sweep
            x = self._mix(x, g, xs, gs, f_old)
            guess = (u, lam)
        raise NewtonFailure(f"the staggered sweeps did not settle in {self.max_sweeps} (last change of f "
                            f"{change:.2e} > damage_tol = {self.damage_tol:.1e})", residuals)

    def _monolithic_newton(self, constraint, u0, lam0, state_old, f_int0, step, start, previous):
        """One path-following step with u, the damage functions and λ solved together (``coupling="monolithic"``).

        Predictor: under a linear constraint the frozen-damage tangent step of the staggered scheme; under
        :class:`DamageControl` the converged point itself (the step's damage is not known before the corrector).
        Corrector: semismooth Newton on
        ``[R_u; H; g] = 0`` with the Jacobian ::

            [ K_II            K_uf                    -q             ] [δu_I]   [-R_u]
            [ -c_b/r_d f G_I  -c_a - c_b/r_d ∂Φ/∂f     -c_b/r_d f G û ] [δf  ] = [-H  ]
            [ a               0                       b              ] [δλ  ]   [-g  ]

        (``∂Φ/∂f = diag(Psibar0 - β L f + f ∂Psibar0/∂f) - β diag(f) L``), restricted to the elements where H
        or its derivative c_b is not negligible (:meth:`_active`; the others keep their f); H is smoothed at its
        kink (:data:`SMOOTHING`). The iterates of f stay above ``f_min`` but may pass ``f^m`` (the complementarity
        pulls them back): clipping them at ``f^m`` switched elements of the damage front off and on from one
        iteration to the next. A backtracking line search on
        ``(|R_u|/tol)^2 + (|H|/damage_tol)^2`` (plus the damage or onset constraint's, scaled by its tolerance)
        breaks the cycles the non-smooth corner of H can still cause. Converged when the residual force meets
        the Newton tolerance, ``max |H| <= damage_tol`` and the constraint holds."""
        if not isinstance(constraint, (LinearConstraint, DamageControl)):
            raise NewtonFailure(f"coupling='monolithic' needs a linear or damage constraint, got {constraint.name}",
                                [])
        opts, free = self.newton_options, self.constraints.free
        f_old = element_damage_function(state_old)
        v0, P0 = self.load_pair(u0, lam0, f_int0)
        residuals: list[float] = []
        damage = isinstance(constraint, DamageControl)
        u, lam, f = u0, lam0, f_old.copy()           # damage control: Newton from the converged point
        if not damage:
            K, K_II = self.tangent(*start, u0)
            point = PathPoint(u0, lam0, v0, P0, u0, lam0, v0, P0, K, self.u_hat, self.f_hat, free, previous)
            du, dlam = self._bordered(constraint, point, K_II, None, residuals)
            lam = lam0 + dlam
            u = self._at(u0[free] + du, lam, u0)
        step_data = (step, u0, lam0, state_old, f_int0, f_old)
        at = self._at_iterate(u, f, lam, step_data, 1, residuals)
        onset = self._onset(at) if damage else None
        for k in range(1, opts.max_iterations + 1):
            norm = float(np.max(np.abs(at.residual[free]), initial=0.0))
            residuals.append(norm)
            tol = opts.residual_tol * at.scale + opts.absolute_force
            v, P = self.load_pair(u, lam, at.f_int)
            point = PathPoint(u0, lam0, v0, P0, u, lam, v, P, None, self.u_hat, self.f_hat, free, previous)
            if onset is not None:
                satisfied = abs(at.phi[onset] / self.model.r_d) <= self.damage_tol
            elif damage:
                satisfied = abs(constraint.residual(f, f_old)) <= constraint.tolerance()
            else:
                satisfied = constraint.satisfied(point, at.scale)
            if norm <= tol and float(np.max(np.abs(at.H), initial=0.0)) <= self.damage_tol and satisfied:
                self.sweeps.append(1)
                self._effort = k
                state = self._damaged_state(at.response.state, state_old, f, at.lap_f)
                self._step_damage = float(self._damage_weights() @ (state["d"][:, 0] - state_old["d"][:, 0]))
                return u, lam, replace(at.response, state=state), at.f_int, at.extra_K, k, residuals
            try:
                point.K, K_II = self.tangent(at.response, at.extra_K, u)
            except LinearSolveError as exc:
                raise NewtonFailure(str(exc), residuals) from exc
            du, df, dlam = self._coupled_correction(constraint, point, K_II, at, f, u, f_old, onset, residuals)
            current, best = self._merit(at, f, tol, constraint, onset, f_old), None
            for t in 0.5 ** np.arange(MAX_BACKTRACKS + 1):
                trial_u = self._at(u[free] + t * du, lam + t * dlam, u)
                trial_f = np.maximum(f + t * df, self.model.f_min)
                candidate = self._at_iterate(trial_u, trial_f, lam + t * dlam, step_data, k + 1, residuals)
                value = self._merit(candidate, trial_f, tol, constraint, onset, f_old)
                if best is None or value < best[0]:
                    best = (value, trial_u, trial_f, lam + t * dlam, candidate)
                if value <= (1.0 - 1e-4 * t) * current:
                    break
            _, u, f, lam, at = best
        raise NewtonFailure(f"monolithic Newton not converged in {opts.max_iterations} iterations", residuals)

    def _merit(self, at, f, tol: float, constraint, onset, f_old) -> float:
        """The line search's ``(|R_u|/tol)^2 + (|H|/damage_tol)^2``, plus the constraint a correction does not keep
        by linearity (the onset's indicator) or does not meet at the step's start (the damage dissipation)."""
        value = (float(np.sum(at.residual[self.constraints.free] ** 2)) / tol**2
                 + float(np.sum(at.H ** 2)) / self.damage_tol**2)
        if onset is not None:
            value += (at.phi[onset] / (self.model.r_d * self.damage_tol)) ** 2
        elif isinstance(constraint, DamageControl):
            value += (constraint.residual(f, f_old) / constraint.tolerance()) ** 2
        return value

    def _onset(self, at: _Iterate) -> int | None:
        """The element about to damage, when a :class:`DamageControl` step starts with no element on its damage
        surface (to within ``NEAR_SURFACE * damage_tol``): the one nearest to it. That step then only loads the
        structure until this element reaches its surface (and damages none), the next one damages."""
        if np.any(self._active(at.H, at.c_b)) or np.any(at.phi >= -NEAR_SURFACE * self.damage_tol * self.model.r_d):
            return None
        return int(np.argmax(at.phi))

    def _active(self, H, c_b) -> np.ndarray:
        """The elements whose f is an unknown of a monolithic correction (see :data:`ACTIVE_DERIVATIVE`)."""
        return (c_b > ACTIVE_DERIVATIVE) | (np.abs(H) > 1e-3 * self.damage_tol)

    def _at_iterate(self, u, f, lam, step_data, k, residuals) -> _Iterate:
        """Everything the monolithic Newton reads at an iterate (u, f, λ): the material response at the damage
        ``f`` from the plastic state at the start of the step, the residual, the driving energies, ``L f``, the
        indicator and the complementarity (:class:`_Iterate`)."""
        step, u0, lam0, state_old, f_int0, f_old = step_data
        model = self.model
        trial = {**state_old, "d": np.repeat(-np.log(f)[:, None], self.kin.nqp, axis=1)}
        ctx = StepContext(step, lam, lam - lam0, lam * self.duration, (lam - lam0) * self.duration, k, u, u0,
                          trial, f_int0)
        try:
            response, residual, f_int, scale, extra_K = self.evaluate(u, trial, ctx)
        except (ArithmeticError, np.linalg.LinAlgError) as exc:
            raise NewtonFailure(f"material update failed: {exc}", residuals) from exc
        psi0_bar = element_mean(response.state["psi0"], self.kin.dx)
        lap_f = np.zeros_like(f) if self.laplacian is None or model.beta == 0.0 else self.laplacian.matrix @ f
        phi = damage_indicator(f, psi0_bar, lap_f, model.beta, model.r_d)
        H, c_a, c_b = _fischer_burmeister(f, f_old, phi, model.r_d, model.f_min, SMOOTHING * self.damage_tol)
        if not (np.all(np.isfinite(residual)) and np.all(np.isfinite(H))):
            raise NewtonFailure("non-finite residual or damage complementarity", residuals)
        return _Iterate(response, residual, f_int, scale, extra_K, psi0_bar, lap_f, phi, H, c_a, c_b, trial)

    def _coupled_correction(self, constraint, point, K_II, at: _Iterate, f, u, f_old, onset, residuals):
        """(δu_I, δf, δλ) of one monolithic Newton iteration (see :meth:`_monolithic_newton`); the last row is the
        linearised constraint, ``a·δu_I + b δλ = -g``; under :class:`DamageControl` ``dD/df·δf = -g``, or, at the
        damage onset (``onset`` = the element about to damage), ``δΦ_onset = -Φ_onset``."""
        model, free, kin = self.model, self.constraints.free, self.kin
        H, c_a, c_b, phi, psi0_bar, R = at.H, at.c_a, at.c_b, at.phi, at.psi0_bar, at.residual[free]
        if isinstance(constraint, DamageControl):
            # the generalised Jacobian's loading branch (Φ stays 0, f free) for elements on the surface to within
            # NEAR_SURFACE: their FB derivative says "unloaded", and no element could then damage
            near = ~self._active(H, c_b) & (f >= f_old) & (phi >= -NEAR_SURFACE * self.damage_tol * model.r_d)
            c_a, c_b = np.where(near, 0.0, c_a), np.where(near, 1.0, c_b)
        zone = np.flatnonzero(self._active(H, c_b))
        needed = zone if onset is None else np.union1d(zone, [onset])   # the blocks' rows and columns used below
        sens = _point_sensitivities(model, at.trial, self.assembler.strain(u), f, kin.components, needed)
        K_uf, G, dpsibar_df = coupling_blocks(self.assembler, sens)
        if self.laplacian is not None and model.beta > 0.0:     # dΦ/df, then dH = -c_a df - c_b / r_d dΦ
            pattern, _, diagonal, _ = _jacobian_pattern(self.laplacian)
            values = indicator_jacobian_values(f, psi0_bar, self.laplacian, model.beta)
            values[diagonal] += f * dpsibar_df
            phi_f = sp.csr_matrix((values, pattern.indices, pattern.indptr), shape=pattern.shape)
        else:
            phi_f = sp.diags(psi0_bar + f * dpsibar_df, format="csr")
        phi_u = sp.diags(f) @ G                                        # over all DOFs
        weight = sp.diags(c_b / model.r_d)
        H_f, H_u = -sp.diags(c_a) - weight @ phi_f, -(weight @ phi_u)
        if onset is not None:
            a, a_f = phi_u[onset].toarray().ravel() / model.r_d, phi_f[onset][:, zone].toarray().ravel() / model.r_d
            a, b, g = a[free], float(a @ self.u_hat), phi[onset] / model.r_d
        elif isinstance(constraint, DamageControl):
            if zone.size == 0:
                raise ConstraintSingular("damage: no element is on its damage surface", residuals)
            a, a_f, b, g = np.zeros(free.size), constraint.gradient(f_old)[zone], 0.0, constraint.residual(f, f_old)
        else:
            a, b = constraint.gradient(point)
            a, a_f, g = np.zeros(free.size) if a is None else a, None, constraint.residual(point)
        q = self.f_hat[free] - (point.K @ self.u_hat)[free]
        H_zone = H_u[zone]
        system = sp.bmat([[K_II, K_uf[free][:, zone], sp.csr_matrix(-q[:, None])],
                          [H_zone[:, free], H_f[zone][:, zone], sp.csr_matrix((H_zone @ self.u_hat)[:, None])],
                          [sp.csr_matrix(a[None, :]), None if a_f is None or zone.size == 0 else
                           sp.csr_matrix(a_f[None, :]), sp.csr_matrix([[b]])]], format="csc")
        rhs = np.concatenate([-R, -H[zone], [-g]])
        try:         # its own solver: the pattern changes with the zone, and K_II's keeps its analysis
            x = self._coupled_solver.solve(system.tocsr(), rhs)
        except LinearSolveError:
            # ill-conditioned where an element's derivatives nearly vanish (its smoothed H at the kink): the solver
            # layer's residual check refuses the solution, SuperLU's unchecked one is a usable Newton direction
            # that the line search judges (double notch, 4141 elements, the first damage-controlled step)
            try:
                x = spla.splu(system.tocsc()).solve(rhs)
            except RuntimeError as exc:                                # exactly singular
                raise NewtonFailure(f"singular monolithic Jacobian: {exc}", residuals) from exc
        if not np.all(np.isfinite(x)):
            raise NewtonFailure("non-finite monolithic correction", residuals)
        df = np.zeros(f.size)
        df[zone] = x[free.size:-1]
        return x[:free.size], df, float(x[-1])

    def _damage_weights(self) -> np.ndarray:
        """``V_e r_d`` per element: the damage dissipation of a unit growth of d (N mm, or N mm/mm)."""
        return self.kin.dx.sum(axis=1) * self.model.r_d

    def _damage_control(self, tau: float | None = None) -> DamageControl:
        """A :class:`DamageControl` with target ``tau`` (default ``path.dissipation``, else 1 % of the external
        work done so far)."""
        if tau is None:
            tau = self.path.dissipation or 0.01 * max(self._work, 1e-300)
        return DamageControl(tau, self._damage_weights())

    def _damaged_state(self, state: dict, state_old: dict, f: np.ndarray, lap_f: np.ndarray) -> dict:
        """The converged monolithic state: damage ``d = -ln f`` (never below the old one), the damage dissipation
        ``r_d Δd`` added, and the element fields ``f`` and ``laplacian`` (``L f``) for the output."""
        nqp = self.kin.nqp
        d = np.maximum(np.repeat(-np.log(f)[:, None], nqp, axis=1), state_old["d"])
        return {**state, "d": d, "dissipation": state["dissipation"] + self.model.r_d * (d - state_old["d"]),
                "f": np.exp(-d), "laplacian": np.repeat(lap_f[:, None], nqp, axis=1)}

    def _mix(self, x, g, xs, gs, f_old):
        """Next damage iterate: Anderson mixing of the last ``anderson`` sweeps (``G(x)`` itself at depth 0).

        Elements the update leaves undamaged are not damaged by the extrapolation."""
        xs.append(x)
        gs.append(g)
        del xs[:-(self.anderson + 1)], gs[:-(self.anderson + 1)]
        if len(xs) < 2:
            return g
        residual = np.array(gs) - np.array(xs)              # f_k = G(x_k) - x_k, rows oldest first
        dF, dG = np.diff(residual, axis=0).T, np.diff(np.array(gs), axis=0).T
        gamma = np.linalg.lstsq(dF, residual[-1], rcond=None)[0]
        mixed = np.clip(g - dG @ gamma, self.model.f_min, f_old)
        return np.where(g < f_old, mixed, f_old)      # no extrapolated damage where the update sees none

    def _reset(self) -> None:
        """Start a run's records: sweeps per step, stalled steps, the step effort and the clock."""
        self.sweeps: list[int] = []
        self._effort, self.stalled, self._t0 = 1.0, 0, _time.perf_counter()
        self._step_damage, self._work = 0.0, 0.0

    def _next_constraint(self, constraint, iterations, softening, work, previous, first_target):
        """The path follower's step adaptation, driven by the sweeps and the first sweep's Newton iterations
        (their sum over the sweeps would shrink every step). Monolithic under ``method="dissipation"``: from load
        control to :class:`DamageControl` after the first step that damaged."""
        self._work = work
        if self._damage_controlled() and isinstance(constraint, LoadFactorControl) and self._step_damage > 0.0:
            return self._damage_control()
        return super()._next_constraint(constraint, int(np.ceil(self._effort)), softening, work, previous,
                                        first_target)

    def _softened(self, released: float, step_work: float) -> bool:
        """Monolithic under ``method="dissipation"``: never, the switch is the damage (plastic flow releases
        energy under load control without any damage)."""
        return False if self._damage_controlled() else super()._softened(released, step_work)

    def _damage_controlled(self) -> bool:
        return self.coupling == "monolithic" and self.method == "dissipation"

    def _limit_point(self, previous):
        """Where load control fails or softens: :class:`DamageControl` in the monolithic dissipation method."""
        return self._damage_control() if self._damage_controlled() else super()._limit_point(previous)

    def _constraint(self, name: str, tau: float):
        return self._damage_control(tau) if name == DamageControl.name else super()._constraint(name, tau)

    def run(self, **options) -> ModelIPathResult:
        """:meth:`abrakit.fem.PathFollowingSolver.run` (same options), returned with Model I's fields and energies.
        A failed step raises :class:`~abrakit.fem.StepFailed` as there; :meth:`result_of` its ``result`` keeps
        the followed part."""
        self._reset()
        return self.result_of(super().run(**options))

    def result_of(self, solve) -> ModelIPathResult:
        """The :class:`ModelIPathResult` of a path follower's :class:`~abrakit.fem.SolveResult` (complete or the
        ``result`` of a :class:`~abrakit.fem.StepFailed`)."""
        state, dx = solve.state, self.kin.dx
        v, P = solve.curves["v"], solve.curves["P"]   # the work-conjugate load pair: W = sum 1/2 (P0 + P1) (v1 - v0)
        energies = model_one_energies(self.model, state, dx, self.laplacian, path_work(v, P))
        return ModelIPathResult(
            solve=solve, f=element_damage_function(state), alpha_p=element_mean(state["alpha_p"], dx),
            external_work=energies["external_work"], stored_energy=energies["stored_energy"],
            dissipated_energy=energies["dissipated_energy"], damage_dissipation=energies["damage_dissipation"],
            sweeps=np.array(self.sweeps), seconds=_time.perf_counter() - self._t0,
            stalled=self.stalled, solver=self)

    def damage_residual(self, state: dict) -> float:
        """Largest change of an element's damage function under one more coupled damage update from ``state``
        (0 at a converged point of the staggered scheme)."""
        again = damage_update(self.model, state, self.kin.dx, self.laplacian, "coupled")
        return float(np.max(np.abs(np.exp(-again["d"]) - np.exp(-state["d"]))))
