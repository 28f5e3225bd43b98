"""Ductile failure at a material point: stress triaxiality, Lode parameter and a damage indicator of Johnson–Cook's
form with Bao and Wierzbicki's cut-off.

The stress state of a point is measured by two ratios of invariants of its stress tensor σ (MPa; in the
finite-strain model the Kirchhoff stress τ = J σ, which gives the same ratios since J > 0):

    η = σ_m / σ_eq,              σ_m = tr σ / 3,  σ_eq = √(3/2 s : s),  s = σ − σ_m I      (stress triaxiality)
    ξ = 27/2 · J₃ / σ_eq³,       J₃ = det s,  ξ ∈ [−1, 1]                                  (Lode parameter)

Uniaxial tension: η = 1/3, ξ = 1; pure shear: η = 0, ξ = 0; equibiaxial tension: η = 2/3, ξ = −1; uniaxial
compression: η = −1/3, ξ = −1. Where the deviator vanishes (σ_eq ≤ 10⁻¹² (|σ_m| + σ_eq)) the ratios are
undefined; such a point gets ξ = 0 and η = ±∞ by the sign of σ_m (0 for a stress-free point), the limits that
the fracture strain below needs (no damage under hydrostatic pressure).

Fracture strain (Johnson & Cook, Eng. Fract. Mech. 21 (1985) 31, with their strain-rate factor
[1 + D₄ ln ε̇*] and temperature factor [1 + D₅ T*] set to 1: quasi-static loading at room temperature, as in the
rate-independent scratch)::

    ε_f(η) = D₁ + D₂ exp(D₃ η)                      for η > η_c,
    ε_f(η) = ∞   (no damage)                        for η ≤ η_c = −1/3,

with the cut-off of Bao & Wierzbicki (Eng. Fract. Mech. 72 (2005) 1049: no fracture below η = −1/3; their
Int. J. Mech. Sci. 46 (2004) 81 maps ε_f over compression, shear and tension). Johnson and
Cook's fit does not depend on ξ; the argument is carried so that a Lode-dependent criterion (Bai & Wierzbicki's
modified Mohr–Coulomb, Int. J. Fract. 161 (2010) 1) has the same interface. Where a fit with D₁ < 0 falls
below ``minimum_strain`` (Armco iron's beyond η ≈ 1.9, outside the tests it was fitted to) ε_f is held there.

Damage indicator (Johnson and Cook's linear accumulation of plastic strain increments), failure at D = 1::

    D = ∫ dε̄ᵖ / ε_f(η, ξ),      D_{n+1} = D_n + Δε̄ᵖ / ε_f(η_{n+1}, ξ_{n+1})

with the equivalent (von Mises) plastic strain ε̄ᵖ and the stress at the end of the increment (backward Euler,
as the radial return of the plasticity). With the yield function |dev σ| − (r_p + K_H α_p) of Eq. (6.51)–(6.53)
α_p accumulates |Δε_p|, so Δε̄ᵖ = √(2/3) Δα_p (uniaxial flow: ε̄ᵖ = ε_p,11).
:func:`abrakit.materials.finite_strain.ductile_damage_update` applies the update to the states of the
finite-strain plasticity after a converged increment. On a proportional path (η constant) D = ε̄ᵖ/ε_f(η).

Default constants: Johnson and Cook's 4340 steel, D₁ = 0.05, D₂ = 3.44, D₃ = −2.12 (their D₄ = 0.002 and
D₅ = 0.61 drop out at the reference rate and temperature), :data:`JOHNSON_COOK_1985` for their other two metals.
Why 4340 for the scratch's St-52 (the decision in :mod:`abrakit.decisions`): no Johnson–Cook fracture set of
St-52 is at hand; of Johnson and Cook's three metals it is the only steel; its D₁ > 0 keeps ε_f positive at every
triaxiality, where Armco iron's fit (ferritic and nearer St-52 in yield stress) reaches zero at η ≈ 1.9; its
ε_f(1/3) = 1.75 exceeds the true fracture strain of order 1 of a structural steel in a tensile test, so it errs
towards less removal, not more.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..validation import (
    broadcast_shapes,
    check_finite,
    check_number_fields,
    check_positive,
    check_range,
    check_shape,
    number_arguments,
)

#: Triaxiality at and below which no ductile damage grows (Bao & Wierzbicki, Eng. Fract. Mech. 72 (2005) 1049).
BAO_WIERZBICKI_CUTOFF = -1.0 / 3.0

#: Johnson & Cook (1985): the fracture constants (D₁, D₂, D₃, D₄, D₅) of their three metals (ε_f dimensionless;
#: D₄ multiplies ln ε̇*, D₅ the homologous temperature T*; both factors are 1 here).
JOHNSON_COOK_1985 = {
    "4340 steel": (0.05, 3.44, -2.12, 0.002, 0.61),
    "Armco iron": (-2.20, 5.43, -0.47, 0.016, 0.63),
    "OFHC copper": (0.54, 4.89, -3.03, 0.014, 1.12),
}

_ZERO_DEVIATOR = 1e-12
_CUTOFF_ROUND_OFF = 1e-12          # uniaxial compression computed in floating point still counts as η = −1/3


def _stress(stress) -> np.ndarray:
    """``stress`` as a finite, symmetric float array (..., 3, 3), else a ValueError naming it."""
    stress = check_shape("stress", np.asarray(check_finite("stress", stress), dtype=float), (..., 3, 3))
    asym = np.abs(stress - np.swapaxes(stress, -1, -2)).max(initial=0.0)
    if asym > 1e-9 * max(np.abs(stress).max(initial=0.0), 1.0):
        raise ValueError(f"stress must be symmetric (..., 3, 3) tensors, got an antisymmetric part of {asym:.3g}")
    return stress


def _invariants(stress: np.ndarray):
    """σ_m, σ_eq and J₃ = det s of symmetric (..., 3, 3) stresses."""
    mean = np.trace(stress, axis1=-2, axis2=-1) / 3.0
    s = stress - mean[..., None, None] * np.eye(3)
    equivalent = np.sqrt(1.5 * np.einsum("...ij,...ij->...", s, s))
    j3 = (s[..., 0, 0] * (s[..., 1, 1] * s[..., 2, 2] - s[..., 1, 2] * s[..., 2, 1])
          - s[..., 0, 1] * (s[..., 1, 0] * s[..., 2, 2] - s[..., 1, 2] * s[..., 2, 0])
          + s[..., 0, 2] * (s[..., 1, 0] * s[..., 2, 1] - s[..., 1, 1] * s[..., 2, 0]))
    return mean, equivalent, j3


def von_mises_stress(stress: ArrayLike) -> np.ndarray:
    """σ_eq = √(3/2 s : s) (MPa) of symmetric stresses ``stress`` (..., 3, 3)."""
    return _invariants(_stress(stress))[1]


def stress_state(stress: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """(η, ξ): the stress triaxiality σ_m/σ_eq and the Lode parameter 27/2 J₃/σ_eq³ of symmetric stresses
    ``stress`` (..., 3, 3) (module docstring; a point without deviator gets η = ±∞ or 0 and ξ = 0)."""
    mean, equivalent, j3 = _invariants(_stress(stress))
    deviatoric = equivalent > _ZERO_DEVIATOR * (np.abs(mean) + equivalent)
    safe = np.where(deviatoric, equivalent, 1.0)
    eta = np.where(deviatoric, mean / safe, np.where(mean > 0.0, np.inf, np.where(mean < 0.0, -np.inf, 0.0)))
    xi = np.where(deviatoric, np.clip(13.5 * j3 / safe**3, -1.0, 1.0), 0.0)
    return eta, xi


def stress_triaxiality(stress: ArrayLike) -> np.ndarray:
    """η = σ_m/σ_eq of symmetric stresses ``stress`` (..., 3, 3) (see :func:`stress_state`)."""
    return stress_state(stress)[0]


def lode_parameter(stress: ArrayLike) -> np.ndarray:
    """ξ = 27/2 J₃/σ_eq³ ∈ [−1, 1] of symmetric stresses ``stress`` (..., 3, 3) (see :func:`stress_state`)."""
    return stress_state(stress)[1]


@number_arguments
def equivalent_plastic_strain(alpha_p: ArrayLike) -> np.ndarray:
    """ε̄ᵖ = √(2/3) α_p: the von Mises equivalent plastic strain of the accumulated |Δε_p| of Eq. (6.7)."""
    return math.sqrt(2.0 / 3.0) * check_positive("alpha_p", np.asarray(alpha_p, dtype=float), allow_zero=True)


@dataclass(frozen=True)
class JohnsonCookFailure:
    """Johnson–Cook fracture strain ε_f = D₁ + D₂ exp(D₃ η) with a triaxiality cut-off and the damage indicator
    D = ∫ dε̄ᵖ/ε_f (module docstring). Defaults: 4340 steel (Johnson & Cook 1985) and Bao and Wierzbicki's
    cut-off η_c = −1/3 (``cutoff=None``: none); ``minimum_strain`` bounds ε_f from below (inactive for D₁ ≥ it
    and D₃ ≤ 0, so for the default). ``JohnsonCookFailure.of("Armco iron")`` takes a row of
    :data:`JOHNSON_COOK_1985`."""

    D1: float = 0.05
    D2: float = 3.44
    D3: float = -2.12
    cutoff: float | None = BAO_WIERZBICKI_CUTOFF
    minimum_strain: float = 0.01

    def __post_init__(self):
        check_number_fields(self)
        for name in ("D1", "D2", "D3"):
            check_finite(name, getattr(self, name))
        check_positive("D2", self.D2, allow_zero=True)
        check_positive("minimum_strain", self.minimum_strain)
        if self.cutoff is not None:
            check_range("cutoff", self.cutoff, -1.0, 1.0)

    @classmethod
    def of(cls, material: str, cutoff: float | None = BAO_WIERZBICKI_CUTOFF) -> JohnsonCookFailure:
        """The constants of ``material``, a key of :data:`JOHNSON_COOK_1985`."""
        if material not in JOHNSON_COOK_1985:
            raise ValueError(f"material must be one of {tuple(JOHNSON_COOK_1985)}, got {material!r}")
        d1, d2, d3, _, _ = JOHNSON_COOK_1985[material]
        return cls(d1, d2, d3, cutoff=cutoff)

    def fracture_strain(self, triaxiality: ArrayLike, lode: ArrayLike | None = None) -> np.ndarray:
        """ε_f(η) (dimensionless; ∞ at and below the cut-off, within 10⁻¹² for round-off). ``lode`` (ξ ∈ [−1, 1],
        broadcasting with η) is checked and not used: Johnson and Cook's fit does not depend on it."""
        try:
            eta = np.asarray(triaxiality, dtype=float)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"triaxiality must be a real number or an array of them, got {triaxiality!r}") from exc
        if np.isnan(eta).any():
            raise ValueError(f"triaxiality must not hold NaN (±inf is allowed), got {triaxiality!r}")
        if lode is not None:
            lode = check_range("lode", lode, -1.0, 1.0)
            broadcast_shapes(triaxiality=eta, lode=lode)
        with np.errstate(invalid="ignore", over="ignore"):
            exponent = np.where(self.D3 == 0.0, 0.0, self.D3 * eta)
            strain = np.maximum(self.D1 + self.D2 * np.exp(exponent), self.minimum_strain)
        if self.cutoff is not None:
            strain = np.where(eta <= self.cutoff + _CUTOFF_ROUND_OFF, np.inf, strain)
        return strain

    def damage_increment(self, plastic_strain_increment: ArrayLike, stress: ArrayLike) -> np.ndarray:
        """ΔD = Δε̄ᵖ/ε_f(η, ξ) for the equivalent plastic strain increments ``plastic_strain_increment`` (≥ 0)
        and the end-of-increment stresses ``stress`` (..., 3, 3)."""
        increment = check_positive("plastic_strain_increment", np.asarray(
            check_finite("plastic_strain_increment", plastic_strain_increment), dtype=float), allow_zero=True)
        eta, xi = stress_state(stress)
        broadcast_shapes(plastic_strain_increment=increment, stress=eta)
        return np.where(increment > 0.0, increment / self.fracture_strain(eta, xi), 0.0)

    def update(self, damage: ArrayLike, plastic_strain_increment: ArrayLike, stress: ArrayLike) -> np.ndarray:
        """D_{n+1} = D_n + Δε̄ᵖ/ε_f(η_{n+1}, ξ_{n+1}): a new array (the inputs are not changed). ``damage`` (≥ 0)
        broadcasts with the points of ``stress`` (..., 3, 3); D is not capped, failure is D ≥ 1."""
        old = check_positive("damage", np.asarray(check_finite("damage", damage), dtype=float), allow_zero=True)
        increment = self.damage_increment(plastic_strain_increment, stress)
        broadcast_shapes(damage=old, plastic_strain_increment=increment)
        return old + increment
