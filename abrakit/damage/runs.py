"""One run of a damage model on a Chapter 7 specimen, recorded the same way for every model (the comparison chapter).

:func:`run_specimen` loads a :class:`~abrakit.damage.specimens.DamageSpecimen` with Model I
(:mod:`abrakit.damage.model_one_fe`), Model II (:mod:`abrakit.damage.model_two_fe`) or the anisotropic softening
damage of seed 001 (``"anisotropic"``, :mod:`abrakit.damage.crack_band`) and returns a :class:`SpecimenRun`. It
lives apart from the specimens so that the models may use the specimens (their demos do) without an import cycle.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from ..fem import PathControl, PathFollowingSolver, StepControl
from ..fem.solver import StepFailed
from ..materials import TABLE_7_1, ModelIDamage
from ..validation import check_option, check_positive, check_range
from .crack_band import specimen_material
from .metrics import element_areas
from .model_one_fe import ModelISolver
from .model_one_path import ModelIPathFollowingSolver
from .model_two_fe import run_model_two
from .specimens import DamageSpecimen

#: Regularisation parameters of Ch. 7: Model I beta (MPa mm^2, Table 7.1), Model II alpha (1/(N mm), Table 7.2).
REGULARISATION = {"I": {"weak": 0.1, "strong": 1.0}, "II": {"weak": 0.05, "strong": 0.005}}
MODELS = ("I", "II", "anisotropic")


@dataclass
class SpecimenRun:
    """Model-independent record of one run: the curve (u in mm, F in N for the whole specimen), the final
    element fields ``stiffness_loss`` (``1 - f`` for Model I, ``1 - f_bar`` for Model II) and ``alpha_p``, and
    the cost (converged ``steps``, Newton ``iterations``, ``cutbacks``, wall ``seconds``); ``dissipated`` (N mm, the
    whole specimen, one value per point of the curve) where the model counts it (the anisotropic one)."""

    model: str
    parameter: float
    u: np.ndarray
    F: np.ndarray
    stiffness_loss: np.ndarray
    alpha_p: np.ndarray
    status: str
    message: str
    steps: int
    iterations: int
    cutbacks: int
    seconds: float
    result: object = None
    dissipated: np.ndarray | None = None


class _Stop(Exception):
    pass


def run_specimen(specimen: DamageSpecimen, model: str, parameter: float, *, step: float = 0.002,
                 stop_fraction: float | None = 0.1, gauge: tuple[float, float] | None = None,
                 opening: tuple[np.ndarray, np.ndarray] | None = None, path: PathControl | None = None,
                 material_options: dict | None = None, damage_step: float | None = None) -> SpecimenRun:
    """Load ``specimen`` to its ``displacement`` in equal increments ``step`` (mm) with Model I or Model II.

    ``model="II"``: :func:`abrakit.damage.model_two_fe.run_model_two` with ``alpha = parameter`` (Table 7.2).
    ``model="I"``: :class:`abrakit.damage.model_one_fe.ModelISolver` with ``beta = parameter`` and Table 7.1
    (implicit return map, consistent tangent at frozen f). Both stop once the force has fallen below
    ``stop_fraction`` of its peak; cutbacks may add steps.

    ``model="anisotropic"``: seed 001's anisotropic softening damage with ``G_Ic = parameter`` (N/mm) and
    :data:`~abrakit.damage.crack_band.STEEL_SPECIMENS`, always path-followed (dissipation control after the peak,
    exact for its secant unloading; ``path`` default: load steps of 10 ``step``, then G_Ic sqrt(A)/100 of
    dissipation per step, A the specimen's area), until ``stop_fraction`` of the peak. ``stiffness_loss`` is then
    the normal damage d_n, ``alpha_p`` zero, and ``dissipated`` the dissipation at every step.
    ``material_options`` change :data:`~abrakit.damage.crack_band.STEEL_SPECIMENS` (e.g. ``{"surface": 0}``).

    ``gauge=(low, high)`` (mm): follow the path instead
    (:class:`~abrakit.damage.model_one_path.ModelIPathFollowingSolver`, opening of the extensometer
    :meth:`DamageSpecimen.gauge`; ``path`` default: first load step 10 ``step``, opening steps at most 20 times the
    first), through any snap-back, until ``stop_fraction`` of the peak. ``opening=(dofs_plus, dofs_minus)``: the
    same with an opening of one's own (mean relative displacement of the two DOF sets), where no row of nodes
    makes a gauge (the plate with a hole's polar mesh). ``damage_step`` (N mm, or N mm/mm in plane strain): follow
    Model I by its damage dissipation instead, in steps of about this much, displacements, damage and load factor
    solved in one Newton system (``coupling="monolithic"``, :class:`~abrakit.damage.model_one_path.DamageControl`;
    ``path`` default: load steps of ``step`` up to the first damage). The damage dissipation grows in every
    step that damages, through any snap-back; the sweeps of the gauge's staggered steps stop settling on fine meshes
    (an element of the damage front toggling between loading and unloading).

    ``model="II"`` with ``path``: Model II under Crisfield's arc length over all unknowns (:func:`run_model_two`
    with ``method="arc-length"``; the rate limit on the magnitude of the boundary work), until ``stop_fraction``.
    (Model II under an opening control was tried on the double notch, 250 elements: its rate limit lets a step
    damage only as much as the boundary work of the step allows, which is almost nothing once the load falls, and
    20 000 opening steps took the force only to 90 % of the peak.)
    """
    check_option("model", model, MODELS)
    name = {"I": "parameter (beta)", "II": "parameter (alpha)"}.get(model, "parameter (G_Ic)")
    check_positive(name, parameter, allow_zero=model == "I")          # beta >= 0; alpha, G_Ic > 0
    check_positive("step", step)
    if stop_fraction is not None:
        check_range("stop_fraction", stop_fraction, 0.0, 1.0, low_open=True, high_open=True)
    if material_options and model != "anisotropic":
        raise ValueError(f"material_options are for model='anisotropic', got model={model!r}")
    if model == "anisotropic":
        return _crack_band(specimen, parameter, path, 10 * step / specimen.displacement, stop_fraction,
                           material_options or {})
    if (gauge is not None or opening is not None) and model != "I":
        raise ValueError(f"gauge, opening: path following by an opening is for Model I only, got model={model!r} "
                         "(Model II follows its path by arc length: path=PathControl(...))")
    if damage_step is not None and model != "I":
        raise ValueError(f"damage_step: damage control is for Model I only, got model={model!r}")
    if sum(x is not None for x in (gauge, opening, damage_step)) > 1:
        raise ValueError("give one of gauge (heights), opening (DOF sets) or damage_step, not several")
    if gauge is not None:
        opening = specimen.gauge(*gauge)
    steps = max(1, int(round(specimen.displacement / step)))
    h = 1.0 / steps
    if model == "II":
        res = run_model_two(specimen, parameter, steps=steps, stop_fraction=stop_fraction, path=path,
                            method="arc-length" if path is not None else "dissipation")
        c = res.curves
        return SpecimenRun("II", parameter, c["u"], c["F"], res.stiffness_loss, res.alpha_p, res.status,
                           res.message, res.steps, res.newton_iterations, res.cutbacks, res.wall_time, res)

    material = ModelIDamage(**{**TABLE_7_1, "beta": parameter}, integration="implicit", tangent="consistent")
    if opening is not None:
        return _follow(specimen, material, opening,
                       path or PathControl(initial=10 * h, maximum=10 * h, max_ratio=20.0, max_steps=20000),
                       stop_fraction)
    if damage_step is not None:
        path = path or PathControl(initial=h, maximum=h, max_ratio=1.0, target_iterations=8, max_steps=20000)
        return _follow(specimen, material, None,
                       replace(path, dissipation=check_positive("damage_step", damage_step)), stop_fraction)
    solver = ModelISolver(specimen.basis, material, specimen.dirichlet,
                          control=StepControl(initial=h, maximum=h, minimum=h * 1e-3))
    name, scale, last, peak = specimen.loaded, specimen.force_scale, [None], [0.0]

    def watch(partial):
        last[0] = partial
        F = partial.curves[f"F_{name}"]
        peak[0] = max(peak[0], float(F[-1]))
        if stop_fraction is not None and len(F) > 2 and F[-1] < stop_fraction * peak[0]:
            raise _Stop

    t0 = time.perf_counter()
    try:
        res = solver.run(vtu_every=0, on_step=watch)
        status = "end" if res.completed else "failed"
    except _Stop:
        res, status = last[0], "fractured"
    seconds = time.perf_counter() - t0
    c = res.curves
    return SpecimenRun("I", parameter, c[f"u_{name}"], scale * c[f"F_{name}"], 1.0 - res.f, res.alpha_p, status,
                       res.message, len(c["step"]) - 1, int(np.sum(c["iterations"])), int(res.cutbacks), seconds,
                       res)


def _ended(F, stop_fraction, max_steps: int) -> tuple[str, str]:
    """Status and message of a path-followed run that returned: "fractured" once the force has fallen to
    ``stop_fraction`` of its peak, else "end" (``max_steps`` ran out first)."""
    F = np.abs(np.asarray(F, dtype=float))
    if stop_fraction and F.size and F[-1] <= stop_fraction * F.max():
        return "fractured", ""
    return "end", (f"max_steps = {max_steps} reached at {F[-1] / max(F.max(), 1e-300):.2f} of the peak force"
                   if F.size else "no step")


def _follow(specimen: DamageSpecimen, material, opening, path: PathControl, stop_fraction) -> SpecimenRun:
    """Model I on ``specimen`` under path following by ``opening`` (DOF sets), or, with ``opening=None``, by the
    damage dissipation ``path.dissipation`` per step (see :func:`run_specimen`)."""
    if opening is None:
        solver = ModelIPathFollowingSolver(specimen.basis, material, specimen.dirichlet, method="dissipation",
                                           coupling="monolithic", path=path)
    else:
        solver = ModelIPathFollowingSolver(specimen.basis, material, specimen.dirichlet, method="opening",
                                           opening=opening, path=path, max_sweeps=400)
    try:
        res = solver.run(stop_force=stop_fraction or 0.0, end=np.inf, progress=False)
        status, message = _ended(res.curves[f"F_{specimen.loaded}"], stop_fraction, solver.path.max_steps)
    except StepFailed as failure:      # keep the followed part of the path
        status, message = "failed", str(failure)
        res = solver.result_of(failure.result)
    c, name = res.curves, specimen.loaded
    return SpecimenRun("I", material.beta, c[f"u_{name}"], specimen.force_scale * c[f"F_{name}"], 1.0 - res.f,
                       res.alpha_p, status, message, len(c["step"]) - 1, int(np.sum(c["iterations"])),
                       int(res.solve.cutbacks), res.seconds, res)


def _crack_band(specimen: DamageSpecimen, toughness: float, path: PathControl | None, increment: float,
                stop_fraction, options: dict) -> SpecimenRun:
    """Seed 001's model on ``specimen`` under dissipation-controlled path following (see :func:`run_specimen`)."""
    material = specimen_material(specimen.basis, check_positive("parameter (G_Ic)", toughness),
                                 mirror_y=specimen.band_mirror == 2, **options)      # band on a symmetry line
    area = float(element_areas(specimen.plane_mesh).sum())
    path = path or PathControl(initial=increment, maximum=increment, dissipation=toughness * np.sqrt(area) / 100,
                               max_steps=5000)
    solver = PathFollowingSolver(specimen.basis, material, specimen.dirichlet, path=path)
    dissipated = [0.0]
    tic = time.perf_counter()
    try:
        res = solver.run(stop_force=stop_fraction or 0.0, end=np.inf, progress=False, vtu_every=0,
                         on_step=lambda r: dissipated.append(float(np.sum(material.dissipation(r.state)
                                                                            * solver.kin.dx))))
        status, message = _ended(res.curves[f"F_{specimen.loaded}"], stop_fraction, path.max_steps)
    except StepFailed as failure:      # keep the followed part of the path
        status, message, res = "failed", str(failure), failure.result
    c, name = res.curves, specimen.loaded
    d_n = res.state["d"][..., 0].mean(axis=1)
    return SpecimenRun("anisotropic", toughness, c[f"u_{name}"], specimen.force_scale * c[f"F_{name}"], d_n,
                       np.zeros_like(d_n), status, message, len(c["step"]) - 1, int(np.sum(c["iterations"])),
                       int(res.cutbacks), time.perf_counter() - tic, res,
                       specimen.force_scale * np.array(dissipated))

