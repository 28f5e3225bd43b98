"""What a path-following run (:meth:`~abrakit.fem.pathfollow.PathFollowingSolver.run`) starts from, carries from one
step to the next and stores in its checkpoints, so that a resumed run continues with the constraint, targets and
counters of the run it continues."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..materials.base import MaterialResponse
from .solver import StepContext


@dataclass
class _Walk:
    """A path-following run's walk along the path so far: the converged point (displacements ``u``, ``state``, load
    factor ``lam``, material ``response``, internal forces ``f_int``, the hook tangents ``extra_K``, the load pair
    ``v``, ``P``), the constraint of the next step, and the counters: cut-backs, external work, peak |P|, each
    constraint type's first target (``firsts``), the previous increment (Δu, Δλ) and the last load-factor increment
    (``last_dlam``)."""

    u: np.ndarray
    state: dict
    lam: float
    response: MaterialResponse
    f_int: np.ndarray
    extra_K: object
    constraint: object
    last_dlam: float
    v: float = 0.0
    P: float = 0.0
    cutbacks: int = 0
    work: float = 0.0
    peak: float = 0.0
    firsts: dict = field(default_factory=dict)
    previous: tuple[np.ndarray, float] | None = None

    @classmethod
    def start(cls, solver, recorder, saved: dict | None, constraint) -> tuple[_Walk, int]:
        """The converged point a run of ``solver`` starts from and its first step: λ = 0 under ``constraint``
        (recorded as step 0), or where the checkpoint ``saved`` left the run."""
        kin = solver.kin
        if saved is None:
            state, lam = solver.material.initial_state((kin.nel, kin.nqp)), 0.0
            u = solver._at(np.zeros(solver.constraints.free.size), 0.0, np.zeros(kin.ndof))
        else:
            state, lam, u = saved["state"], saved["load_factor"], saved["u"]
        ctx0 = StepContext(0, lam, 0.0, lam * solver.duration, 0.0, 0, u, u, state, np.zeros(kin.ndof))
        response, _, f_int, _, extra_K = solver.evaluate(u, state, ctx0)
        run = cls(u, state, lam, response, f_int, extra_K, constraint, last_dlam=solver.path.initial)
        if saved is not None:
            return run, run.resume(saved, recorder, solver._constraint)
        run.v, run.P = solver.load_pair(u, lam, f_int)
        recorder.record(0, lam, u, f_int, response, state, 0, [], constraint=0, v=run.v, P=run.P, released=0.0)
        return run, 1

    def accept(self, u, lam, response, f_int, extra_K, v, P, step_work) -> None:
        """Make the converged step to (u, λ) the new start: its increment the previous one, its work added."""
        self.work += step_work
        self.previous = (u - self.u, lam - self.lam)
        self.u, self.lam, self.response, self.f_int, self.state = u, lam, response, f_int, response.state
        self.extra_K = extra_K
        self.v, self.P = v, P
        self.peak = max(self.peak, abs(P))

    def checkpoint(self, recorder, step: int, finished: bool = False):
        """Store the run as it is after ``step`` (:meth:`~abrakit.fem.recorder.RunRecorder.checkpoint`)."""
        previous = self.previous
        control = {"step": step, "finished": finished, "cutbacks": self.cutbacks, "work": self.work,
                   "peak": self.peak, "v": self.v, "P": self.P,
                   "constraint": self.constraint.name, "tau": self.constraint.tau, "last_dlam": self.last_dlam,
                   "firsts": {t.name: tau for t, tau in self.firsts.items()},
                   "previous_dlam": None if previous is None else previous[1]}
        return recorder.checkpoint(self.u, self.state, self.lam, control, f_int=self.f_int,
                                   previous_du=None if previous is None else previous[0],
                                   stress=self.response.stress, tangent=self.response.tangent)

    def resume(self, saved: dict, recorder, constraint_named) -> int:
        """Continue exactly where the checkpoint ``saved`` left the run (``constraint_named(name, tau)`` rebuilds a
        constraint); returns the next step."""
        c, arrays = saved["meta"]["control"], saved["arrays"]
        self.f_int = arrays.get("f_int", self.f_int)
        if "tangent" in arrays:        # the converged step's tangent starts the next step (see constrained_newton)
            self.response = MaterialResponse(arrays["stress"], arrays["tangent"], self.state)
        recorder.last = (self.u, self.state, self.response, self.f_int)
        self.cutbacks, self.work, self.peak, self.v, self.P = c["cutbacks"], c["work"], c["peak"], c["v"], c["P"]
        self.constraint = constraint_named(c["constraint"], c["tau"])
        self.firsts = {type(constraint_named(name, tau)): tau for name, tau in c["firsts"].items()}
        self.last_dlam = c["last_dlam"]
        if "previous_du" in arrays:
            self.previous = (arrays["previous_du"], c["previous_dlam"])
        return c["step"] + 1
