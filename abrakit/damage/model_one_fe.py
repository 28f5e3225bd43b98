r"""Model I in the finite element loop: Algorithm 1 of the seed on :class:`abrakit.fem.Solver` (Ch. 6.4.1).

Every load step m -> m+1 has two stages (the *operator split* of Eq. 6.62/6.63):

1. **Displacements.** Newton iterations for ``R_u = 0`` (6.58) with the damage function of the last step frozen:
   the stress is ``f^m E : (eps^{m+1} - eps_p^{m+1})`` (6.62) and the material tangent ``f^m E`` (6.63)
   (``ModelIDamage(tangent="operator_split")``) or its plastic correction (``tangent="consistent"``; same
   converged answer, fewer iterations while plastic flow is active). The material is called with
   ``damage=False``.
2. **Damage, after convergence.** One damage function ``f_i`` per element, at its centre. The driving energy
   is the element mean of Psi0+ over the quadrature points, ``Psibar0_i = int_e Psi0+ dV / V_e``; the Laplacian
   ``Lambda_f = L f`` (6.74) and its derivative ``D Lambda_f = diag L`` (6.75) come from the Taylor stencil
   precomputed once per mesh (:func:`abrakit.damage.element_laplacian`, Neumann condition 6.44 by mirrored
   ghosts). Where the indicator ``Phi_d,i = f_i Psibar0_i - beta f_i Lambda_f,i - r_d`` (6.64, 6.76) is positive,
   f falls until it is zero; ``f`` never grows (no healing) and stays in ``[f_min, 1]``.

   ``damage_scheme="seed"`` is Algorithm 1 as printed: ``Lambda_f`` from the old field ``f^m`` and the Newton
   update (6.77) of each element's own f (iterated to its root by :meth:`ModelIDamage.update_damage`), i.e. one
   Jacobi sweep of the coupled problem per load step. The neighbours then lag behind by a relative amount of
   order ``beta / (Psibar0 h^2)`` per step, so the damage trails the load on fine meshes and the results depend on
   the mesh *and* the step (a 41-element bar with beta = 1 peaks 34 % high at 1 % load steps, 13 % at 0.25 %).
   ``damage_scheme="coupled"`` (default) solves the indicators of all elements together
   (:func:`coupled_damage_function`): the converged limit of the seed's update, independent of the step.

Because stage 2 is explicit, a step may change f a lot. A step in which the damage variable ``d = -ln f`` of
some element grows by more than ``max_dd`` is rejected and retried with a smaller load increment (the solver's
cutback); explicit damage growth shrinks with the increment. Where it does not (cutting the increment back did
not halve it), or the increment is down to ``jump_step``, the structure has reached a snap-back or a sudden
force drop: with ``snap_back="pass"`` the step is accepted -- the force drops at practically constant
displacement, as a displacement-controlled test shows it -- and counted in ``result.jumps``; with
``snap_back="stop"`` the run stops with a message, the converged steps are kept in the result and the last
converged state is saved to ``<output>/last_converged.npz``.

Energy bookkeeping per converged step (N mm, or N mm per mm of thickness in plane strain):

- external work ``W = sum_steps 1/2 (F^m + F^{m+1}) . (u^{m+1} - u^m)`` over the prescribed DOFs (reactions) and
  any external force;
- stored energy ``int (f Psi0 + 1/2 K_H alpha_p^2) dV + int beta/2 |grad f|^2 dV`` (6.23, 6.24), the gradient from
  the same Taylor stencil;
- dissipated energy ``int (r_p sum |d eps_p| + r_d d) dV`` (6.25).

``energy_error = W - stored - dissipated`` is O(load step) on smooth stretches (the split evaluates the stress of
a step with ``f^m``); in a sudden drop it jumps by the elastic energy released at fixed displacement, which a
quasi-static model cannot dissipate (in a test it becomes kinetic energy). With the tension split (6.56) and
compressive principal strains the released ``f (Psi0 - Psi0+) dd`` is not dissipated by ``r_d dd`` either: the
seed's model is not energy-consistent there.

Units: N, mm, MPa; ``beta`` in MPa mm^2.
"""

from __future__ import annotations

import time as _time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ..fem.kinematics import element_mean
from ..fem.solver import NewtonFailure, NewtonResult, Solver, StepContext, StepFailed
from ..io import CurveWriter, write_json
from ..materials.model_one import damage_function_update
from ..validation import check_finite, check_option, check_positive, check_range, number_arguments
from .laplacian import ElementLaplacian, element_laplacian

SNAP_BACK = ("pass", "stop")
DAMAGE_SCHEMES = ("seed", "coupled")


def element_damage_function(state: dict) -> np.ndarray:
    """Element damage function ``f_i = exp(-d_i)`` (Eq. 6.11) of a Model I state whose ``d`` is ``(nel, nqp)``."""
    return np.exp(-state["d"][:, 0])


@lru_cache(maxsize=8)
def _jacobian_pattern(laplacian: ElementLaplacian):
    """CSR pattern of L plus its diagonal, the row of every entry, the diagonal positions and L on the pattern."""
    import scipy.sparse as sp

    L = laplacian.matrix.tocsr()
    pattern = (abs(L) + sp.eye(L.shape[0], format="csr")).tocsr()
    pattern.sort_indices()
    row = np.repeat(np.arange(L.shape[0]), np.diff(pattern.indptr))
    values = np.asarray(L[row, pattern.indices]).ravel()
    return pattern, row, np.flatnonzero(row == pattern.indices), values


#: Generalised derivative of the Fischer-Burmeister function at a = b = 0.
FB_CORNER = 1.0 - np.sqrt(0.5)


def _fischer_burmeister(f: np.ndarray, f_old: np.ndarray, phi: np.ndarray, r_d: float, f_min: float,
                       mu: float = 0.0):
    """The complementarity of Eq. (6.64) per element, ``H_i = a_i + b_i - sqrt(a_i^2 + b_i^2 + 2 mu^2)`` with
    ``a = f_old - f`` (room left below the old value) and ``b = -Phi_d / r_d``, and its partial derivatives
    ``(H, c_a, c_b)``: ``dH = -c_a df - c_b / r_d dPhi_d``. With ``mu = 0``, ``H = 0`` iff ``a >= 0, b >= 0,
    a b = 0``; a smoothing ``mu > 0`` makes H differentiable at ``a = b = 0`` and its root ``a, b > 0, a b = mu^2``
    (Kanzow 1996). At the floor ``f = f_min`` with ``Phi_d > 0`` the lower bound is active, ``H = 0`` and the row
    reads ``df = 0`` (``c_a = 1``, ``c_b = 0``)."""
    a, b = f_old - f, -phi / r_d
    rho = np.sqrt(a * a + b * b + 2.0 * mu * mu)
    H = a + b - rho
    safe = np.where(rho > 0.0, rho, 1.0)
    c_a = np.where(rho > 0.0, 1.0 - a / safe, FB_CORNER)
    c_b = np.where(rho > 0.0, 1.0 - b / safe, FB_CORNER)
    floor = (f <= f_min) & (b < 0.0)
    H[floor], c_a[floor], c_b[floor] = 0.0, 1.0, 0.0
    return H, c_a, c_b


def indicator_jacobian_values(f: np.ndarray, psi0_bar: np.ndarray, laplacian: ElementLaplacian,
                              beta: float) -> np.ndarray:
    """``d Phi_d / d f = diag(Psibar0 - beta L f) - beta diag(f) L`` of Eq. (6.76) at fixed ``Psibar0``, as values
    on the pattern of :func:`_jacobian_pattern` (L plus its diagonal)."""
    _, row, diagonal, L_data = _jacobian_pattern(laplacian)
    values = -beta * f[row] * L_data
    values[diagonal] += psi0_bar - beta * (laplacian.matrix @ f)
    return values


def coupled_damage_function(f_old, psi0_bar, laplacian: ElementLaplacian, beta: float, r_d: float,
                            f_min: float, *, f_start=None, tol: float = 1e-9, max_iterations: int = 60
                            ) -> tuple[np.ndarray, int]:
    """Element damage functions solving the indicator of *all* elements at once, Eq. (6.64)/(6.76) (``"coupled"``).

    Finds ``f`` in ``[f_min, f_old]`` such that, element by element, either ``f_i = f_old_i`` and
    ``Phi_d,i(f) <= 0``, or ``Phi_d,i(f) = 0``, or ``f_i = f_min`` and ``Phi_d,i(f) >= 0``, where
    ``Phi_d,i(f) = f_i (Psibar0_i - beta (L f)_i) - r_d`` (MPa) couples the neighbours through the Laplacian
    ``L f`` (6.74). This complementarity problem is written with the
    Fischer-Burmeister function, ``H_i = a_i + b_i - sqrt(a_i^2 + b_i^2) = 0`` with ``a = f_old - f`` and
    ``b = -Phi_d / r_d``, and solved by Newton's method with an Armijo line search on ``|H|^2 / 2``; the Jacobian
    of ``Phi_d`` is ``diag(Psibar0 - beta L f) - beta diag(f) L``. (A plain active-set Newton cycles where many
    elements sit on the damage surface at once, e.g. a uniformly softening bar.)

    The seed's update (6.77) is the first Newton step of one element with its neighbours frozen; this is the
    converged, coupled limit. ``f_start``: initial guess in ``[f_min, f_old]`` (default ``f_old``). Returns
    ``(f, iterations)``; raises ``RuntimeError`` if ``max |H| <= tol`` is not reached.
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    check_positive("r_d", r_d)
    check_positive("beta", beta, allow_zero=True)
    check_range("f_min", f_min, 0.0, 1.0, low_open=True)
    check_positive("tol", tol)
    check_range("max_iterations", max_iterations, 1, None)
    if not isinstance(laplacian, ElementLaplacian):
        raise TypeError(f"laplacian must be an ElementLaplacian, got {type(laplacian).__name__}")
    f_old = check_range("f_old", f_old, 0.0, 1.0, low_open=True)
    f_old = np.atleast_1d(f_old)
    psi0_bar = check_finite("psi0_bar", psi0_bar)
    if np.shape(psi0_bar) not in ((), f_old.shape) or f_old.shape != (laplacian.matrix.shape[0],):
        raise ValueError(f"f_old {f_old.shape} and psi0_bar {np.shape(psi0_bar)} must have one value per element "
                         f"of the Laplacian ({laplacian.matrix.shape[0]})")
    L = laplacian.matrix
    n = f_old.size
    pattern, row, diagonal, _ = _jacobian_pattern(laplacian)

    def residual(f):
        return _fischer_burmeister(f, f_old, f * (psi0_bar - beta * (L @ f)) - r_d, r_d, f_min)

    f = f_old.copy() if f_start is None else np.clip(f_start, f_min, f_old)
    H, c_a, c_b = residual(f)
    error = float(np.max(np.abs(H), initial=0.0))
    for iteration in range(max_iterations + 1):
        if error <= tol:
            return f, iteration
        if iteration == max_iterations:
            break
        # dH/df = -diag(c_a) - diag(c_b / r_d) dPhi_d/df
        values = -(c_b / r_d)[row] * indicator_jacobian_values(f, psi0_bar, laplacian, beta)
        values[diagonal] -= c_a
        # rows with c_b = 0 (f = f_old, Phi_d < 0: outside the damage zone) read -step_i = -H_i = 0; solve the rest
        zone = (c_b != 0.0) | (H != 0.0)
        index = np.cumsum(zone) - 1
        keep = zone[row] & zone[pattern.indices]
        jacobian = sp.csc_matrix((values[keep], (index[row[keep]], index[pattern.indices[keep]])),
                                 shape=(int(zone.sum()),) * 2)
        step = np.zeros(n)
        step[zone] = spla.spsolve(jacobian, -H[zone]) if zone.sum() > 1 else -H[zone] / jacobian.toarray().ravel()
        merit, t = 0.5 * float(H @ H), 1.0
        while True:  # Armijo on |H|^2 / 2, whose slope along the Newton step is -|H|^2
            trial = np.clip(f + t * step, f_min, f_old)
            H_trial, c_a_trial, c_b_trial = residual(trial)
            if 0.5 * float(H_trial @ H_trial) <= (1.0 - 2e-4 * t) * merit or t < 1e-6:
                break
            t *= 0.5
        f, H, c_a, c_b = trial, H_trial, c_a_trial, c_b_trial
        error = float(np.max(np.abs(H), initial=0.0))
    raise RuntimeError(f"coupled damage update did not converge in {max_iterations} Newton iterations "
                       f"(max |H| = {error:.3e})")


def damage_update(material, state: dict, dx: np.ndarray, laplacian: ElementLaplacian | None,
                  scheme: str = "seed") -> dict:
    """Stage 2 of Algorithm 1 on a converged step: element-wise damage update, Eq. (6.64), (6.74)-(6.77).

    ``state`` comes from ``material.update(..., damage=False)`` with ``d`` constant over each element's points;
    ``dx`` are the quadrature weights ``(nel, nqp)`` (mm^dim). ``scheme="seed"``: Algorithm 1 as printed, the
    Laplacian ``Lambda_f`` from the old field ``f^m`` and the element's own Newton update (6.77) (solved to its
    root by :meth:`ModelIDamage.update_damage`); ``"coupled"``: the neighbours' values are the new ones too
    (:func:`coupled_damage_function`). Returns a new state (``d``, ``dissipation`` updated) with the element fields
    ``f`` and ``laplacian`` (the Lambda_f used, 1/mm^2) stored per point.
    """
    check_option("scheme", scheme, DAMAGE_SCHEMES)
    f_old = element_damage_function(state)
    psi0_bar = element_mean(state["psi0"], dx)
    zeros = np.zeros_like(f_old)
    if laplacian is None or material.beta == 0.0:
        lap, lap_derivative = zeros, zeros
    elif scheme == "seed":
        lap, lap_derivative = laplacian(f_old), laplacian.diagonal
    else:
        f_seed = damage_function_update(f_old, psi0_bar, laplacian(f_old), laplacian.diagonal, material.beta,
                                        material.r_d, material.f_min)
        f_new, _ = coupled_damage_function(f_old, psi0_bar, laplacian, material.beta, material.r_d,
                                                    material.f_min, f_start=f_seed)
        lap_derivative = laplacian.diagonal
        # Lambda_f with the neighbours at their new values, linearised in the own value about f^m (6.75):
        lap = laplacian(f_new) - lap_derivative * (f_new - f_old)
    new = material.update_damage(state, psi0_bar=psi0_bar[:, None], laplacian=lap[:, None],
                                 laplacian_derivative=lap_derivative[:, None])
    nqp = dx.shape[1]
    new["f"] = np.repeat(np.exp(-new["d"][:, :1]), nqp, axis=1)
    new["laplacian"] = np.repeat(lap[:, None], nqp, axis=1)
    return new


@number_arguments
def gradient_energy(f: ArrayLike, volumes: ArrayLike, laplacian: ElementLaplacian | None, beta: float) -> float:
    """``int beta/2 |grad f|^2 dV`` (6.24) with the stencil's reconstructed gradient at the element centres (N mm)."""
    if laplacian is None or beta == 0.0:
        return 0.0
    grad = laplacian.gradient(f)
    return float(0.5 * beta * np.sum(volumes * np.sum(grad**2, axis=1)))


def model_one_energies(model, state: dict, dx: np.ndarray, laplacian: ElementLaplacian | None,
                       external: float) -> dict:
    """Stored, dissipated energy and the balance error of Eq. (6.23)-(6.25), integrated over the mesh (N mm):
    ``external_work``, ``stored_energy`` (gradient included), ``gradient_energy``, ``dissipated_energy``,
    ``damage_dissipation``, ``plastic_dissipation`` and ``energy_error`` = external - stored - dissipated."""
    stored = float(np.sum(dx * model.stored_energy(state)))
    gradient = gradient_energy(element_damage_function(state), dx.sum(axis=1), laplacian, model.beta)
    dissipated = float(np.sum(dx * model.dissipation(state)))
    damage = float(np.sum(dx * model.r_d * state["d"]))
    return {"external_work": external, "stored_energy": stored + gradient, "gradient_energy": gradient,
            "dissipated_energy": dissipated, "damage_dissipation": damage,
            "plastic_dissipation": dissipated - damage, "energy_error": external - stored - gradient - dissipated}


def check_model_one_material(material) -> None:
    """Raise ``TypeError`` unless ``material`` offers what the Model I solvers call (a ModelIDamage does)."""
    for attribute in ("update_damage", "beta", "r_d", "stored_energy", "dissipation"):
        if not hasattr(material, attribute):
            raise TypeError(f"material must be a Model I material (abrakit.materials.ModelIDamage), got "
                            f"{type(material).__name__} without {attribute!r}")


def mesh_laplacian(kin, material, laplacian: ElementLaplacian | None = None) -> ElementLaplacian | None:
    """The element Laplacian of ``kin``'s mesh: ``laplacian`` checked against the element count, or built when
    the material has ``beta > 0`` (``None`` for a local model)."""
    if laplacian is None and material.beta > 0.0:
        laplacian = element_laplacian(kin.basis.mesh)
    if laplacian is not None and laplacian.matrix.shape[0] != kin.nel:
        raise ValueError(f"laplacian: built for {laplacian.matrix.shape[0]} elements, the mesh has {kin.nel}")
    return laplacian


@dataclass
class ModelIResult:
    """History of a Model I run; one entry per converged step in ``curves`` (index 0: the start).

    ``curves``: ``step``, ``load_factor``, ``u_<name>``, ``F_<name>`` (every monitor of the solver; N, mm),
    ``external_work``, ``stored_energy``, ``gradient_energy``, ``dissipated_energy``, ``damage_dissipation``,
    ``plastic_dissipation``, ``energy_error`` (= external - stored - dissipated) (N mm), ``min_f``, ``max_dd``
    (largest drop of f in the step), ``jump`` (1 where a step was accepted as a snap-back/sudden drop),
    ``iterations``. Final fields per element: ``f``, ``alpha_p`` (element mean), ``laplacian``.
    ``completed`` is False when the run stopped early; ``message`` then says why.
    """

    curves: dict[str, np.ndarray]
    f: np.ndarray
    alpha_p: np.ndarray
    u: np.ndarray
    state: dict
    completed: bool
    message: str
    cutbacks: int
    jumps: int
    wall_time: float
    output: Path | None
    laplacian: ElementLaplacian | None = None
    solve: object = None

    @property
    def d(self) -> np.ndarray:
        """Element damage variable ``d = -ln f``."""
        return -np.log(self.f)

    @property
    def load_factors(self) -> np.ndarray:
        return self.curves["load_factor"]

    def peak(self, name: str) -> tuple[float, float]:
        """``(F_max, u at F_max)`` of the monitor ``name`` (N, mm)."""
        F, u = self.curves[f"F_{name}"], self.curves[f"u_{name}"]
        i = int(np.argmax(F))
        return float(F[i]), float(u[i])


@dataclass(frozen=True)
class FrozenDamage:
    """Stage 1 of Algorithm 1: the Model I material with its damage function frozen at ``f^m`` (6.62, 6.63)."""

    material: object

    def initial_state(self, shape: tuple[int, ...]) -> dict[str, np.ndarray]:
        """The material's start state plus the element fields ``f = 1`` and ``laplacian = 0`` (for the output)."""
        state = self.material.initial_state(shape)
        state["f"], state["laplacian"] = np.ones(shape), np.zeros(shape)
        return state

    def update(self, state, eps, dt: float = 1.0, **loading):
        return self.material.update(state, eps, dt, damage=False, **loading)


@dataclass
class _Step:
    """What stage 2 of the last accepted step did (read by the run loop after the solver records the step)."""

    max_dd: float = 0.0
    jump: bool = False


ENERGY_COLUMNS = ("external_work", "stored_energy", "gradient_energy", "dissipated_energy", "damage_dissipation",
                  "plastic_dissipation", "energy_error")


class ModelISolver(Solver):
    """Algorithm 1 (Model I) on :class:`abrakit.fem.Solver`: Newton with f frozen, then the element damage step.

    Besides the keyword options of :class:`abrakit.fem.Solver` (``external_force``, ``loading``, ``extra_terms``,
    ``monitors``, ``control``, ``newton``, ``linear_solver``, ``duration``, ``bbar``):

    Parameters
    ----------
    basis : vector basis of a ``MeshQuad``/``MeshTri`` (plane strain) or ``MeshHex``/``MeshTet`` mesh.
    material : :class:`abrakit.materials.ModelIDamage` (or any object with its ``update(..., damage=False)``,
        ``update_damage``, ``beta``, ``r_d``, ``stored_energy`` and ``dissipation``).
    dirichlet : prescribed displacements; a named one is recorded as ``u_<name>`` / ``F_<name>``.
    max_dd : largest growth of the damage variable ``d = -ln f`` of an element in one step (> 0; 0.25 = the
        stiffness falls by at most 22 %); a step with more is retried with a smaller load increment.
    snap_back : ``"pass"``: accept an unavoidable large growth (a snap-back / sudden force drop, see the module
        docstring); ``"stop"``: end the run there (``result.completed = False``, last state saved with ``output``).
    jump_step : load-factor increment at which a large growth is always accepted; default and smallest value
        ``control.minimum / control.cutback`` (every cutback sequence passes through it before giving up).
    damage_scheme : ``"coupled"`` (default) or ``"seed"`` (Algorithm 1 as printed), see the module docstring.
    laplacian : precomputed :class:`ElementLaplacian` of the mesh (built here when ``beta > 0`` and not given).
    """

    def __init__(self, basis, material, dirichlet: Sequence = (), *, max_dd: float = 0.25, snap_back: str = "pass",
                 jump_step: float | None = None, damage_scheme: str = "coupled",
                 laplacian: ElementLaplacian | None = None, **solver_options):
        check_model_one_material(material)
        super().__init__(basis, FrozenDamage(material), dirichlet, **solver_options)
        self.model = material
        self.max_dd = check_range("max_dd", max_dd, 0.0, None, low_open=True)
        self.snap_back = check_option("snap_back", snap_back, SNAP_BACK)
        self.damage_scheme = check_option("damage_scheme", damage_scheme, DAMAGE_SCHEMES)
        floor = self.control.minimum / self.control.cutback
        self.jump_step = floor if jump_step is None else check_range("jump_step", jump_step, floor, None)
        self.laplacian = mesh_laplacian(self.kin, material, laplacian)
        self._step, self._rejected = _Step(), None

    # ---- one load step of Algorithm 1 ----------------------------------------------------------------------------
    def newton(self, u_trial, state_old, ctx: StepContext, lift=None) -> NewtonResult:
        """Stage 1 (Newton iterations, f frozen), then stage 2 (damage update); reject too large drops of f."""
        res = super().newton(u_trial, state_old, ctx, lift=lift)
        try:
            state = damage_update(self.model, res.response.state, self.kin.dx, self.laplacian, self.damage_scheme)
        except RuntimeError as exc:
            raise NewtonFailure(str(exc), res.residuals) from exc
        max_dd = float(np.max(state["d"][:, 0] - state_old["d"][:, 0], initial=0.0))
        jump = max_dd > self.max_dd
        start = ctx.load_factor - ctx.delta
        if jump and not self._accept_jump(start, ctx.delta, max_dd):
            self._rejected = (start, ctx.delta, max_dd)
            raise NewtonFailure(f"the damage variable grew by {max_dd:.3g} in one step (max_dd = "
                                f"{self.max_dd:.3g}): a snap-back or sudden force drop", res.residuals)
        self._step, self._rejected = _Step(max_dd, jump), None
        return replace(res, response=replace(res.response, state=state))

    def _accept_jump(self, start: float, delta: float, max_dd: float) -> bool:
        """A large damage increment that does not shrink with the load increment is a snap-back: pass it.

        Explicit damage grows in proportion to a small load increment; if cutting the increment back did not
        (at least) halve the growth, or the increment is already at ``jump_step``, the drop is accepted.
        """
        if self.snap_back == "stop":
            return False
        if delta <= self.jump_step * (1.0 + 1e-9):
            return True
        previous = self._rejected
        if previous is None or abs(previous[0] - start) > 1e-12 * max(1.0, abs(start)) or previous[1] <= delta:
            return False
        return max_dd > 0.5 * previous[2]

    # ---- the load path ---------------------------------------------------------------------------------------------
    def run(self, *, end: float = 1.0, output: str | Path | None = None, vtu_every: int = 1, progress: bool = False,
            on_step: Callable[[ModelIResult], None] | None = None) -> ModelIResult:
        """Follow the load path 0 -> ``end``; returns a :class:`ModelIResult`, also when the run stopped early.

        ``output``: directory for the solver's ``curves.csv`` and ``fields/step.pvd`` (cell fields ``d``, ``f``,
        ``alpha_p``, ``psi0``, ``laplacian``, stresses, ...), ``model_one.csv`` (curves and energies, one row per
        converged step, written as the run goes), ``summary.json`` and ``last_converged.npz`` (the solver's
        checkpoint, every 10 steps, at the end and when the run stops).
        ``on_step(result)`` is called after every converged step with the partial result.
        """
        t0 = _time.perf_counter()
        columns = ["step", "load_factor"] + [f"{k}_{n}" for n in self.monitors for k in ("u", "F")]
        columns += [*ENERGY_COLUMNS, "min_f", "max_dd", "jump", "iterations"]
        writer = CurveWriter(Path(output) / "model_one.csv", columns) if output is not None else None
        prescribed = self.constraints.prescribed
        state = self.material.initial_state((self.kin.nel, self.kin.nqp))
        u = self.constraints.apply(np.zeros(self.kin.ndof), 0.0)
        last = {"u": u, "f_int": np.zeros(self.kin.ndof), "f_ext": self._external(0.0), "work": 0.0}
        rows = []

        def record(step, lam, u, state, iterations):
            row = {"step": step, "load_factor": lam, "iterations": iterations,
                   "min_f": float(state["f"].min()), "max_dd": self._step.max_dd, "jump": int(self._step.jump)}
            for name, dofs in self.monitors.items():
                row[f"u_{name}"] = float(np.mean(u[dofs])) if dofs.size else 0.0
                row[f"F_{name}"] = float(np.sum(last["f_int"][dofs]))
            row.update(self._energies(state, last["work"]))
            rows.append(row)
            if writer is not None:
                writer.write(**{k: row[k] for k in columns})

        def after_step(res):
            lam = float(res.load_factors[-1])
            f_ext = self._external(lam)
            du = res.u - last["u"]
            last["work"] += 0.5 * float((last["f_int"] + res.f_int)[prescribed] @ du[prescribed])
            if f_ext is not None:
                last["work"] += 0.5 * float((last["f_ext"] + f_ext) @ du)
            last.update(u=res.u, f_int=res.f_int, f_ext=f_ext)
            record(len(res.load_factors) - 1, lam, res.u, res.state, int(res.iterations[-1]))
            if on_step is not None:
                on_step(self._result(res, rows, True, "", t0))

        self._step, self._rejected = _Step(), None
        record(0, 0.0, u, state, 0)
        completed, message = True, ""
        try:
            solve = super().run(end=end, state0=state, output=output, vtu_every=vtu_every, progress=progress,
                                on_step=after_step)
        except StepFailed as failure:
            completed, solve = False, failure.result
            message = f"Model I run stopped at load factor {failure.load_factor:.6g}: {failure}"
            warnings.warn(message, RuntimeWarning, stacklevel=2)
        finally:
            if writer is not None:
                writer.close()
        result = self._result(solve, rows, completed, message, t0)
        if output is not None:
            write_json(Path(output) / "summary.json", self._summary(result))
        return result

    # ---- bookkeeping -------------------------------------------------------------------------------------------------
    def _external(self, lam: float):
        return None if self.external_force is None else np.asarray(self.external_force(lam), dtype=float)

    def _energies(self, state: dict, external: float) -> dict:
        return model_one_energies(self.model, state, self.kin.dx, self.laplacian, external)

    def _result(self, solve, rows, completed: bool, message: str, t0: float) -> ModelIResult:
        curves = {k: np.array([r[k] for r in rows]) for k in rows[0]}
        state = solve.state
        return ModelIResult(
            curves=curves, f=state["f"][:, 0].copy(), alpha_p=element_mean(state["alpha_p"], self.kin.dx),
            u=solve.u, state=state, completed=completed, message=message, cutbacks=solve.cutbacks,
            jumps=int(curves["jump"].sum()), wall_time=_time.perf_counter() - t0, output=solve.output,
            laplacian=self.laplacian, solve=solve)

    def _summary(self, result: ModelIResult) -> dict:
        c = result.curves
        out = {"completed": result.completed, "message": result.message, "steps": len(c["step"]) - 1,
               "cutbacks": result.cutbacks, "jumps": result.jumps, "wall_time_s": result.wall_time,
               "elements": self.kin.nel, "beta": self.model.beta}
        out.update({k: float(c[k][-1]) for k in ENERGY_COLUMNS})
        for name in self.monitors:
            out[f"peak_F_{name}"], out[f"u_at_peak_{name}"] = result.peak(name)
        return out


def solve_model_one(basis, material, dirichlet: Sequence = (), *, end: float = 1.0, output=None,
                    vtu_every: int = 1, progress: bool = False, **options) -> ModelIResult:
    """One-call form: ``ModelISolver(basis, material, dirichlet, **options).run(end=..., output=...)``."""
    return ModelISolver(basis, material, dirichlet, **options).run(end=end, output=output, vtu_every=vtu_every,
                                                                   progress=progress)
