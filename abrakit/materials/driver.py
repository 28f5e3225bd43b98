"""Material-point driver in the spirit of MFront's MTest: impose a strain path, get curves and internal variables.

Each step imposes some Mandel strain components and some stress components; the free strain components are
found by Newton's method on the imposed stresses (mixed control), with the material's tangent as Jacobian
and a finite-difference Jacobian as fallback (for operator-split tangents such as Model I's ``f^m E``).

Paths are arrays of values, one per step (``ramp``, ``cycles``), so they compose::

    result = uniaxial_stress(VonMisesPlasticity(200e3, 0.3, 60.0, 8000.0), ramp(0.01, 100))
    result.strain_component("11"), result.stress_component("11"), result.internal["alpha_p"]

Any batch shape after the step axis runs in parallel (e.g. ``(n_steps, n_points)`` strain values).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .. import tensors as T
from ..validation import check_finite, check_instance, check_positive, check_shape, number_arguments
from .base import finite_difference_tangent

_COMPONENTS = {"11": 0, "22": 1, "33": 2, "23": 3, "13": 4, "12": 5, "32": 3, "31": 4, "21": 5}
_SQRT2 = np.sqrt(2.0)


def _component_index(name: str) -> int:
    if name not in _COMPONENTS:
        raise ValueError(f"component must be one of {sorted(set(_COMPONENTS))}, got {name!r}")
    return _COMPONENTS[name]


@dataclass(frozen=True)
class PathResult:
    """Curves of one driven path, including the initial (virgin, stress-free) point as row 0.

    ``time`` (N+1,), ``strain`` and ``stress`` (N+1, ..., 6) Mandel, ``internal``: every state entry stacked
    over the steps, ``iterations`` (N,): Newton iterations per step (0 under pure strain control).
    """

    time: np.ndarray
    strain: np.ndarray
    stress: np.ndarray
    internal: dict[str, np.ndarray]
    iterations: np.ndarray

    def __post_init__(self):
        for name in ("time", "strain", "stress"):              # a path that went astray stops, never NaN curves
            check_finite(name, getattr(self, name))
        rows = check_shape("time", self.time, (None,)).shape[0]
        for name in ("strain", "stress"):
            shape = np.shape(getattr(self, name))
            if len(shape) < 2 or shape[0] != rows or shape[-1] != 6:
                raise ValueError(f"{name} must have shape ({rows}, ..., 6), got {shape}")
        check_instance("internal", self.internal, dict)
        for key, value in self.internal.items():
            if np.shape(value)[:1] != (rows,) or (np.asarray(value).dtype.kind == "f" and np.isnan(value).any()):
                raise ValueError(f"internal[{key!r}] must hold {rows} rows without NaN, got shape {np.shape(value)}")
        iterations = np.asarray(self.iterations)
        if iterations.shape != (rows - 1,) or (iterations.size and iterations.dtype.kind not in "iu") \
                or np.any(iterations < 0):
            raise ValueError(f"iterations must be {rows - 1} counts >= 0, got {self.iterations!r}")

    def strain_component(self, name: str) -> np.ndarray:
        """Tensor component ``eps_ij`` (``name="11"``, ``"12"``, ...) along the path (shears un-scaled)."""
        k = _component_index(name)
        return self.strain[..., k] / (_SQRT2 if k >= 3 else 1.0)

    def stress_component(self, name: str) -> np.ndarray:
        """Tensor component ``sigma_ij`` (MPa) along the path."""
        k = _component_index(name)
        return self.stress[..., k] / (_SQRT2 if k >= 3 else 1.0)

    def stress_tensor(self) -> np.ndarray:
        """Stresses as ``(N+1, ..., 3, 3)`` tensors."""
        return T.from_mandel(self.stress)


class DriverError(RuntimeError):
    """Raised when the mixed-control Newton iteration of a step does not converge."""


@number_arguments
def ramp(peak: ArrayLike, n_steps: int) -> np.ndarray:
    """``n_steps`` equal increments from 0 to ``peak`` (the values after each step)."""
    if n_steps < 1:
        raise ValueError(f"n_steps must be >= 1, got {n_steps}")
    check_finite("peak", peak)
    return np.linspace(0.0, 1.0, n_steps + 1)[1:] * peak


@number_arguments
def cycles(amplitude: float, n_cycles: int, steps_per_quarter: int, mean: float = 0.0) -> np.ndarray:
    """Symmetric triangle wave ``mean -> mean + a -> mean - a -> mean`` repeated ``n_cycles`` times."""
    if n_cycles < 1 or steps_per_quarter < 1:
        raise ValueError("n_cycles and steps_per_quarter must be >= 1")
    check_finite("amplitude", amplitude)
    check_finite("mean", mean)
    phase = np.arange(1, 4 * steps_per_quarter * n_cycles + 1) / (4.0 * steps_per_quarter)
    return mean + amplitude * (2.0 / np.pi) * np.arcsin(np.sin(2.0 * np.pi * phase))


@number_arguments
def drive(
    material,
    strain: ArrayLike,
    stress=None,
    stress_controlled=None,
    *,
    dt: float = 1.0,
    loading: dict | Callable | None = None,
    tol: float = 1e-9,
    max_iter: int = 30,
    jacobian: str = "material",
) -> PathResult:
    """Drive ``material`` through a path of ``N`` steps under mixed strain/stress control.

    ``strain``: (N, ..., 6) Mandel values of the strain-controlled components (the other entries are ignored).
    ``stress``: (N, ..., 6) Mandel values of the stress-controlled components (default 0).
    ``stress_controlled``: boolean mask of length 6 (default: none, pure strain control).
    ``loading``: keyword arguments for ``material.update`` — a dict used at every step, or a callable
    ``loading(step, state, eps) -> dict`` (``state`` is the converged state of the previous step).
    Convergence: ``max |sigma_free - target| <= tol (1 + max |sigma|)`` (MPa). ``jacobian``: ``"material"``
    (the returned tangent, retried with finite differences if Newton fails) or ``"finite_difference"``.
    """
    check_positive("tol", tol)
    if max_iter < 0:                         # 0: the step's strain-controlled response only, no correction
        raise ValueError(f"max_iter must be a non-negative integer, got {max_iter!r}")
    strain = np.asarray(check_finite("strain", strain), dtype=float)
    if strain.ndim < 2 or strain.shape[-1] != 6:
        raise ValueError(f"strain must have shape (n_steps, ..., 6), got {strain.shape}")
    stress_target = np.zeros_like(strain) if stress is None else np.broadcast_to(check_finite("stress", stress),
                                                                                 strain.shape)
    mask = np.zeros(6, bool) if stress_controlled is None else np.asarray(stress_controlled, bool)
    if mask.shape != (6,):
        raise ValueError(f"stress_controlled must be a boolean mask of length 6, got shape {mask.shape}")
    if jacobian not in ("material", "finite_difference"):
        raise ValueError(f"jacobian must be 'material' or 'finite_difference', got {jacobian!r}")
    dt = check_positive("dt", dt)
    n_steps, batch = strain.shape[0], strain.shape[1:-1]
    state = material.initial_state(batch)

    strains, stresses, states, iterations = [np.zeros((*batch, 6))], [np.zeros((*batch, 6))], [state], []
    eps = np.zeros((*batch, 6))
    for m in range(n_steps):
        eps = np.where(mask, eps, strain[m])  # free components start from the last converged values
        kwargs = loading(m, state, eps) if callable(loading) else dict(loading or {})
        try:
            response, eps, its = _solve_step(material, state, eps, stress_target[m], mask, dt, kwargs, tol, max_iter,
                                             jacobian)
        except DriverError:
            if jacobian != "material":
                raise
            response, eps, its = _solve_step(material, state, eps, stress_target[m], mask, dt, kwargs, tol,
                                             max_iter, "finite_difference")
        state = response.state
        strains.append(eps)
        stresses.append(response.stress)
        states.append(state)
        iterations.append(its)
    internal = {key: np.stack([s[key] for s in states]) for key in states[0]}
    return PathResult(dt * np.arange(n_steps + 1), np.stack(strains), np.stack(stresses), internal,
                      np.array(iterations))


def _solve_step(material, state, eps, target, mask, dt, kwargs, tol, max_iter, jacobian):
    """Newton on the stress-controlled components of one step; returns (response, strain, iterations)."""
    free = np.flatnonzero(mask)
    for iteration in range(max_iter + 1):
        response = material.update(state, eps, dt, **kwargs)
        if free.size == 0:
            return response, eps, 0
        residual = response.stress[..., free] - target[..., free]
        scale = 1.0 + np.max(np.abs(response.stress))
        if not np.all(np.isfinite(residual)):
            raise DriverError("non-finite stress in the mixed-control iteration")
        if np.max(np.abs(residual)) <= tol * scale:
            return response, eps, iteration
        if iteration == max_iter:
            break
        if jacobian == "material":
            tangent = response.tangent
        else:
            tangent = finite_difference_tangent(material, state, eps, h=1e-8, dt=dt, **kwargs)
        J = tangent[..., free[:, None], free[None, :]]
        correction = np.linalg.solve(J, residual[..., None])[..., 0]
        eps = eps.copy()
        eps[..., free] -= correction
    raise DriverError(
        f"mixed control did not converge in {max_iter} iterations (max residual {np.max(np.abs(residual)):.3e} MPa)"
    )


def _axis_path(values, components, name: str):
    """Mandel strain path ``(N, ..., 6)`` with ``strain[..., k] = weight * values`` for each (k, weight);
    ``name``: the parameter that gave ``values`` (its errors name it)."""
    values = np.asarray(check_finite(name, values), dtype=float)
    strain = np.zeros((*values.shape, 6))
    for k, weight in components.items():
        strain[..., k] = weight * values
    return strain


def uniaxial_strain(material, eps11, **kwargs) -> PathResult:
    """``eps_11`` imposed (values per step), every other strain component zero."""
    return drive(material, _axis_path(eps11, {0: 1.0}, "eps11"), **kwargs)


def uniaxial_stress(material, eps11, **kwargs) -> PathResult:
    """``eps_11`` imposed, every other stress component zero (mixed control)."""
    mask = np.array([False, True, True, True, True, True])
    return drive(material, _axis_path(eps11, {0: 1.0}, "eps11"), stress_controlled=mask, **kwargs)


def plane_strain_tension(material, eps11, **kwargs) -> PathResult:
    """``eps_11`` imposed, ``eps_33 = 0`` and zero shear strains (plane strain), ``sigma_22 = 0``."""
    mask = np.array([False, True, False, False, False, False])
    return drive(material, _axis_path(eps11, {0: 1.0}, "eps11"), stress_controlled=mask, **kwargs)


def pure_shear(material, gamma12, **kwargs) -> PathResult:
    """Engineering shear ``gamma_12 = 2 eps_12`` imposed, every other strain component zero."""
    return drive(material, _axis_path(gamma12, {5: _SQRT2 / 2.0}, "gamma12"), **kwargs)
