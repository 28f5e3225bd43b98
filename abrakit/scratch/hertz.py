"""Hertz's elastic sphere-on-half-space contact, the verification of the scratch's indentation step (Sec. 8.1).

A sphere of radius R pressed to depth d into an elastic half-space (frictionless, small strain):

    F = (4/3) E* √R d^(3/2),    a = √(R d),    p_0 = 3F / (2π a²) = (2E*/π) √(d/R),
    1/E* = (1 − ν²)/E + (1 − ν_i²)/E_i.

Units: N, mm, MPa. The half model of the scratch carries F/2.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from abrakit.validation import broadcast_shapes, check_poisson, check_positive, number_arguments

QUARTZ_POISSON = 0.17
"""Poisson's ratio of the quartz grain, Table 8.1 (E = 73 GPa)."""


class HertzContact(NamedTuple):
    """force F (N), contact_radius a (mm), max_pressure p_0 (MPa), effective_modulus E* (MPa)."""

    force: float | np.ndarray
    contact_radius: float | np.ndarray
    max_pressure: float | np.ndarray
    effective_modulus: float


def _out(x):
    x = np.asarray(x)
    return float(x) if x.ndim == 0 else x


@number_arguments
def effective_modulus(E: ArrayLike, nu: ArrayLike, E_indenter: ArrayLike = np.inf,
                      nu_indenter: ArrayLike = QUARTZ_POISSON) -> float:
    """Contact modulus E* = 1 / ((1 − ν²)/E + (1 − ν_i²)/E_i) in MPa; a rigid indenter (E_i = ∞) gives E/(1 − ν²)."""
    E = check_positive("E", E)
    nu = check_poisson("nu", nu)
    compliance = (1.0 - nu**2) / E
    nu_indenter = check_poisson("nu_indenter", nu_indenter)
    if not np.all(np.asarray(E_indenter, float) == np.inf):      # +inf: a rigid indenter
        E_indenter = check_positive("E_indenter", E_indenter)
        compliance += (1.0 - nu_indenter**2) / E_indenter
    return 1.0 / compliance


@number_arguments
def hertz_sphere(E: ArrayLike, nu: ArrayLike, R: ArrayLike, d: ArrayLike, *, E_indenter: ArrayLike = np.inf,
                 nu_indenter: ArrayLike = QUARTZ_POISSON) -> HertzContact:
    """Force, contact radius and peak pressure of a sphere (radius ``R``, mm) pressed to depth ``d`` (mm, ≥ 0,
    scalar or array) into a half-space of modulus ``E`` (MPa) and Poisson's ratio ``nu``; the indenter is rigid
    unless ``E_indenter`` is given (e.g. quartz, 73000 MPa and ν = 0.17, Table 8.1)."""
    E_star = effective_modulus(E, nu, E_indenter, nu_indenter)
    R = check_positive("R", R)
    d = np.asarray(check_positive("d", d, allow_zero=True))
    force = 4.0 / 3.0 * E_star * np.sqrt(R) * d**1.5
    radius = np.sqrt(R * d)
    pressure = 2.0 * E_star / np.pi * np.sqrt(d / R)
    return HertzContact(_out(force), _out(radius), _out(pressure), float(E_star))


@number_arguments
def hertz_depth(F: ArrayLike, E: ArrayLike, nu: ArrayLike, R: ArrayLike, *, E_indenter: ArrayLike = np.inf,
                nu_indenter: ArrayLike = QUARTZ_POISSON):
    """Indentation depth (mm) under force ``F`` (N, ≥ 0): d = (3F / (4 E* √R))^(2/3), the inverse of
    :func:`hertz_sphere`."""
    E_star = effective_modulus(E, nu, E_indenter, nu_indenter)
    R = check_positive("R", R)
    F = np.asarray(check_positive("F", F, allow_zero=True))
    broadcast_shapes(F=F, R=R)
    return _out((3.0 * F / (4.0 * E_star * np.sqrt(R))) ** (2.0 / 3.0))
