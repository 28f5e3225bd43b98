r"""Model II in the finite element loop: Algorithm 2 of the seed on :class:`abrakit.fem.Solver` (Ch. 6.5).

Every quadrature point carries an emulated RVE of ``n`` sub-domains (:class:`abrakit.materials.ModelIIDamage`):
in every Newton iteration of a load step m -> m+1 the material is called from the converged state m with the
current strain, does the plastic step with ``f_bar^m``, sweeps the sub-domains (rule 6.95: sub-domain i grows by
the rate limit where ``p_d,i > r_d / n``, capped at ``d_i <= 0.999``) and returns ``f_bar^{m+1} E : eps_e`` (6.99).

**The rate limit, Eq. (6.96)-(6.98), (6.103).** The damage of a sub-domain may grow in one step by at most
``alpha l_ext dt``, with the power of the external forces (6.97) ``l_ext = Delta u . sum f* / dt``. What is passed
to the material (as ``external_work``, so ``dt`` drops out) is

.. math::

    \ell_\text{ext}\,\Delta t = s \sum_{D} \big(u_D^{m+1} - u_D^{m}\big)\, f^{*m}_D \qquad [\text{N mm}],

the sum running over all prescribed DOFs D (only the loaded edge moves, so it is the increment of the applied
displacement times the reaction of the loaded edge), with the reactions ``f*^m`` = internal forces on those DOFs
at the **last converged** step (explicit: the increment is fixed during the Newton iterations of a step, so
Newton sees a material whose damage rule does not chase its own reaction) and ``s`` the specimen's
``force_scale`` (the 3 mm thickness in plane strain: ``alpha`` of Table 7.2 is per N mm of the seed's 3 mm plate,
and ``l_ext`` is the power on the modelled quarter/half, as the seed's model sees it). In the first step
``f*^0 = 0``, so no damage can start there. With ``dt = 1 s`` (Table 7.2) ``l_ext`` and the work coincide.

**Energy bookkeeping** per converged step (N mm, for the whole 3 mm plate):

- external work ``W = sum 1/2 s (f*^m + f*^{m+1}) . (u^{m+1} - u^m)`` (trapezoidal rule on the reactions);
- stored energy ``int (f_bar Psi0 + 1/2 K_H alpha_p^2) dV`` (6.89);
- plastic dissipation ``int r_p sum |d eps_p| dV`` (6.82);
- damage dissipation: the energy released by the damage increments, in the trapezoidal form that matches W,
  ``int 1/2 (f_bar^m - f_bar^{m+1}) eps_e^m : E : eps_e^{m+1} dV`` -- all of it is dissipated, since the rate
  limit (not ``r_d``) is what stops the growth: ``p_d,i dd_i >= r_d/n dd_i`` (6.95); the part
  ``r_d/n sum dd_i`` of (6.90) is recorded as ``threshold_dissipation``.

With these, ``W = stored + dissipated`` is an identity for the elastic and damage parts; what remains
(``energy_error``) is the first-order splitting error of Algorithm 2, whose plastic step uses ``f_bar^m`` while
the stress carries ``f_bar^{m+1}``: it shrinks in proportion to the load step.

**Output** (directory ``output``): ``force_displacement.csv`` (one row per converged step, written as the run
goes), ``fields/damage.pvd`` + ``.vtu`` (every ``vtu_every`` steps and the last one: displacement; per element
``f_bar``, ``stiffness_loss = 1 - f_bar``, ``d_mean`` and ``d_max`` over the sub-domains, ``alpha_p``,
``psi0``, ``von_mises``), ``summary.json``, and ``last_converged.npz`` (:func:`abrakit.fem.recorder.load_run`
reads it): every ``checkpoint_every`` steps and at the end (the final state, or the last good one when a step failed)
the state, the energy account with its rows and the solver's step control, from which ``resume=True`` continues a
killed run.

**Sudden force drops.** A step whose Newton iterations fail (a band snapping through) is cut back by the solver
(the damage increment shrinks with the displacement increment); below ``control.minimum`` the run stops with
``status = "failed"``, a message naming the load factor, and the last converged state in the result and on disk.
The run may also stop once the force has fallen below ``stop_fraction`` of its peak (``status = "fractured"``).

Units: N, mm, MPa; ``alpha`` in 1/(N mm).
"""

from __future__ import annotations

import time as _time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from ..fem.kinematics import element_mean
from ..fem.output import RunWriter, cell_fields, meshio_cells
from ..fem.recorder import continuation_arrays, load_run, save_run
from ..fem.solver import StepFailed
from ..io import CurveWriter, VtuSeries, write_json
from ..materials import TABLE_7_2, ModelIIDamage
from ..materials.model_two import damage_function, effective_damage_function
from ..validation import check_finite, check_indices, check_option, check_positive, check_range, check_shape

CURVE_COLUMNS = ("step", "load_factor", "u", "F", "external_work", "rate_limit_work", "damage_increment",
                 "stored_energy", "plastic_dissipation", "damage_dissipation", "threshold_dissipation",
                 "dissipated_energy", "energy_error", "max_d", "min_f_bar", "damaged_area", "iterations",
                 "cutbacks", "seconds")


def element_f_bar(state: dict, dx: np.ndarray) -> np.ndarray:
    """Element mean of ``f_bar`` (6.87), in [0, 1] (the rounding of the mean of ones is clipped)."""
    return np.minimum(element_mean(f_bar_of(state), dx), 1.0)


def rate_limit_work(u: np.ndarray, u_old: np.ndarray, reactions_old: np.ndarray, prescribed: np.ndarray,
                    force_scale: float = 1.0) -> float:
    """``l_ext dt = s sum_D (u_D^{m+1} - u_D^m) f*_D^m`` (N mm), Eq. (6.97) times dt: the work of the last
    converged reactions ``reactions_old`` (internal forces, N or N/mm) over the applied displacement increment."""
    u, u_old, reactions_old = (check_shape(name, check_finite(name, value), (None,)) for name, value in
                               (("u", u), ("u_old", u_old), ("reactions_old", reactions_old)))
    if not u.shape == u_old.shape == reactions_old.shape:
        raise ValueError(f"u, u_old and reactions_old must have one shape, got {u.shape}, {u_old.shape}, "
                         f"{reactions_old.shape}")
    prescribed = check_indices("prescribed", prescribed, u.size)
    du = u[prescribed] - u_old[prescribed]
    return float(check_finite("force_scale", force_scale) * np.dot(du, reactions_old[prescribed]))


def f_bar_of(state: dict) -> np.ndarray:
    """Effective damage function ``f_bar = n / sum 1/f(d_i)`` (6.87) at every point of a Model II state."""
    return effective_damage_function(damage_function(state["d"]))


def default_material(alpha: float = 0.05, **overrides) -> ModelIIDamage:
    """Table 7.2 (E, nu, r_d, n, dt, r_p, K_H) with the given ``alpha``; implicit return map unless overridden.

    The seed integrates plasticity by explicit Euler (6.59); the radial return (backward Euler) used by default
    here is exact on radial paths and has no first-order lag of ``alpha_p`` (see :mod:`abrakit.materials.plasticity`);
    ``integration="explicit"`` gives the seed's scheme.
    """
    params = {**TABLE_7_2, "alpha": check_positive("alpha", alpha), "integration": "implicit"}
    params.update(overrides)
    return ModelIIDamage(**params)


@dataclass
class ModelTwoResult:
    """History of a Model II run; ``curves`` has one entry per converged step (index 0: the unloaded start).

    ``curves``: the :data:`CURVE_COLUMNS` -- ``u`` (mm) and ``F`` (N, whole specimen) of the loaded edge, the
    energies (N mm), ``rate_limit_work`` (the work passed to the rate limit in that step), ``damage_increment``
    (``alpha`` times it), ``max_d``, ``min_f_bar``, ``damaged_area`` (mm^2 with ``f_bar <= 0.25``), Newton
    ``iterations``, ``cutbacks`` so far, ``seconds`` (wall time of the step). Final element fields: ``f_bar``,
    ``d_mean``, ``alpha_p`` (element means). ``status``: ``"end"`` (load path completed), ``"fractured"``
    (force fell below ``stop_fraction`` of the peak), ``"failed"`` (a step could not be completed; ``message``).
    """

    curves: dict[str, np.ndarray]
    f_bar: np.ndarray
    d_mean: np.ndarray
    alpha_p: np.ndarray
    u: np.ndarray
    state: dict
    status: str
    message: str
    cutbacks: int
    wall_time: float
    alpha: float
    elements: int
    output: Path | None = None
    checkpoint: Path | None = None

    @property
    def completed(self) -> bool:
        return self.status != "failed"

    @property
    def steps(self) -> int:
        return len(self.curves["step"]) - 1

    @property
    def newton_iterations(self) -> int:
        return int(self.curves["iterations"].sum())

    @property
    def stiffness_loss(self) -> np.ndarray:
        """``1 - f_bar`` per element: 0 intact, 1 fully damaged."""
        return 1.0 - self.f_bar

    def peak(self) -> tuple[float, float]:
        """``(F_max, u at F_max)`` (N, mm)."""
        i = int(np.argmax(self.curves["F"]))
        return float(self.curves["F"][i]), float(self.curves["u"][i])

    @property
    def dissipated_energy(self) -> float:
        """Total dissipation at the end of the run (plastic + damage), N mm."""
        return float(self.curves["dissipated_energy"][-1])

    def summary(self) -> dict:
        F_max, u_peak = self.peak()
        c = self.curves
        return {"status": self.status, "message": self.message, "alpha": self.alpha, "elements": self.elements,
                "steps": self.steps, "newton_iterations": self.newton_iterations, "cutbacks": self.cutbacks,
                "wall_time_s": self.wall_time, "seconds_per_step": self.wall_time / max(self.steps, 1),
                "peak_force_N": F_max, "u_at_peak_mm": u_peak, "final_u_mm": float(c["u"][-1]),
                "external_work_Nmm": float(c["external_work"][-1]), "dissipated_energy_Nmm": self.dissipated_energy,
                "energy_error_Nmm": float(c["energy_error"][-1]), "max_d": float(c["max_d"].max()),
                "min_f_bar": float(c["min_f_bar"].min())}


class _Stop(Exception):
    pass


@dataclass
class _Bookkeeping:
    rows: list = field(default_factory=list)
    external: float = 0.0
    plastic: float = 0.0
    released: float = 0.0
    threshold: float = 0.0
    peak: float = 0.0
    u_prev: np.ndarray | None = None
    f_prev: np.ndarray | None = None
    state_prev: dict | None = None
    clock: float = 0.0
    last: object = None


#: how a path-followed step evaluates its rate limit: from the current Newton iterate, or frozen at the step's
#: first iterate (the predictor), a diagnostic (see :func:`model_two_solver`)
RATE_LIMITS = ("iterate", "predictor")


def model_two_solver(basis, material: ModelIIDamage, dirichlet, *, force_scale: float = 1.0, steps: int = 200,
                     control=None, newton=None, linear_solver="auto", end: float = 1.0, path=None,
                     method: str = "dissipation", rate_limit: str = "iterate"):
    """:class:`abrakit.fem.Solver` with the Model II rate limit in its ``loading`` hook (see the module docstring).

    ``steps`` equal load increments over ``[0, end]`` unless ``control`` is given: cutbacks by 1/4 down to
    ``1e-3`` of a step; after a cutback the increment doubles again after every step that converged within
    8 Newton iterations. (The damage rule switches sub-domains on and off between iterates, so Model II steps
    often need 5-8 iterations; with the solver's default "easy" limit of 4 a single cutback at a damage jump
    would leave the rest of the run at the small increment.)

    ``path`` (a :class:`~abrakit.fem.PathControl`): a :class:`~abrakit.fem.PathFollowingSolver` with ``method``
    instead. The load factor is then an unknown and may fall (snap-back), where the reactions do negative work
    over the increment; the rate limit takes the magnitude of that work, ``|s sum_D du_D f*_D^m|``: the damage of
    a step is bounded by the energy exchanged at the loaded boundary, whichever way it flows. With
    ``rate_limit="iterate"`` that work follows the unknown load factor through the Newton iterations, and the
    tangent does not carry this dependence; ``rate_limit="predictor"`` freezes it at the step's first iterate. This
    is a diagnostic, not a method (the step's damage then does not follow the corrected load factor): on the plate
    with a hole (250 elements, alpha = 0.05) the live rate limit creeps at the peak for 600 steps, the frozen one
    passes the peak in 9 steps and stops at 91 % of it, where the arc-length equation has no real root
    (``benchmarks/bench_model_two_steps.py``). Model II needs no path following: its path is a graph over u
    (book chapter "Model II", section "Model II does not snap back").
    """
    from ..fem import PathFollowingSolver, Solver, StepControl

    steps = int(check_range("steps", steps, 1, None))
    scale = check_positive("force_scale", force_scale)
    check_option("rate_limit", rate_limit, RATE_LIMITS)
    if control is None:
        step = end / steps
        control = StepControl(initial=step, maximum=step, minimum=step * 1e-3, growth=2.0, easy_iterations=8,
                              easy_steps=1)
    if path is None:
        solver = Solver(basis, material, dirichlet, control=control, newton=newton, linear_solver=linear_solver)
    else:
        solver = PathFollowingSolver(basis, material, dirichlet, newton=newton, linear_solver=linear_solver,
                                     method=method, path=path)
    prescribed = solver.constraints.prescribed
    magnitude = abs if path is not None else float
    frozen = {}

    def loading(ctx):
        if rate_limit == "iterate" or ctx.iteration <= 1 or not frozen:
            frozen["work"] = magnitude(rate_limit_work(ctx.u, ctx.u_old, ctx.f_int_old, prescribed, scale))
        return {"external_work": frozen["work"]}

    solver.loading = loading
    return solver


class _ModelTwoRun:
    """The record of a Model II run (see the module docstring): its energy account and rows, the curves and VTU
    files, the checkpoint, and what happens after every converged step (account, checkpoint, ``on_step``, the
    stop once the force has fallen below ``stop_fraction`` of its peak)."""

    def __init__(self, specimen, material: ModelIIDamage, solver, output, *, vtu_every: int, checkpoint_every: int,
                 stop_fraction: float | None, on_step, fingerprint: dict):
        self.specimen, self.material, self.solver = specimen, material, solver
        kin = solver.kin
        self.dx, self.scale = kin.dx, specimen.force_scale
        self.prescribed, self.loaded = solver.constraints.prescribed, specimen.loaded_dofs
        self.mesh = kin.basis.mesh
        self.out = out = Path(output) if output is not None else None
        self.writer = CurveWriter(out / "force_displacement.csv", CURVE_COLUMNS) if out is not None else None
        self.vtu = VtuSeries(out / "fields", stem="damage") if out is not None else None
        self.nodal = np.asarray(kin.basis.nodal_dofs)
        self.points = np.vstack([self.mesh.p, np.zeros((3 - self.mesh.dim(), self.mesh.p.shape[1]))]).T
        self.vtu_every, self.checkpoint_every = vtu_every, checkpoint_every
        self.stop_fraction, self.on_step, self.fingerprint = stop_fraction, on_step, fingerprint
        self.book = _Bookkeeping()
        self.t0 = _time.perf_counter()

    @property
    def checkpoint_path(self) -> Path:
        return self.out / RunWriter.CHECKPOINT

    def write_fields(self, res, step) -> None:
        if self.vtu is None:
            return
        state, dx, mesh = res.state, self.dx, self.mesh
        f_bar = element_f_bar(state, dx)
        fields = cell_fields(res.response.stress, {})
        fields.update(f_bar=f_bar, stiffness_loss=1.0 - f_bar, d_mean=element_mean(state["d"].mean(axis=-1), dx),
                      d_max=state["d"].max(axis=(1, 2)), alpha_p=element_mean(state["alpha_p"], dx),
                      psi0=element_mean(state["psi0"], dx))
        disp = np.zeros((mesh.p.shape[1], 3))
        disp[:, : self.nodal.shape[0]] = res.u[self.nodal].T
        self.vtu.write(float(step), self.points, meshio_cells(mesh), point_data={"displacement": disp},
                       cell_data={k: [np.asarray(v, dtype=float)] for k, v in fields.items()})

    def account(self, res) -> None:
        """Energies and checks of the last converged step (the first call records the start)."""
        book, material, dx, scale, prescribed = self.book, self.material, self.dx, self.scale, self.prescribed
        state, u, f_int = res.state, res.u, res.f_int
        step = len(book.rows)                    # rows[0] is the start: continued runs number on
        f_bar = f_bar_of(state)
        row = {"step": step, "load_factor": float(res.load_factors[-1]),
               "u": float(np.mean(u[self.loaded])), "F": scale * float(np.sum(f_int[self.loaded])),
               "iterations": int(res.iterations[-1]), "cutbacks": int(res.cutbacks)}
        work = 0.0
        if book.state_prev is not None:
            old = book.state_prev
            if np.any(state["d"] < old["d"]):
                raise RuntimeError("Model II: damage decreased in a converged step (irreversibility violated)")
            work = rate_limit_work(u, book.u_prev, book.f_prev, prescribed, scale)
            book.external += 0.5 * scale * float(np.dot((book.f_prev + f_int)[prescribed],
                                                        (u - book.u_prev)[prescribed]))
            # released energy, trapezoidal like W: 1/2 (f_bar^m - f_bar^{m+1}) eps_e^m : E : eps_e^{m+1}
            cross = np.einsum("...i,ij,...j->...", old["eps"] - old["eps_p"], material.stiffness,
                              state["eps"] - state["eps_p"])
            book.released += scale * float(np.sum(dx * 0.5 * (f_bar_of(old) - f_bar) * cross))
            dd = np.sum(state["d"] - old["d"], axis=-1)
            threshold = material.r_d / material.n * dd
            book.threshold += scale * float(np.sum(dx * threshold))
            book.plastic += scale * float(np.sum(dx * (state["dissipation"] - old["dissipation"] - threshold)))
        d_max = float(state["d"].max(initial=0.0))
        if d_max > material.d_max * (1 + 1e-12):
            raise RuntimeError(f"Model II: damage {d_max} above the cap d_max = {material.d_max}")
        stored = scale * float(np.sum(dx * material.stored_energy(state)))
        dissipated = book.plastic + book.released
        now = _time.perf_counter()
        row.update(external_work=book.external, rate_limit_work=work,
                   damage_increment=material.alpha * max(work, 0.0), stored_energy=stored,
                   plastic_dissipation=book.plastic, damage_dissipation=book.released,
                   threshold_dissipation=book.threshold, dissipated_energy=dissipated,
                   energy_error=book.external - stored - dissipated, max_d=d_max,
                   min_f_bar=float(f_bar.min(initial=1.0)),
                   damaged_area=scale / self.specimen.thickness * float(np.sum(dx * (f_bar <= 0.25))),
                   seconds=now - book.clock)
        book.clock = now
        book.rows.append(row)
        book.u_prev, book.f_prev, book.state_prev, book.last = u, f_int, state, res
        book.peak = max(book.peak, row["F"])
        if self.writer is not None:
            self.writer.write(**row)
        if self.vtu_every and step % self.vtu_every == 0:
            self.write_fields(res, step)

    def result(self, status, message, solve, checkpoint=None) -> ModelTwoResult:
        curves = {k: np.array([r[k] for r in self.book.rows]) for k in CURVE_COLUMNS}
        state, dx = solve.state, self.dx
        return ModelTwoResult(
            curves=curves, f_bar=element_f_bar(state, dx),
            d_mean=element_mean(state["d"].mean(axis=-1), dx), alpha_p=element_mean(state["alpha_p"], dx),
            u=solve.u, state=state, status=status, message=message, cutbacks=int(solve.cutbacks),
            wall_time=_time.perf_counter() - self.t0, alpha=float(self.material.alpha),
            elements=int(self.solver.kin.nel), output=self.out, checkpoint=checkpoint)

    def save(self, res, status="running", message="") -> Path:
        """The checkpoint: the converged state, the energy account and rows, the VTU entries, the step control."""
        book = self.book
        arrays = {"f_int": res.f_int} | continuation_arrays(res.continuation)     # f_int: also the account's
        account_ = {k: getattr(book, k) for k in ("rows", "external", "plastic", "released", "threshold", "peak")}
        control = None if res.continuation is None else res.continuation["control"]
        return save_run(self.checkpoint_path, res.u, res.state, float(res.load_factors[-1]), float(res.times[-1]),
                        fingerprint=self.fingerprint, control=control, arrays=arrays, account=account_,
                        vtu=VtuSeries.position(self.vtu), status=status, message=message)

    def after_step(self, res) -> None:
        """``on_step`` of the solver: account, checkpoint every ``checkpoint_every`` steps, the caller's
        ``on_step``, and the stop (:class:`_Stop`) once the force fell below ``stop_fraction`` of the peak."""
        self.account(res)
        book = self.book
        if self.out is not None and self.checkpoint_every and (len(book.rows) - 1) % self.checkpoint_every == 0:
            self.save(res)
        if self.on_step is not None:
            self.on_step(self.result("running", "", res))
        F = book.rows[-1]["F"]
        if self.stop_fraction is not None and len(book.rows) > 2 and F < self.stop_fraction * book.peak:
            raise _Stop()

    def load(self) -> dict | None:
        """The checkpoint of this run in ``output`` (None without one or without ``output``)."""
        if self.out is None:
            return None
        return load_run(self.checkpoint_path, self.fingerprint, "Model II run (material, steps or mesh differ)")

    def start(self, saved: dict | None) -> dict | None:
        """The account from the unloaded start, or from the checkpoint ``saved``; returns the solver's
        continuation (None from the start). ``force_displacement.csv`` is rewritten with the rows so far."""
        book, kin = self.book, self.solver.kin
        continuation = None
        if saved is None:    # the unloaded start (the solver records it but reports only converged steps)
            book.u_prev, book.f_prev = self.solver.constraints.apply(np.zeros(kin.ndof), 0.0), np.zeros(kin.ndof)
            book.rows.append({k: 0.0 for k in CURVE_COLUMNS}
                             | {"min_f_bar": 1.0, "u": float(np.mean(book.u_prev[self.loaded]))})
            book.state_prev = self.material.initial_state((kin.nel, kin.nqp))
        else:                # where the checkpoint left the run: its account, rows and output
            meta = saved["meta"]
            for name, value in meta["account"].items():
                setattr(book, name, value)
            book.u_prev, book.f_prev, book.state_prev = saved["u"], saved["arrays"]["f_int"], saved["state"]
            if self.vtu is not None:
                self.vtu.restart(meta["vtu"])
            continuation = saved["continuation"]
        if self.writer is not None:
            self.writer.rewrite(book.rows)
        book.clock = _time.perf_counter()
        return continuation

    def close(self) -> None:
        if self.writer is not None:
            self.writer.close()

    def stored(self, saved: dict) -> ModelTwoResult:
        """A finished run's result from its checkpoint, nothing recomputed."""
        self.start(saved)
        self.close()
        solve = SimpleNamespace(u=saved["u"], state=saved["state"], cutbacks=int(self.book.rows[-1]["cutbacks"]))
        return self.result(saved["meta"]["status"], saved["meta"]["message"], solve, self.checkpoint_path)

    def finish(self, status: str, message: str, solve) -> ModelTwoResult:
        """The result; with ``output`` the last fields, the final checkpoint and ``summary.json``."""
        book, checkpoint = self.book, None
        if book.last is None:  # not even the first step converged: the last good state is the start
            book.last = solve
        if self.out is not None:
            if not self.vtu_every or (len(book.rows) - 1) % self.vtu_every:
                self.write_fields(book.last, len(book.rows) - 1)
            checkpoint = self.save(book.last, status, message)
        res = self.result(status, message, solve if status != "fractured" else book.last, checkpoint)
        if self.out is not None:
            write_json(self.out / "summary.json", {"specimen": self.specimen.summary(), **res.summary()})
        return res


def run_model_two(specimen, alpha: float = 0.05, *, material: ModelIIDamage | None = None, steps: int = 200,
                  end: float = 1.0, stop_fraction: float | None = None, output: str | Path | None = None,
                  vtu_every: int = 0, control=None, newton=None, linear_solver="auto", progress: bool = False,
                  on_step: Callable[[ModelTwoResult], None] | None = None, path=None,
                  method: str = "dissipation", rate_limit: str = "iterate", checkpoint_every: int = 10,
                  resume: bool = False) -> ModelTwoResult:
    """Load ``specimen`` (:mod:`abrakit.damage.specimens`) with Model II: Algorithm 2 at every quadrature point.

    Parameters
    ----------
    specimen : a :class:`~abrakit.damage.specimens.DamageSpecimen` (mesh, basis, Dirichlet conditions, loaded edge).
    alpha : rate-limit factor (1/(N mm)): Table 7.2 uses 0.05 (almost local) and 0.005 (regularised).
    material : a :class:`ModelIIDamage`; default :func:`default_material` (Table 7.2 with ``alpha``).
    steps : number of equal load steps from 0 to ``end`` (load factor; 1 = ``specimen.displacement``).
    stop_fraction : stop once the force has fallen below this fraction of its peak after the peak.
    output : directory for the curves, VTU fields (every ``vtu_every`` steps, 0: last step only), summary and
        checkpoint; ``None`` writes nothing.
    on_step : called with the partial result after every converged step.
    path, method, rate_limit : path following (a :class:`~abrakit.fem.PathControl` and the constraint method of
        :class:`~abrakit.fem.PathFollowingSolver`) instead of ``steps`` equal displacement increments; see
        :func:`model_two_solver` for the rate limit under path following.
    checkpoint_every, resume : with ``output``, ``last_converged.npz`` is also written every ``checkpoint_every``
        converged steps (0: only at the end) with the energy account, the rows and the solver's step control;
        ``resume=True`` continues a killed run from it (``force_displacement.csv`` and the VTU series rewound), and
        a finished run's rerun returns its result at once. Displacement control only (``path=None``).
    """
    material = default_material(alpha) if material is None else material
    check_positive("end", end)
    if stop_fraction is not None:
        check_range("stop_fraction", stop_fraction, 0.0, 1.0, low_open=True, high_open=True)
    vtu_every = int(check_range("vtu_every", vtu_every, 0, None))
    check_range("checkpoint_every", checkpoint_every, 0, None)
    if resume and path is not None:
        raise ValueError("resume: run_model_two resumes displacement-controlled runs only (path=None); a "
                         "path-followed run resumes through PathFollowingSolver.run(output=..., resume=True)")
    solver = model_two_solver(specimen.basis, material, specimen.dirichlet, force_scale=specimen.force_scale,
                              steps=steps, control=control, newton=newton, linear_solver=linear_solver, end=end,
                              path=path, method=method, rate_limit=rate_limit)
    fingerprint = {"material": repr(material), "steps": steps, "end": end, "dofs": int(solver.kin.ndof),
                   "elements": int(solver.kin.nel)}
    run = _ModelTwoRun(specimen, material, solver, output, vtu_every=vtu_every, checkpoint_every=checkpoint_every,
                       stop_fraction=stop_fraction, on_step=on_step, fingerprint=fingerprint)
    saved = run.load() if resume else None
    if saved is not None and saved["meta"]["status"] != "running":   # a finished run: its result at once
        return run.stored(saved)
    continuation = run.start(saved)
    status, message = "end", ""
    try:
        resumed = {} if continuation is None else {"continuation": continuation}      # from the checkpoint
        solve = solver.run(end=end, progress=progress, on_step=run.after_step, output=None, **resumed)
    except _Stop:
        solve, status = run.book.last, "fractured"
        rows, peak = run.book.rows, run.book.peak
        message = (f"stopped at u = {rows[-1]['u']:.4g} mm: the force {rows[-1]['F']:.4g} N fell below "
                   f"{stop_fraction:g} of the peak {peak:.4g} N")
    except StepFailed as failure:
        solve, status = failure.result, "failed"
        message = (f"Model II run stopped at load factor {failure.load_factor:.6g} "
                   f"(u = {run.book.rows[-1]['u']:.4g} mm): {failure.reason}; the load step could not be completed "
                   f"even when cut back to {solver.control.minimum:.3g}. The result and "
                   f"{RunWriter.CHECKPOINT if run.out else 'result.state'} hold the last converged state.")
        warnings.warn(message, RuntimeWarning, stacklevel=2)
    finally:
        run.close()
    return run.finish(status, message, solve)
