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

Dissipation control suits Model I no better than Model II: the material is plastic too, and elastic unloading from
a plastic state releases energy by the G of the dissipation constraint without damaging.

Cost: each sweep is a Newton solve; sweeps are few where damage grows slowly and many near a snap-back. The
staggered scheme is the seed's own splitting (Eq. 6.62/6.63), only converged; the monolithic alternative (damage in
the Newton system) would need the damage update's derivative with respect to the strain.
"""

from __future__ import annotations

import time as _time
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from ..fem.pathfollow import PathFollowingSolver
from ..fem.solver import NewtonFailure
from ..validation import check_range
from .laplacian import ElementLaplacian
from .model_one_fe import (
    FrozenDamage,
    check_model_one_material,
    damage_update,
    element_damage_function,
    element_mean,
    mesh_laplacian,
    model_one_energies,
)

__all__ = ["ModelIPathFollowingSolver", "ModelIPathResult"]

#: A step whose sweeps have not improved for this many sweeps is accepted if its change is within
#: ``STALL_FACTOR * damage_tol`` (measured on the double notch: a 2e-6 cycle at tolerance 1e-6 after 400 sweeps).
STALL_SWEEPS, STALL_FACTOR = 30, 10.0


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
    ``laplacian``: the mesh's :class:`~abrakit.damage.ElementLaplacian` (built here when ``beta > 0``). Other
    arguments as for :class:`~abrakit.fem.PathFollowingSolver` (``method``, ``path``, ``opening``, ``monitors``,
    ``newton``, ...).
    """

    def __init__(self, basis, material, dirichlet: Sequence = (), *, damage_tol: float = 1e-6,
                 max_sweeps: int = 100, target_sweeps: int = 8, anderson: int = 5,
                 laplacian: ElementLaplacian | None = None, **options):
        check_model_one_material(material)
        super().__init__(basis, FrozenDamage(material), dirichlet, **options)
        self.model = material
        self.damage_tol = check_range("damage_tol", damage_tol, 0.0, 1.0, low_open=True, high_open=True)
        self.max_sweeps = int(check_range("max_sweeps", max_sweeps, 1, None))
        self.anderson = int(check_range("anderson", anderson, 0, None))
        self.target_sweeps = int(check_range("target_sweeps", target_sweeps, 1, self.max_sweeps))
        self.laplacian = mesh_laplacian(self.kin, material, laplacian)
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

    def _next_constraint(self, constraint, iterations, *args):
        """The path follower's step adaptation, driven by the sweeps and the first sweep's Newton iterations
        (their sum over the sweeps would shrink every step)."""
        return super()._next_constraint(constraint, int(np.ceil(self._effort)), *args)

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
        energies = model_one_energies(self.model, state, dx, self.laplacian,
                                      float(np.sum(0.5 * (P[1:] + P[:-1]) * np.diff(v))))
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
