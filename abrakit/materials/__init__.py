"""Constitutive models of Ch. 6 at a material point, one interface for the driver and the finite element solver.

Strains and stresses are Mandel vectors ``(..., 6)``, order (11, 22, 33, 23, 13, 12), shears times sqrt(2);
tangents ``(..., 6, 6)``. Every model has ``initial_state(shape)`` and a pure
``update(state, eps, dt=1.0, **loading) -> MaterialResponse(stress, tangent, state)``; see :mod:`.base`.
"""

from __future__ import annotations

import numpy as np

from .anisotropic_damage import AnisotropicSofteningDamage, ProjectedBandWidth, projected_band_width
from .base import (
    DEVIATORIC,
    IDENTITY,
    Material,
    MaterialResponse,
    deviator,
    finite_difference_tangent,
)
from .driver import (
    DriverError,
    PathResult,
    cycles,
    drive,
    plane_strain_tension,
    pure_shear,
    ramp,
    uniaxial_strain,
    uniaxial_stress,
)
from .elastic import LinearElastic
from .finite_strain import LogStrainPlasticity
from .model_one import ModelIDamage
from .model_two import ModelIIDamage, effective_damage_function, erve_strains
from .plasticity import VonMisesPlasticity, plastic_step, uniaxial_hardening_modulus, uniaxial_yield_stress
from .softening import LinearSofteningDamage
from .softening_laws import ExponentialSoftening, LinearSoftening, max_band_width, softening_law
from .strength_statistics import StrengthStatistics

#: Table 7.1, Model I (MPa; beta in MPa mm^2: 0.1 almost local, 1 regularised).
TABLE_7_1 = {"E": 200000.0, "nu": 0.33, "r_d": 0.05, "r_p": 60.0, "K_H": 8000.0, "beta": 0.1}
#: Table 7.2, Model II (MPa, dt in s; alpha in 1/(N mm): 0.05 almost local, 0.005 regularised).
TABLE_7_2 = {"E": 200000.0, "nu": 0.33, "r_d": 0.1, "n": 20, "dt": 1.0, "r_p": 60.0, "K_H": 8000.0, "alpha": 0.05}

__all__ = [
    "AnisotropicSofteningDamage",
    "ExponentialSoftening",
    "LinearSoftening",
    "ProjectedBandWidth",
    "StrengthStatistics",
    "max_band_width",
    "projected_band_width",
    "softening_law",
    "DEVIATORIC",
    "IDENTITY",
    "TABLE_7_1",
    "TABLE_7_2",
    "DriverError",
    "LinearElastic",
    "LinearSofteningDamage",
    "LogStrainPlasticity",
    "Material",
    "MaterialResponse",
    "ModelIDamage",
    "ModelIIDamage",
    "PathResult",
    "VonMisesPlasticity",
    "cycles",
    "demo",
    "deviator",
    "drive",
    "effective_damage_function",
    "erve_strains",
    "finite_difference_tangent",
    "plane_strain_tension",
    "plastic_step",
    "pure_shear",
    "ramp",
    "uniaxial_hardening_modulus",
    "uniaxial_strain",
    "uniaxial_stress",
    "uniaxial_yield_stress",
]


def demo() -> str:
    """Uniaxial tension of the Table 7.1 steel at a point: plasticity against the closed form, Model I/II peaks."""
    p = TABLE_7_1
    plastic = VonMisesPlasticity(p["E"], p["nu"], p["r_p"], p["K_H"], integration="implicit")
    eps = ramp(0.01, 50)
    curve = uniaxial_stress(plastic, eps)
    sigma_0, H = uniaxial_yield_stress(p["r_p"]), uniaxial_hardening_modulus(p["K_H"])
    eps_y, E_t = sigma_0 / p["E"], p["E"] * H / (p["E"] + H)
    closed = np.where(eps < eps_y, p["E"] * eps, sigma_0 + E_t * (eps - eps_y))
    error = np.max(np.abs(curve.stress_component("11")[1:] - closed))

    model_one = ModelIDamage(p["E"], 0.0, p["r_d"])
    peak_one = uniaxial_strain(model_one, ramp(2e-3, 400)).stress_component("11").max()
    model_two = ModelIIDamage(p["E"], 0.0, 0.1, n=20)
    path_two = uniaxial_strain(model_two, ramp(3e-3, 300), loading={"external_work": 1.0})
    return (
        f"von Mises (implicit), uniaxial stress to 1 %: yield {sigma_0:.2f} MPa, final stress "
        f"{curve.stress_component('11')[-1]:.2f} MPa, max error to the closed form {error:.1e} MPa\n"
        f"Model I (beta = 0, nu = 0), uniaxial strain: peak {peak_one:.2f} MPa vs sqrt(2 r_d E) = "
        f"{np.sqrt(2 * p['r_d'] * p['E']):.2f} MPa\n"
        f"Model II (n = 20, alpha dW = 0.05 per step): peak {path_two.stress_component('11').max():.2f} MPa, "
        f"final sub-domain damage {np.round(path_two.internal['d'][-1], 3).tolist()}"
    )
