"""The record of a Newton run: its converged history, its output files and its checkpoint.

:class:`RunRecorder` keeps one row per converged step (load factor, time, Newton iterations, the mean displacement
and summed force of every monitored DOF set, and any extra columns), writes it through a
:class:`~abrakit.fem.output.RunWriter` as the run goes (``curves.csv``, ``fields/step.pvd``) and saves the
checkpoint ``last_converged.npz`` from which :meth:`RunRecorder.resume` takes an interrupted run up again.
:func:`save_run` and :func:`load_run` are the one checkpoint format of every run (the solver's, the scratch's and
Model II's): state, fingerprint, step control, arrays and the run's record. :attr:`SolveResult.continuation` is
where a run stands after its last converged step; :func:`continuation_arrays` and :func:`continuation_of` put it
into a checkpoint and read it back.

Example::

    saved = load_run(folder / "last_converged.npz", fingerprint)
    solver.run(end=1.0, continuation=saved["continuation"])
"""

from __future__ import annotations

import time as _time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .output import RunWriter, load_matching_checkpoint, save_checkpoint


@dataclass
class SolveResult:
    """History of a run: one entry per converged step (index 0 is the start state)."""

    load_factors: np.ndarray
    times: np.ndarray
    iterations: np.ndarray
    curves: dict[str, np.ndarray]
    u: np.ndarray
    state: dict
    response: Any
    f_int: np.ndarray
    residual_histories: list[list[float]]
    cutbacks: int
    wall_time: float
    output: Path | None = None
    continuation: dict | None = None
    """Where :meth:`~abrakit.fem.Solver.run` stands after the last converged step, what ``run(continuation=...)``
    needs to go on exactly as this run would: ``u``, ``state``, ``load_factor``, ``f_int``, ``u_prev`` (the step
    before, for extrapolation) and ``control`` (JSON-able: ``step``, ``delta`` — the next step size —, ``easy``,
    ``cutbacks``, ``delta_prev``)."""


def continuation_arrays(continuation: dict | None) -> dict:
    """The arrays of a :attr:`SolveResult.continuation` that a checkpoint keeps beside ``u`` and the state
    (``f_int``, ``u_prev`` where given); its ``control`` goes into the checkpoint's meta. :func:`continuation_of`
    reads them back."""
    if continuation is None:
        return {}
    return {k: continuation[k] for k in ("f_int", "u_prev") if continuation[k] is not None}


def continuation_of(saved: dict) -> dict | None:
    """The :attr:`SolveResult.continuation` kept by a checkpoint (the dict of
    :func:`~abrakit.fem.output.load_checkpoint`, its step control in ``meta["control"]``), or ``None`` if it keeps
    no step control (a phase end, a finished run)."""
    control = saved["meta"].get("control")
    if control is None:
        return None
    arrays = saved["arrays"]
    return {"u": saved["u"], "state": saved["state"], "load_factor": saved["load_factor"],
            "f_int": arrays.get("f_int"), "u_prev": arrays.get("u_prev"), "control": control}


def save_run(path, u, state, load_factor: float, time: float, *, fingerprint: dict, control: dict | None = None,
             arrays: dict | None = None, **meta) -> Path:
    """Write the checkpoint of a run (atomically, :func:`~abrakit.fem.output.save_checkpoint`): ``u``, the material
    ``state``, the load factor and time, the run's ``fingerprint`` (what a resumed run must match), the solver's
    step ``control`` (JSON-able; ``None`` where the run stands at the end of a phase), the ``arrays`` it needs
    beyond u and the state (``None`` entries left out) and the run's own JSON-able ``meta`` (its record so far).
    :func:`load_run` reads it back."""
    arrays = {k: v for k, v in (arrays or {}).items() if v is not None}
    return save_checkpoint(path, u, state, load_factor, time, arrays=arrays,
                           meta={"fingerprint": fingerprint, "control": control, **meta})


def load_run(path, fingerprint: dict, run: str = "problem") -> dict | None:
    """The checkpoint of :func:`save_run` at ``path`` (``None`` if there is none) with ``"continuation"`` added
    (:func:`continuation_of`); a checkpoint of another ``run`` (another fingerprint) is refused by name."""
    saved = load_matching_checkpoint(path, fingerprint, run)
    if saved is not None:
        saved["continuation"] = continuation_of(saved)
    return saved


@dataclass
class _History:
    load_factors: list = field(default_factory=list)
    times: list = field(default_factory=list)
    iterations: list = field(default_factory=list)
    residuals: list = field(default_factory=list)
    rows: list = field(default_factory=list)

    def add(self, row: dict, iterations: int, residuals: list) -> None:
        """One converged step: its curve row (holding ``load_factor`` and ``time``) and Newton history."""
        self.load_factors.append(row["load_factor"])
        self.times.append(row["time"])
        self.iterations.append(iterations)
        self.residuals.append(residuals)
        self.rows.append(row)


class RunRecorder:
    """The history of a run: one row per converged step (load factor, time, iterations, monitored displacements
    and forces, and any ``extra`` columns), written through a :class:`RunWriter` as it goes when ``output`` is
    given, and turned into a :class:`SolveResult`. With ``output`` it also saves a checkpoint every
    ``checkpoint_every`` steps, from which :meth:`resume` takes an interrupted run up again."""

    def __init__(self, solver, output, vtu_every: int, extra_columns: Sequence[str] = (),
                 checkpoint_every: int = 0):
        self.solver = solver
        self.columns = ["step", "load_factor", "time", "iterations", *extra_columns] + [
            f"{kind}_{name}" for name in solver.monitors for kind in ("u", "F")]
        self.output = Path(output) if output is not None else None
        self.writer = (RunWriter(output, solver.kin.basis.mesh, self.columns, vtu_every)
                       if output is not None else None)
        self.checkpoint_every = checkpoint_every
        self.nodal = np.asarray(solver.kin.basis.nodal_dofs)
        self.hist = _History()
        self.t0 = _time.perf_counter()
        self.last = None

    def record(self, step, lam, u, f_int, response, state, iterations, residuals, **extra) -> None:
        duration = self.solver.duration
        row = {"step": step, "load_factor": lam, "time": lam * duration, "iterations": iterations, **extra}
        for name, dofs in self.solver.monitors.items():
            row[f"u_{name}"] = float(np.mean(u[dofs])) if dofs.size else 0.0
            row[f"F_{name}"] = float(np.sum(f_int[dofs]))
        self.hist.add(row, iterations, residuals)
        self.last = (u, state, response, f_int)
        if self.writer is not None:
            self.writer.write_step(row, lam * duration, u, self.nodal, response.stress, state)

    def result(self, cutbacks: int) -> SolveResult:
        hist = self.hist
        u, state, response, f_int = self.last
        curves = {k: np.array([r[k] for r in hist.rows]) for k in self.columns}
        return SolveResult(np.array(hist.load_factors), np.array(hist.times), np.array(hist.iterations), curves,
                           u, state, response, f_int, hist.residuals, cutbacks, _time.perf_counter() - self.t0,
                           self.output)

    def _fingerprint(self) -> dict:
        kin = self.solver.kin
        return {"ndof": int(kin.ndof), "nel": int(kin.nel), "nqp": int(kin.nqp), "columns": self.columns,
                "duration": float(self.solver.duration)}

    def checkpoint(self, u, state, lam, control: dict | None = None, **arrays) -> Path | None:
        """Save the last converged step with the history so far, the step control (``control``, JSON-able: the
        step, step sizes, counters) and the named ``arrays`` it needs (``None`` ones are left out), or nothing
        without ``output``."""
        if self.writer is None:
            return None
        hist = self.hist
        return save_run(self.writer.checkpoint_path, u, state, lam, lam * self.solver.duration,
                        fingerprint=self._fingerprint(), control=control or {}, arrays=arrays,
                        history={"rows": hist.rows, "iterations": hist.iterations, "residuals": hist.residuals},
                        output=self.writer.position())

    def due(self, step: int) -> bool:
        return self.writer is not None and self.checkpoint_every > 0 and step % self.checkpoint_every == 0

    def resume(self) -> dict | None:
        """The checkpoint in ``output`` (:func:`load_run`) with the history restored and the output files rewound
        to it, or ``None`` when there is none. A checkpoint of a different problem (DOFs, elements, points,
        columns) is refused."""
        if self.writer is None:
            return None
        saved = load_run(self.writer.checkpoint_path, self._fingerprint())
        if saved is None:
            return None
        meta = saved["meta"]
        history = meta["history"]
        for row, iterations, residuals in zip(history["rows"], history["iterations"], history["residuals"],
                                              strict=True):
            self.hist.add(row, iterations, residuals)
        self.writer.restart(history["rows"], meta["output"])
        return saved

    def close(self) -> None:
        if self.writer is not None:
            self.writer.close()
