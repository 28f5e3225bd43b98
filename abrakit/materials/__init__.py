"""Constitutive models of Ch. 6 at a material point, one interface for the driver and the finite element solver.

Strains and stresses are Mandel vectors ``(..., 6)``, order (11, 22, 33, 23, 13, 12), shears times sqrt(2);
tangents ``(..., 6, 6)``. Every model has ``initial_state(shape)`` and a pure
``update(state, eps, dt=1.0, **loading) -> MaterialResponse(stress, tangent, state)``; see :mod:`.base`.
"""

from __future__ import annotations

from .anisotropic_damage import SURFACES, AnisotropicSofteningDamage
from .base import Material, MaterialResponse, finite_difference_tangent
from .driver import cycles, drive, plane_strain_tension, pure_shear, ramp, uniaxial_strain, uniaxial_stress
from .ductile_failure import JohnsonCookFailure
from .elastic import LinearElastic
from .finite_strain import LogStrainPlasticity
from .model_one import ModelIDamage
from .model_two import ModelIIDamage
from .plasticity import VonMisesPlasticity, uniaxial_hardening_modulus, uniaxial_yield_stress
from .softening import LinearSofteningDamage
from .strength_statistics import StrengthStatistics, normal_cdf, truncated_cdf, weibull_cdf, weibull_mean

#: Table 7.1, Model I (MPa; beta in MPa mm^2: 0.1 almost local, 1 regularised).
TABLE_7_1 = {"E": 200000.0, "nu": 0.33, "r_d": 0.05, "r_p": 60.0, "K_H": 8000.0, "beta": 0.1}
#: Table 7.2, Model II (MPa, dt in s; alpha in 1/(N mm): 0.05 almost local, 0.005 regularised).
TABLE_7_2 = {"E": 200000.0, "nu": 0.33, "r_d": 0.1, "n": 20, "dt": 1.0, "r_p": 60.0, "K_H": 8000.0, "alpha": 0.05}

__all__ = [
    # the interface of every model (Ch. 6)
    "Material", "MaterialResponse", "finite_difference_tangent",
    # the models
    "LinearElastic", "VonMisesPlasticity", "LogStrainPlasticity", "ModelIDamage", "ModelIIDamage",
    "LinearSofteningDamage", "AnisotropicSofteningDamage", "SURFACES", "TABLE_7_1", "TABLE_7_2",
    # closed forms of the plasticity model
    "uniaxial_yield_stress", "uniaxial_hardening_modulus",
    # the material-point driver
    "ramp", "cycles", "drive", "uniaxial_stress", "uniaxial_strain", "pure_shear", "plane_strain_tension",
    # ductile failure of the scratch's steel (material removal)
    "JohnsonCookFailure",
    # strength statistics of seed 001
    "StrengthStatistics", "normal_cdf", "truncated_cdf", "weibull_cdf", "weibull_mean",
]
