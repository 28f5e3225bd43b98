r"""Localisation and regularisation (Ch. 6.2): a bar with a weak spot, pulled under displacement control.

A local softening model leaves the width of the softening zone to the mesh: the strain localises into a single
element, so refining the mesh shrinks the zone, the energy dissipated to break the bar tends to zero and the
post-peak branch steepens (seed Ch. 6.2: "a crack whose formation requires no energy"). A regularised model
fixes the width by a material parameter, and the answers converge.

**The bar.** ``length`` (mm) along x, cross-section ``area`` (mm^2), ``n_elements`` square bilinear elements in
one row (a 2D plane-strain strip one element high, through :mod:`abrakit.fem`) with ``nu = 0``, so every element
is in uniaxial stress and strain exactly as in a 1D bar. The cross-section enters through the quadrature weights
(``dx -> dx * A a(x) / h``): forces come out in N, energies in N mm. The weak spot is a reduction of the
cross-section, ``a(x) = 1 - depth * exp(-(x - L/2)^2 / (2 width^2))``, averaged over each element, minus
``notch`` in the single centre element: the smooth part is the same imperfection on every mesh (what a
regularised model sees), the centre element breaks the tie so that a local model localises in one element.
Left end fixed in x, the bottom edge in y, the right end pulled to ``end_displacement``.

**Models.** ``"local"``: Model I with ``beta = 0`` (the seed's local limit, Eq. 6.24); ``"model_one"``: Model I
with ``beta = 1`` MPa mm^2 (Table 7.1, strong regularisation) through :class:`~abrakit.damage.model_one_fe.ModelISolver`
(coupled damage update); ``"model_two"``: Model II (ERVE, Table 7.2 ``r_d``, ``n``) at the material level, the
rate limit fed with the external work of each step, ``Delta W = Delta u . F^m`` (Eq. 6.97, 6.103). All without
plasticity (``r_p = None``) so that the only softening is damage. Any other material can be passed as well.

Units: N, mm, MPa; energies N mm.
"""

from __future__ import annotations

import time as _time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import skfem

from ..fem import Dirichlet, Kinematics, NewtonOptions, PathControl, Solver, StepControl, vector_basis
from ..fem.boundary import node_row_dofs
from ..materials import TABLE_7_1, TABLE_7_2, ModelIDamage, ModelIIDamage
from ..validation import check_positive, check_range, number_arguments
from .metrics import path_work
from .model_one_fe import ModelISolver
from .model_one_path import ModelIPathFollowingSolver

#: Young's modulus (MPa) of Tables 7.1/7.2; nu = 0 makes the strip a 1D bar.
E_BAR = TABLE_7_1["E"]


def bar_models(beta: float = 1.0, alpha: float = 0.01) -> dict:
    """The three materials of the study: local Model I, regularised Model I (``beta``, MPa mm^2), Model II.

    ``alpha`` (1/(N mm)) is Model II's rate limit for this bar: the seed's 0.05/0.005 refer to specimens whose
    external work is ~100x larger, and the limit scales with the work of the whole body (Eq. 6.98).
    """
    return {
        "local": ModelIDamage(E_BAR, 0.0, TABLE_7_1["r_d"], beta=0.0),
        "model_one": ModelIDamage(E_BAR, 0.0, TABLE_7_1["r_d"], beta=beta),
        "model_two": ModelIIDamage(E_BAR, 0.0, TABLE_7_2["r_d"], n=TABLE_7_2["n"], alpha=alpha),
    }


@number_arguments
def bar_mesh(n_elements: int, length: float = 20.0) -> skfem.MeshQuad:
    """One row of ``n_elements`` square quadrilaterals on [0, length] x [0, h]; boundaries left, right, bottom."""
    if isinstance(n_elements, bool) or int(n_elements) != n_elements or n_elements < 3 or n_elements % 2 == 0:
        raise ValueError(f"n_elements must be an odd integer >= 3 (the weak element sits in the middle), "
                         f"got {n_elements!r}")
    length = check_positive("length", length)
    n = int(n_elements)
    h = length / n
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0.0, length, n + 1), np.array([0.0, h]))
    tol = 1e-9 * length
    return mesh.with_boundaries({"left": lambda x: x[0] < tol, "right": lambda x: x[0] > length - tol,
                                 "bottom": lambda x: x[1] < tol})


def cross_section(mesh, *, area: float = 100.0, depth: float = 0.05, width: float = 1.0,
                  notch: float = 0.02) -> np.ndarray:
    """Element cross-sections A a_e (mm^2): Gaussian reduction ``depth`` of half-width ``width`` (mm), element means,
    and ``notch`` less in the centre element."""
    area = check_positive("area", area)
    check_range("depth", depth, 0.0, 1.0, high_open=True)
    width = check_positive("width", width)
    check_range("notch", notch, 0.0, 1.0 - depth, high_open=True)
    edges = np.unique(mesh.p[0])
    length = edges[-1] - edges[0]
    centre = edges[0] + length / 2
    # element mean of the Gaussian, exact: integral of exp(-s^2/2) is sqrt(pi/2) erf(s/sqrt 2)
    from scipy.special import erf

    s = (edges - centre) / width
    mean = np.sqrt(np.pi / 2) * width * np.diff(erf(s / np.sqrt(2.0))) / np.diff(edges)
    a = 1.0 - depth * mean
    x_centre = mesh.p[0, mesh.t].mean(axis=0)
    order = np.argsort(x_centre)  # tensor meshes number elements along x; map to be safe
    a_elements = np.empty_like(a)
    a_elements[order] = a
    a_elements[np.argmin(np.abs(x_centre - centre))] -= notch
    return area * a_elements


@dataclass
class BarRun:
    """One bar computation: ``u`` (mm) and ``F`` (N) of the pulled end per converged step, energies (N mm),
    element centres ``x`` (mm) and the final stiffness fraction ``f`` per element (Model I f, Model II f_bar)."""

    model: str
    n_elements: int
    u: np.ndarray
    F: np.ndarray
    external_work: float
    dissipated: float
    x: np.ndarray
    f: np.ndarray
    completed: bool
    wall_time: float
    jumps: int = 0
    result: object = None

    @property
    def h(self) -> float:
        return float(self.x[1] - self.x[0])

    @property
    def peak(self) -> float:
        return float(self.F.max())

    @property
    def drop_displacement(self) -> float:
        """Displacement (mm) at which the force first falls below half its peak after the peak (nan if never)."""
        i = int(np.argmax(self.F))
        below = np.flatnonzero(self.F[i:] < 0.5 * self.F[i])
        return float(self.u[i + below[0]]) if below.size else float("nan")

    @property
    def damaged_width(self) -> float:
        """Length of bar with less than half its stiffness left, ``f < 0.5`` (mm)."""
        return float(np.sum(self.f < 0.5) * self.h)


def run_bar(material, n_elements: int, *, name: str = "", length: float = 20.0, area: float = 100.0,
            end_displacement: float = 0.04, step: float = 0.002, depth: float = 0.05, width: float = 1.0,
            notch: float = 0.02, damage_scheme: str = "coupled", gauge: float | None = None,
            damage_step: float | None = None, coupling: str = "staggered") -> BarRun:
    """Pull the bar with a weak spot to ``end_displacement`` (mm) in load steps of ``step`` (fraction of the path).

    Model I materials (with ``update_damage``) run through :class:`ModelISolver` (with ``damage_scheme``), or,
    with ``gauge`` (a fraction of the length), through
    :class:`~abrakit.damage.model_one_path.ModelIPathFollowingSolver`, steered by the opening of the middle
    ``gauge`` of the bar in steps of about ``step`` (load factor, then opening), through the snap-back until the
    force falls to 5 % of its peak or the end displacement is reached (``result``: the path follower's result);
    with ``damage_step`` (N mm) instead, through the monolithic solver (``coupling="monolithic"``) under load
    control to the first damage and then in steps of that damage dissipation
    (:class:`~abrakit.damage.model_one_path.DamageControl`); ``coupling`` chooses the gauge run's solution of a step;
    any other material through :class:`abrakit.fem.Solver`, with ``external_work`` passed to ``update`` when it is
    a :class:`~abrakit.materials.ModelIIDamage` (rate limit, Eq. 6.97/6.103).
    """
    end_displacement = check_positive("end_displacement", end_displacement)
    step = check_range("step", step, 0.0, 1.0, low_open=True)
    mesh = bar_mesh(n_elements, length)
    basis = vector_basis(mesh)
    kin = Kinematics.from_basis(basis)
    h = length / n_elements
    sections = cross_section(mesh, area=area, depth=depth, width=width, notch=notch)
    kin = replace(kin, dx=kin.dx * (sections / h)[:, None])  # a bar of cross-section A a(x), not a 2D strip
    conditions = [Dirichlet.on(basis, "left", "x"), Dirichlet.on(basis, "bottom", "y"),
                  Dirichlet.on(basis, "right", "x", end_displacement, name="end")]
    control = StepControl(initial=step, maximum=step, minimum=1e-4 * step)
    x = mesh.p[0, mesh.t].mean(axis=0)
    t0 = _time.perf_counter()
    if gauge is not None or damage_step is not None:
        if gauge is not None and damage_step is not None:
            raise ValueError("give gauge (opening control) or damage_step (damage control), not both")
        if not hasattr(material, "update_damage"):
            raise TypeError("gauge, damage_step (path following) need a Model I material "
                            "(abrakit.materials.ModelIDamage)")
        if gauge is not None:
            check_range("gauge", gauge, 0.0, 1.0, low_open=True, high_open=True)
            ends = [node_row_dofs(basis, "x", length * a, "x") for a in (0.5 + gauge / 2, 0.5 - gauge / 2)]
            solver = ModelIPathFollowingSolver(kin, material, conditions, method="opening", opening=tuple(ends),
                                               path=PathControl(initial=step, maximum=step, max_ratio=1.0),
                                               coupling=coupling)
        else:
            path = PathControl(initial=step, maximum=step, dissipation=check_positive("damage_step", damage_step),
                               target_iterations=8, max_ratio=1.0, max_steps=5000)
            solver = ModelIPathFollowingSolver(kin, material, conditions, method="dissipation", path=path,
                                               coupling="monolithic")
        res = solver.run(progress=False, stop_force=0.05)
        c = res.curves
        return BarRun(name, n_elements, c["u_end"], c["F_end"], res.external_work, res.dissipated_energy, x, res.f,
                      True, _time.perf_counter() - t0, 0, res)
    if hasattr(material, "update_damage"):
        solver = ModelISolver(kin, material, conditions, control=control, damage_scheme=damage_scheme)
        res = solver.run()
        c = res.curves
        return BarRun(name, n_elements, c["u_end"], c["F_end"], float(c["external_work"][-1]),
                      float(c["dissipated_energy"][-1]), x, res.f, res.completed, _time.perf_counter() - t0,
                      res.jumps, res)
    prescribed = np.concatenate([c.dofs for c in conditions])

    def loading(ctx):  # external work of the step with the reactions of the last converged step, Eq. (6.97)
        return {"external_work": float((ctx.u - ctx.u_old)[prescribed] @ ctx.f_int_old[prescribed])}

    is_model_two = isinstance(material, ModelIIDamage)
    solver = Solver(kin, material, conditions, control=control, loading=loading if is_model_two else None,
                    newton=NewtonOptions(residual_tol=1e-5, max_iterations=30))
    res = solver.run(progress=False)
    u, F = res.curves["u_end"], res.curves["F_end"]
    work = path_work(u, F)
    if is_model_two:  # f_bar = (1 - d_eff)^2, Eq. (6.87)
        f = ((1.0 - material.effective_damage(res.state)) ** 2).mean(axis=1)
    else:
        f = np.ones(kin.nel)
    dissipated = float(np.sum(kin.dx * material.dissipation(res.state))) if hasattr(material, "dissipation") else 0.0
    return BarRun(name, n_elements, u, F, work, dissipated, x, f, True, _time.perf_counter() - t0)


def curve_distance(a: BarRun, b: BarRun) -> float:
    """Relative L2 distance of two force-displacement curves over their common range, ``||F_a - F_b|| / ||F_b||``."""
    u_max = min(a.u[-1], b.u[-1])
    u = np.linspace(0.0, u_max, 2001)
    Fa, Fb = np.interp(u, a.u, a.F), np.interp(u, b.u, b.F)
    return float(np.sqrt(np.trapezoid((Fa - Fb) ** 2, u) / np.trapezoid(Fb**2, u)))


@dataclass
class LocalisationStudy:
    """Runs of every model on every mesh, and the numbers that show (or not) mesh dependence."""

    n_elements: tuple[int, ...]
    runs: dict[str, list[BarRun]] = field(default_factory=dict)

    def energies(self, model: str) -> np.ndarray:
        return np.array([r.dissipated for r in self.runs[model]])

    def energy_ratio(self, model: str) -> float:
        """Dissipated energy on the finest mesh over that on the coarsest (1 = mesh independent)."""
        e = self.energies(model)
        return float(e[-1] / e[0])

    def energy_spread(self, model: str) -> float:
        """``(max - min) / mean`` of the dissipated energy over the meshes."""
        e = self.energies(model)
        return float((e.max() - e.min()) / e.mean())

    def peak_spread(self, model: str) -> float:
        """``(max - min) / mean`` of the peak force over the meshes."""
        p = np.array([r.peak for r in self.runs[model]])
        return float((p.max() - p.min()) / p.mean())

    def curve_distance(self, model: str) -> float:
        """Relative L2 distance between the force-displacement curves of the coarsest and the finest mesh.

        With a snap-back passed at fixed displacement this is dominated by where the vertical drop falls (one load
        step apart gives a few per cent); the dissipated energy is the robust measure."""
        runs = self.runs[model]
        return curve_distance(runs[0], runs[-1])

    def table(self) -> list[dict]:
        """One row per model and mesh: elements, h, peak force, dissipated energy, damaged width, time."""
        return [{"model": name, "elements": r.n_elements, "h_mm": r.h, "peak_N": r.peak,
                 "dissipated_Nmm": r.dissipated, "u_drop_mm": r.drop_displacement,
                 "damaged_width_mm": r.damaged_width, "jumps": r.jumps,
                 "completed": r.completed, "time_s": r.wall_time}
                for name, runs in self.runs.items() for r in runs]


def localisation_study(n_elements: Sequence[int] = (21, 41, 81, 161), models: dict | None = None,
                       **bar) -> LocalisationStudy:
    """Run every model of ``models`` (default :func:`bar_models`) on every mesh; ``bar``: options of :func:`run_bar`."""
    models = bar_models() if models is None else models
    n_elements = tuple(int(n) for n in n_elements)
    if len(n_elements) < 2:
        raise ValueError(f"n_elements: give at least two meshes, got {n_elements}")
    study = LocalisationStudy(n_elements)
    for name, material in models.items():
        study.runs[name] = [run_bar(material, n, name=name, **bar) for n in n_elements]
    return study
